//! Frequencies of the linear partials a two-step modal scheme simulates, in closed form.
//!
//! Every linear part of the modal schemes here is, per mode, a recursion
//! `q(n+1) - C q(n) + C̃ q(n-1) = 0` (the θ = 1 and exact plate schemes after dividing by
//! `1 + c̃h/2`, the string's exact scheme as it stands). Its characteristic roots are
//! `z = √C̃ e^{±iφ}` with `cos φ = C / (2√C̃)`, so the scheme's partial oscillates at
//! `φ / h` rad/s (folded into `[0, π/h]`), to be compared with the continuous damped frequency
//! `√(ω² - σ²)` (SEED.md 1.1-1.2: the θ-family's numerical frequency is the θ = 1 case with
//! `C̃ = 1`). Used by `noether accuracy` for the "frequency error in cents of the linear
//! partials" metric. Any thread (no state).

use super::frequency::cents;

/// One linear partial: the continuous model's frequency and the scheme's (Hz).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearPartial {
    /// Damped frequency of the continuous mode `√(ω² - σ²) / 2π` (Hz).
    pub exact_hz: f64,
    /// Frequency of the scheme's recursion for that mode (Hz), folded into `[0, fs/2]`.
    pub simulated_hz: f64,
}

/// The angular frequency (rad/s) of `q(n+1) - c q(n) + c_tilde q(n-1) = 0` at step `h` (s), or
/// `None` when the recursion does not oscillate (real roots: `|c| ≥ 2√c̃`) or `c_tilde ≤ 0`.
pub fn two_step_frequency(c: f64, c_tilde: f64, h: f64) -> Option<f64> {
    if !(c_tilde > 0.0 && h > 0.0 && c.is_finite()) {
        return None;
    }
    let cos_phi = c / (2.0 * c_tilde.sqrt());
    (cos_phi.abs() < 1.0).then(|| cos_phi.acos() / h)
}

/// Damped angular frequency `√(ω² - σ²)` (rad/s), `None` when over- or critically damped.
pub fn damped_frequency(omega: f64, sigma: f64) -> Option<f64> {
    (omega > sigma).then(|| ((omega - sigma) * (omega + sigma)).sqrt())
}

/// Largest `|cents|` between simulated and exact frequency over the partials whose exact
/// frequency lies below `band_hz` (only those are heard); `None` if there is none.
pub fn max_cents_error(partials: &[LinearPartial], band_hz: f64) -> Option<f64> {
    partials
        .iter()
        .filter(|p| p.exact_hz > 0.0 && p.exact_hz < band_hz)
        .map(|p| cents(p.simulated_hz, p.exact_hz).abs())
        .fold(None, |m, c| Some(m.map_or(c, |m: f64| m.max(c))))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::schemes::linear::numerical_frequency;

    /// The undamped θ = 1 recursion `q⁺ - (2 - h²ω²) q + q⁻` has the θ-family's closed form
    /// `ω_d = (2/h) asin(hω/2)` (SEED.md 1.1); both evaluate the same angle, so they agree to
    /// the acos form's round-off, `ε / (ω_d h)²` relative (here 1e-11 at ωh = 0.01).
    #[test]
    fn theta_one_matches_the_closed_form() {
        let h = 1.0 / 48_000.0;
        for omega in [480.0, 3000.0, 40_000.0, 90_000.0] {
            let x = omega * h;
            let got = two_step_frequency(2.0 - x * x, 1.0, h).unwrap();
            let want = numerical_frequency(1.0, h, omega).unwrap();
            assert!((got / want - 1.0).abs() < 1e-11, "{omega}: {got} vs {want}");
        }
        // Beyond the θ = 1 limit hω = 2 the recursion does not oscillate.
        assert_eq!(two_step_frequency(2.0 - 2.1f64.powi(2), 1.0, h), None);
    }

    /// A damped sinusoid sampled exactly, `e^{-σnh} cos(ω_d n h)`, satisfies the recursion with
    /// `C = 2 e^{-σh} cos(ω_d h)`, `C̃ = e^{-2σh}`: the frequency comes back to 1e-12.
    #[test]
    fn exact_recursion_returns_the_damped_frequency() {
        let (omega, sigma, h) = (2.0 * std::f64::consts::PI * 440.0, 30.0, 1.0 / 44_100.0);
        let wd = damped_frequency(omega, sigma).unwrap();
        let c = 2.0 * (-sigma * h).exp() * (wd * h).cos();
        let got = two_step_frequency(c, (-2.0 * sigma * h).exp(), h).unwrap();
        assert!((got / wd - 1.0).abs() < 1e-12);
        let p = [LinearPartial {
            exact_hz: wd / std::f64::consts::TAU,
            simulated_hz: got / std::f64::consts::TAU,
        }];
        assert!(max_cents_error(&p, 20_000.0).unwrap() < 1e-8);
        assert_eq!(max_cents_error(&p, 100.0), None);
    }
}
