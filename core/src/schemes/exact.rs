//! Exact two-step scheme for `ü + 2ξω0 u̇ + ω0² u = 0`, any `ξ ≥ 0` (SEED.md section 1.2).
//!
//! With `λ1,2 = ω0(-ξ ± √(ξ²-1))` the sampled exact solution `u_n = u(nh)` satisfies
//! `u_{n+1} - a1 u_n + a2 u_{n-1} = 0`, `a1 = e^{λ1 h} + e^{λ2 h}`, `a2 = e^{-2ξω0h}` (SEED.md 1.2;
//! `ξ = 0` gives `u_{n+1} - 2cos(ω0h) u_n + u_{n-1} = 0`). So the samples equal the exact solution
//! to round-off for any `h`, aliasing included (the recurrence only sees `ω0` modulo `2π/h`).
//!
//! Implementation: state `(u_n, d_n)`, `d_n = u_n - u_{n-1}`, updated as
//! `d_{n+1} = a2 d_n - b u_n`, `u_{n+1} = u_n + d_{n+1}`, with `b = 1 - a1 + a2` computed
//! without cancellation for every `ξ` (no `0/0` at `ξ = 1`) by the shared kernel
//! [`super::two_step::DampedTwoStep`] (`a1 = C`, `a2 = C̃`, `b = β` there, with `σ = ξω0`,
//! `ω = ω0`). The first step is `u_1 = u(h)` from [`damped_linear`]; `u_{-1} = u(-h)` is the
//! history (used only by the energy at `n = 0` and the first dissipation increment: if `u(-h)`
//! overflows, for `ξω0h` in the hundreds, those are infinite while the samples stay exact).
//!
//! # Discrete energy balance
//! Splitting the recurrence into centred differences (as in S. Bilbao, *Numerical Sound
//! Synthesis*, Wiley 2009, chapter 3, lossy oscillator) gives the equivalent form
//! `δ_{tt}u + 2σ̃ δ_{t.}u + Ω̃² u = 0`, with
//! `σ̃ = (1 - a2) / ((1 + a2) h) = tanh(ξω0h)/h` and `Ω̃² = 2b / ((1 + a2) h²)`.
//! Multiplying by `δ_{t.}u` and using the identities of SEED.md section 0:
//! `δ_{t+} E_n = -2σ̃ (δ_{t.}u_n)²` with `E_n = ½(δ_{t-}u_n)² + ½ Ω̃² u_n u_{n-1}`.
//! [`OscillatorStepper::discrete_energy`] is `E_n`, and
//! [`OscillatorStepper::dissipated_energy`] accumulates `D_{n+1} = D_n + 2hσ̃(δ_{t.}u_n)²`, so
//! `E_n + D_n = E_0` in exact arithmetic. When `ξ = 0`, `σ̃ = 0`, `Ω̃ = (2/h) sin(ω0h/2)` and
//! `E_n = (u_n² - 2cos(ω0h) u_n u_{n-1} + u_{n-1}²) / (2h²)`: the quadratic invariant of the
//! recurrence, exactly conserved. As `h → 0`, `Ω̃ → ω0` and `σ̃ → ξω0`, so `E_n → H` and `D_n`
//! tends to the continuous dissipation `∫ 2ξω0 u̇² dt`. For exact samples with `ξ = 0`,
//! `E_n = (sin(ω0h)/(ω0h))² H` (exactly): positive semi-definite for every `h`, and equal to 0
//! when `ω0h` is a multiple of π, where the samples cannot carry the velocity. For `ξ > 0`,
//! `E_n` is positive definite (`Ω̃²h² < 4` then).

use super::closed_form::damped_linear;
use super::two_step::DampedTwoStep;
use super::OscillatorStepper;
use crate::error::{check_non_negative, check_positive, ParamError};

/// Exact scheme stepper for the damped linear oscillator.
///
/// Built once (validates, computes the coefficients), then owned and stepped by one thread.
#[derive(Debug, Clone)]
pub struct ExactScheme {
    /// Natural angular frequency ω0, rad per time unit.
    omega0: f64,
    /// Damping ratio ξ ≥ 0.
    xi: f64,
    /// Time step `h`, time units.
    h: f64,
    /// `a1 = 2e^{-ξω0h}K` (SEED.md 1.2), dimensionless.
    a1: f64,
    /// `a2 = e^{-2ξω0h}`, dimensionless.
    a2: f64,
    /// `b = 1 - a1 + a2`, dimensionless.
    b: f64,
    /// `Ω̃²` of the energy, (rad per time unit)².
    omega_tilde_sq: f64,
    /// `σ̃` of the dissipation, per time unit.
    sigma_tilde: f64,
    /// Displacement `u_n`.
    u: f64,
    /// Increment `d_n = u_n - u_{n-1}`.
    d: f64,
    /// Exact `u(h)` after a reset, used by the first step.
    u_first: f64,
    /// Accumulated dissipation `D_n`, energy units (per unit mass).
    dissipated: f64,
    /// Steps since the last reset.
    n: u64,
}

