//! The θ-family for the linear oscillator `ü + ω0² u = 0` (SEED.md section 1.1).
//!
//! Scheme: `δ_{tt}u + ω0² (θ + (1-θ) μ_{t.}) u = 0`, θ in [0, 1] (S. Bilbao, *Numerical Sound
//! Synthesis*, Wiley 2009, chapter 3). With `w = h²ω0²` it is the two-step recurrence
//! `u_{n+1} = 2c u_n - u_{n-1}`, `c = (1 - θw/2) / (1 + (1-θ)w/2)`.
//!
//! Implementation: the state is `(u_n, d_n)` with the increment `d_n = u_n - u_{n-1}`, updated
//! as `d_{n+1} = d_n - κ u_n`, `u_{n+1} = u_n + d_{n+1}` with `κ = 2(1-c) = w / (1 + (1-θ)w/2)`.
//! This is algebraically the recurrence above, but the rounding of each step perturbs the
//! discrete energy by `O(ε)` relatively instead of `O(ε/(ω0 h))` (the classic "summed form"
//! of Störmer-Verlet, E. Hairer, C. Lubich, G. Wanner, *Geometric Numerical Integration*,
//! Springer 2006, section VIII.5).
//!
//! Discrete energy (SEED.md 1.1), exactly conserved:
//! `h_n = ½ (δ_{t-}u)² + ω0² (θ ½ u_n u_{n-1} + (1-θ) ½ μ_{t-}(u²))`
//! `    = ½ (d_n/h)² + ω0² (½ u_n (u_n - d_n) + (1-θ) d_n² / 4)`.
//!
//! Starting values: `u_{-1} = c u0 - h v0`, the value for which the recurrence is symmetric
//! about `n = 0` and `δ_{t.} u_0 = v0`. Then `u_1 = c u0 + h v0` and
//! `u_n = u0 cos(n ω_d h) + (h v0 / sin(ω_d h)) sin(n ω_d h)` exactly: a discrete sinusoid at the
//! numerical frequency ω_d of [`numerical_frequency`] from the first sample on.

use super::OscillatorStepper;
use crate::error::{check_closed, check_positive, ParamError};

/// Numerical angular frequency `ω_d` of the θ-scheme, or `None` when the scheme is not stable
/// (`h ω0 ≥` [`stability_limit`]) or an input is invalid (`h ≤ 0`, `omega0 ≤ 0`, θ ∉ [0, 1],
/// non-finite).
///
/// SEED.md 1.1 gives `ω_d = (1/h) arccos((1 - θ h²ω0²/2) / (1 + (1-θ) h²ω0²/2))`; this evaluates
/// the equivalent `ω_d = (2/h) asin( (hω0/2) / √(1 + (1-θ) h²ω0²/2) )` (from
/// `1 - cos(ω_d h) = 2 sin²(ω_d h/2)`), which keeps full relative precision for small `h ω0`
/// where the arccos form loses digits. Units: rad per time unit of `h`.
pub fn numerical_frequency(theta: f64, h: f64, omega0: f64) -> Option<f64> {
    if !(h.is_finite() && h > 0.0 && omega0.is_finite() && omega0 > 0.0) {
        return None;
    }
    if !(0.0..=1.0).contains(&theta) {
        return None;
    }
    let x = h * omega0;
    let s = 0.5 * x / (1.0 + 0.5 * (1.0 - theta) * x * x).sqrt();
    (s < 1.0).then(|| 2.0 * s.asin() / h)
}

/// Supremum of stable `h ω0` for the θ-scheme: `2 / √(2θ - 1)` for θ > ½, `+∞` for θ ≤ ½
/// (unconditionally stable; at θ = ½ the formula's limit is infinite too). Dimensionless.
/// At `h ω0` equal to the limit the recurrence has the double root `-1` and grows linearly.
pub fn stability_limit(theta: f64) -> f64 {
    if theta > 0.5 {
        2.0 / (2.0 * theta - 1.0).sqrt()
    } else {
        f64::INFINITY
    }
}

/// Refuses a step `h` at or beyond the θ-family's stability limit for the linear frequency
/// `omega0` (`h ω0 <` [`stability_limit`]`(θ)`, SEED.md 1.1); `theta_field` names the θ being
/// checked in the message (`theta`, `theta1`). Past the limit the recurrence has a root of
/// modulus > 1 and the discrete energy is indefinite, so the run would explode: constructors
/// call this instead of building an exploding scheme. Runs on the configuration thread.
pub fn check_stable_step(
    h: f64,
    omega0: f64,
    theta: f64,
    theta_field: &str,
) -> Result<(), ParamError> {
    let limit = stability_limit(theta);
    if h * omega0 < limit {
        return Ok(());
    }
    Err(ParamError::new(
        "h",
        h,
        format!(
            "h < {} = 2/(ω0 √(2θ-1)) for {theta_field} = {theta}, ω0 = {omega0} (the θ-scheme is \
             only conditionally stable for θ > 1/2, SEED.md 1.1; lower {theta_field} to 1/2 or \
             below for unconditional stability)",
            limit / omega0
        ),
    ))
}

