//! The exact two-step scheme of one damped mode, its discrete energy and its exact start.
//!
//! Mode `q̈ + 2σ q̇ + ω² q = F/μ`. The free solutions are `e^{(-σ ± √(σ²-ω²)) t}`, so their
//! samples satisfy exactly (SEED.md 1.2 and 3.2)
//! `q^{n+1} - c q^n + c̃ q^{n-1} = 0`, `c = e^{-σh}(e^{λh} + e^{-λh})`, `λ = √(σ²-ω²)`,
//! `c̃ = e^{-2σh}`,
//! for every `σ ≥ 0`, `ω ≥ 0`, `h > 0`: `c = 2e^{-σh}cos(ω_d h)` (`ω_d = √(ω²-σ²)`) when
//! `σ < ω`, `c = 2e^{-σh}` at `σ = ω`, `c = e^{-(σ-λ)h} + e^{-(σ+λ)h}` when `σ > ω` (written with
//! `σ - λ = ω²/(σ+λ)` so neither cancellation nor overflow occurs). No branch divides by
//! `ω_d` or `λ`.
//!
//! Forced scheme (SEED.md 3.2): `(μ/h²)(q^{n+1} - c q^n + c̃ q^{n-1}) = F^n`. It is the
//! centred scheme `μ(a δ_tt q + b q + 2s δ_t. q) = F` with
//! `a = (1+c̃)/2`, `b = (1 + c̃ - c)/h²`, `s = (1 - c̃)/(2h)` (expand `δ_tt`, `δ_t.` and match
//! the three coefficients). Multiplying by `δ_t. q` and using the identities of SEED.md §0:
//! `δ_{t-} E^{n+1/2} = -2μ s (δ_t. q^n)² + F^n δ_t. q^n`,
//! `E^{n+1/2} = (μ/2)[a (δ_{t+} q^n)² + b q^{n+1} q^n]`.
//! Without damping `a = 1`, `s = 0` and `E` is exactly conserved. With `m = (q^{n+1}+q^n)/2`,
//! `p = δ_{t+} q^n`: `E = (μ/2)[(a - bh²/4) p² + b m²]`, `a - bh²/4 = (1 + c̃ + c)/4 ≥ 0` and
//! `b ≥ 0` (both vanish only on the measure-zero sets `ω_d h ∈ πℤ`), so the energy is
//! non-negative; the model reports the first term as kinetic and the second as potential.
//!
//! Consistency: `a = 1 - σh + O(h²)`, so the forced scheme approximates `μ(1 - σh) q̈ + ...`: the
//! force is consistent to first order in `σh` (for strings `σh < 1e-3` at audio rates).
//!
//! Pure functions, called on the control thread at build time and by `reset`/`pluck`.

/// Coefficients of the exact scheme of one mode and of its energy.
///
/// The model steps the difference form `Δ^{n+1} = c̃ Δ^n - β q^n + (h²/μ) F^n`,
/// `q^{n+1} = q^n + Δ^{n+1}` (`Δ^n = q^n - q^{n-1}`), which is the same recursion with
/// `β = 1 + c̃ - c` computed without cancellation, so that neither the update nor the energy
/// loses digits when `ωh ≪ 1` (at fs = 2 MHz the fundamental has `ωh ≈ 6e-4` and `2 - c ≈ 4e-7`).
///
/// Computed at build time; read by the audio thread on every step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeCoefficients {
    /// `c = e^{-σh}(e^{λh} + e^{-λh})` (dimensionless).
    pub c: f64,
    /// `c̃ = e^{-2σh}` (dimensionless).
    pub c_tilde: f64,
    /// `β = 1 + c̃ - c = (1 - e^{-σh})² + 2e^{-σh}(1 - C(h))` (dimensionless, ≥ 0).
    pub beta: f64,
    /// Energy weight of `(δ_{t+}q)²`: `a = (1 + c̃)/2` (dimensionless).
    pub a: f64,
    /// Energy weight of `q^{n+1} q^n`: `b = β/h²` in s⁻².
    pub b: f64,
    /// Equivalent damping of the centred form: `s = (1 - c̃)/(2h)` in s⁻¹.
    pub s: f64,
}