impl ExactScheme {
    /// Builds the scheme; `omega0 > 0`, `xi ≥ 0`, `h > 0`, all finite. Starts at rest until
    /// [`OscillatorStepper::reset`].
    pub fn new(omega0: f64, xi: f64, h: f64) -> Result<Self, ParamError> {
        check_positive("omega0", omega0)?;
        check_non_negative("xi", xi)?;
        check_positive("h", h)?;
        let k = DampedTwoStep::new(omega0, xi * omega0, h);
        Ok(Self {
            omega0,
            xi,
            h,
            a1: k.c,
            a2: k.c_tilde,
            b: k.beta,
            omega_tilde_sq: k.omega_tilde_sq(),
            sigma_tilde: k.sigma_tilde(),
            u: 0.0,
            d: 0.0,
            u_first: 0.0,
            dissipated: 0.0,
            n: 0,
        })
    }

    /// Coefficients `(a1, a2)` of `u_{n+1} - a1 u_n + a2 u_{n-1} = 0` (dimensionless).
    pub fn coefficients(&self) -> (f64, f64) {
        (self.a1, self.a2)
    }

    /// Angular frequency read back from the recurrence coefficients, `ω` in `[0, π/h]` with
    /// `cos(ωh) = a1 / (2√a2)`: the damped frequency `ω0√(1-ξ²)` folded (aliased) into the
    /// base band. `None` for `ξ ≥ 1` (no oscillation). Evaluated as
    /// `sin²(ωh/2) = (b - (1-√a2)²) / (4√a2)` for full precision at small `h`.
    pub fn recurrence_frequency(&self) -> Option<f64> {
        if self.xi >= 1.0 {
            return None;
        }
        let one_minus_root = -(-self.xi * self.omega0 * self.h).exp_m1();
        let s2 = (self.b - one_minus_root * one_minus_root) / (4.0 * self.a2.sqrt());
        Some(2.0 * s2.clamp(0.0, 1.0).sqrt().asin() / self.h)
    }

    /// Energy-balance coefficients `(σ̃, Ω̃²)` of the equivalent centred scheme (module docs).
    pub fn balance_coefficients(&self) -> (f64, f64) {
        (self.sigma_tilde, self.omega_tilde_sq)
    }
}

impl OscillatorStepper for ExactScheme {
    fn name(&self) -> &'static str {
        "exact"
    }

    fn step_size(&self) -> f64 {
        self.h
    }

    fn reset(&mut self, u0: f64, v0: f64) {
        let back = damped_linear(self.omega0, self.xi, u0, v0, -self.h).0;
        self.u_first = damped_linear(self.omega0, self.xi, u0, v0, self.h).0;
        self.u = u0;
        self.d = u0 - back;
        self.dissipated = 0.0;
        self.n = 0;
    }

    fn step(&mut self) {
        let d_next = if self.n == 0 {
            self.u_first - self.u
        } else {
            self.a2 * self.d - self.b * self.u
        };
        // 2hσ̃ (δ_{t.}u)² with δ_{t.}u = (d_{n+1} + d_n) / (2h).
        let s = d_next + self.d;
        self.dissipated += self.sigma_tilde * s * s / (2.0 * self.h);
        self.d = d_next;
        self.u += d_next;
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
        let v = self.d / self.h;
        0.5 * v * v + 0.5 * self.omega_tilde_sq * self.u * (self.u - self.d)
    }

    fn physical_energy(&self) -> f64 {
        let v = self.velocity();
        0.5 * v * v + 0.5 * self.omega0 * self.omega0 * self.u * self.u
    }

    fn dissipated_energy(&self) -> f64 {
        self.dissipated
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coefficients_match_seed_formula() {
        // SEED.md 1.2: a1 = e^{-ξω0h}(e^{hω0√(ξ²-1)} + e^{-hω0√(ξ²-1)}), i.e. 2e^{-ξω0h}cos(..)
        // for ξ < 1, 2e^{-ω0h} at ξ = 1, 2e^{-ξω0h}cosh(..) for ξ > 1 (direct evaluation,
        // relative error a few ulps at these moderate arguments).
        for &(xi, h) in &[(0.0, 0.31), (0.1, 2.0), (1.0, 2.0), (2.0, 2.0), (0.0, 10.0)] {
            let s = ExactScheme::new(1.0, xi, h).unwrap();
            let (a1, a2) = s.coefficients();
            let want = if xi < 1.0 {
                2.0 * (-xi * h).exp() * ((1.0 - xi * xi).sqrt() * h).cos()
            } else {
                2.0 * (-xi * h).exp() * ((xi * xi - 1.0).sqrt() * h).cosh()
            };
            assert!(
                (a1 - want).abs() < 1e-14 * (1.0 + want.abs()),
                "xi {xi} h {h}"
            );
            assert!((a2 - (-2.0 * xi * h).exp()).abs() < 1e-16);
        }
        assert_eq!(ExactScheme::new(1.0, -0.1, 0.1).unwrap_err().field, "xi");
    }
}