/// θ-scheme stepper for `ü + ω0² u = 0`.
///
/// Built once (validates, no allocation at all), then owned and stepped by one thread.
#[derive(Debug, Clone)]
pub struct ThetaScheme {
    /// Natural angular frequency ω0, rad per time unit.
    omega0: f64,
    /// θ in [0, 1].
    theta: f64,
    /// Time step `h`, time units.
    h: f64,
    /// `κ = 2(1 - c) = h²ω0² / (1 + (1-θ) h²ω0²/2)`, dimensionless.
    kappa: f64,
    /// Displacement `u_n`.
    u: f64,
    /// Increment `d_n = u_n - u_{n-1}`, displacement units.
    d: f64,
    /// Steps since the last reset.
    n: u64,
}

impl ThetaScheme {
    /// Builds the scheme; `omega0 > 0`, `theta` in [0, 1], `h > 0`, all finite, and `h ω0`
    /// below the stability limit ([`check_stable_step`]). Starts at rest (`u0 = v0 = 0`) until
    /// [`OscillatorStepper::reset`] is called.
    pub fn new(omega0: f64, theta: f64, h: f64) -> Result<Self, ParamError> {
        check_positive("omega0", omega0)?;
        check_closed("theta", theta, 0.0, 1.0)?;
        check_positive("h", h)?;
        let w = h * h * omega0 * omega0;
        check_positive("h*omega0", w)?;
        check_stable_step(h, omega0, theta, "theta")?;
        Ok(Self {
            omega0,
            theta,
            h,
            kappa: w / (1.0 + 0.5 * (1.0 - theta) * w),
            u: 0.0,
            d: 0.0,
            n: 0,
        })
    }

    /// The recurrence coefficient `c` of `u_{n+1} = 2c u_n - u_{n-1}` (dimensionless).
    pub fn recurrence_coefficient(&self) -> f64 {
        1.0 - 0.5 * self.kappa
    }

    /// This scheme's [`numerical_frequency`] (`None` when unstable).
    pub fn numerical_frequency(&self) -> Option<f64> {
        numerical_frequency(self.theta, self.h, self.omega0)
    }
}

impl OscillatorStepper for ThetaScheme {
    fn name(&self) -> &'static str {
        "theta"
    }

    fn step_size(&self) -> f64 {
        self.h
    }

    fn reset(&mut self, u0: f64, v0: f64) {
        self.u = u0;
        // u_{-1} = c u0 - h v0, so d_0 = (1 - c) u0 + h v0 = κ u0 / 2 + h v0.
        self.d = 0.5 * self.kappa * u0 + self.h * v0;
        self.n = 0;
    }

    fn step(&mut self) {
        self.d -= self.kappa * self.u;
        self.u += self.d;
        self.n += 1;
    }

    fn steps_taken(&self) -> u64 {
        self.n
    }

    fn displacement(&self) -> f64 {
        self.u
    }

    fn velocity(&self) -> f64 {
        self.d / self.h
    }

    fn discrete_energy(&self) -> f64 {
        let (u, d, w2) = (self.u, self.d, self.omega0 * self.omega0);
        let v = d / self.h;
        0.5 * v * v + w2 * (0.5 * u * (u - d) + 0.25 * (1.0 - self.theta) * d * d)
    }

    fn physical_energy(&self) -> f64 {
        let v = self.velocity();
        0.5 * v * v + 0.5 * self.omega0 * self.omega0 * self.u * self.u
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discrete_sinusoid_from_the_first_sample() {
        // The symmetric start makes u_n = u0 cos(nφ) + (h v0/sin φ) sin(nφ) exactly; 40 steps
        // of round-off stay below 1e-13 of the unit amplitude.
        let (w, th, h, u0, v0) = (1.3, 0.3, 0.2, 0.7, -0.4);
        let mut s = ThetaScheme::new(w, th, h).unwrap();
        s.reset(u0, v0);
        let phi = numerical_frequency(th, h, w).unwrap() * h;
        for n in 1..=40 {
            s.step();
            let x = n as f64 * phi;
            let exact = u0 * x.cos() + h * v0 / phi.sin() * x.sin();
            assert!((s.displacement() - exact).abs() < 1e-13, "n {n}");
        }
        assert!((s.recurrence_coefficient() - phi.cos()).abs() < 1e-15);
    }

    #[test]
    fn limits_and_invalid_inputs() {
        assert_eq!(stability_limit(1.0), 2.0);
        assert!(stability_limit(0.5).is_infinite());
        assert!(numerical_frequency(1.0, 2.0, 1.0).is_none());
        assert!(numerical_frequency(1.0, 1.999, 1.0).is_some());
        assert!(numerical_frequency(0.0, 1e6, 1.0).is_some());
        assert!(numerical_frequency(1.5, 0.1, 1.0).is_none());
        assert!(numerical_frequency(0.5, f64::NAN, 1.0).is_none());
        let e = ThetaScheme::new(1.0, 1.5, 0.1).unwrap_err();
        assert_eq!(e.field, "theta");
    }
}