/// Damped kernel at time `t`: `(e^{-σt}C, e^{-σt}(1 - C), e^{-σt}S)` where
/// `C = cos(ω_d t)`, `S = sin(ω_d t)/(ω_d t)` for `σ < ω`, `C = cosh(λt)`,
/// `S = sinh(λt)/(λt)` for `σ > ω`, `C = S = 1` at `σ = ω`. `1 - C` is formed without
/// cancellation (`2 sin²(x/2)`, `-2 sinh²(x/2)`), and no branch divides by `ω_d` or `λ`.
fn kernel(omega: f64, sigma: f64, t: f64) -> (f64, f64, f64) {
    // ω² - σ² without cancellation.
    let disc = (omega - sigma) * (omega + sigma);
    let e = (-sigma * t).exp();
    if disc > 0.0 {
        let x = disc.sqrt() * t;
        let half = (0.5 * x).sin();
        (e * x.cos(), 2.0 * e * half * half, e * sinc(x))
    } else if disc < 0.0 {
        let lam = (-disc).sqrt();
        let x = lam * t;
        // e^{-σt}cosh(λt) = (e^{-(σ-λ)t} + e^{-(σ+λ)t})/2 with σ - λ = ω²/(σ + λ): no overflow.
        let slow = (-(omega * omega / (sigma + lam)) * t).exp();
        let fast = (-(sigma + lam) * t).exp();
        let ec = 0.5 * (slow + fast);
        let (em, es) = if x <= 1.0 {
            let sh = (0.5 * x).sinh();
            let sinhc = if x < 1e-4 {
                1.0 + x * x / 6.0 + x * x * x * x / 120.0
            } else {
                x.sinh() / x
            };
            (-2.0 * e * sh * sh, e * sinhc)
        } else {
            (e - ec, (slow - fast) / (2.0 * x))
        };
        (ec, em, es)
    } else {
        (e, 0.0, e)
    }
}

/// `sin(x)/x`, with its Taylor form near 0.
fn sinc(x: f64) -> f64 {
    if x.abs() < 1e-4 {
        1.0 - x * x / 6.0 + x * x * x * x / 120.0
    } else {
        x.sin() / x
    }
}

impl ModeCoefficients {
    /// Exact-scheme coefficients for angular frequency `omega` (rad/s, ≥ 0), damping `sigma`
    /// (s⁻¹, ≥ 0) and step `h` (s, > 0). Finite for all such inputs.
    pub fn new(omega: f64, sigma: f64, h: f64) -> Self {
        let (ec, em, _) = kernel(omega, sigma, h);
        let c_tilde = (-2.0 * sigma * h).exp();
        let one_minus_e = -(-sigma * h).exp_m1();
        let beta = one_minus_e * one_minus_e + 2.0 * em;
        Self {
            c: 2.0 * ec,
            c_tilde,
            beta,
            a: 0.5 * (1.0 + c_tilde),
            b: beta / (h * h),
            s: -(-2.0 * sigma * h).exp_m1() / (2.0 * h),
        }
    }
}

/// Exact free solution over one step from `q(0) = q0`, `q̇(0) = v0`, returned as the increment
/// `Δ^1 = q(h) - q0 = q0 (e^{-σh}C(h) - 1) + (v0 + σ q0) h e^{-σh} S(h)` (formed without
/// cancellation; see [`ModeCoefficients`] for `C`, `S`). With `σ = 0`, `v0 = 0`,
/// `q0 + Δ^1 = q0 cos(ωh)`, so the samples of the two-step scheme are exactly `q0 cos(ω n h)`.
pub fn exact_first_increment(omega: f64, sigma: f64, h: f64, q0: f64, v0: f64) -> f64 {
    let (_, em, es) = kernel(omega, sigma, h);
    q0 * ((-sigma * h).exp_m1() - em) + (v0 + sigma * q0) * h * es
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Closed-form free solution, for checking (fine for moderate σt, ωt).
    fn closed(omega: f64, sigma: f64, t: f64, q0: f64, v0: f64) -> f64 {
        let (ec, _, es) = kernel(omega, sigma, t);
        q0 * ec + (v0 + sigma * q0) * t * es
    }

    #[test]
    fn two_step_recursion_reproduces_samples_in_all_regimes() {
        // Under-, critically and over-damped, and σ within 1e-12 of ω (no 0/0): the recursion
        // must reproduce the closed-form samples to round-off (1e-12 relative to q0 over 40
        // steps, each step loses at most a few ulps).
        let h = 0.05;
        for &(omega, sigma) in &[
            (10.0, 0.0),
            (10.0, 1.0),
            (10.0, 10.0),
            (10.0, 10.0 * (1.0 + 1e-12)),
            (10.0, 30.0),
            (0.0, 2.0),
            (0.0, 0.0),
        ] {
            let co = ModeCoefficients::new(omega, sigma, h);
            assert!(co.c.is_finite() && co.b.is_finite() && co.beta >= 0.0);
            let (q0, v0) = (1.0, 0.3);
            let mut d = exact_first_increment(omega, sigma, h, q0, v0);
            let mut q = q0 + d;
            assert!((q - closed(omega, sigma, h, q0, v0)).abs() < 1e-15);
            for n in 2..40 {
                d = co.c_tilde * d - co.beta * q;
                q += d;
                let want = closed(omega, sigma, n as f64 * h, q0, v0);
                assert!((q - want).abs() < 1e-12, "ω={omega} σ={sigma} n={n}");
            }
            // β agrees with 1 + c̃ - c (which may cancel) to round-off of its terms.
            assert!((co.beta - (1.0 + co.c_tilde - co.c)).abs() < 1e-15 * 4.0);
        }
    }

    #[test]
    fn huge_overdamping_stays_finite() {
        let co = ModeCoefficients::new(1.0, 1e6, 1.0);
        assert!(co.c.is_finite() && co.c_tilde == 0.0 && co.s.is_finite());
        assert!(exact_first_increment(1.0, 1e6, 1.0, 1.0, 0.0).is_finite());
    }
}
