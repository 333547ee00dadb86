//! The exact two-step scheme of one damped mode and its discrete energy.
//!
//! Mode `q̈ + 2σ q̇ + ω² q = F/μ`. Its free samples satisfy exactly (SEED.md 1.2 and 3.2)
//! `q^{n+1} - c q^n + c̃ q^{n-1} = 0`, `c = e^{-σh}(e^{λh} + e^{-λh})`, `λ = √(σ²-ω²)`,
//! `c̃ = e^{-2σh}`, for every `σ ≥ 0`, `ω ≥ 0`, `h > 0`. The coefficients `c`, `c̃`,
//! `β = 1 + c̃ - c` and the exact start come from the shared kernel
//! [`crate::schemes::two_step`] (all regimes, without cancellation or overflow); this module
//! adds the string's energy weights.
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

use crate::schemes::two_step::DampedTwoStep;

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
    /// `β = 1 + c̃ - c`, cancellation-free ([`DampedTwoStep::beta`]; dimensionless, ≥ 0).
    pub beta: f64,
    /// Energy weight of `(δ_{t+}q)²`: `a = (1 + c̃)/2` (dimensionless).
    pub a: f64,
    /// Energy weight of `q^{n+1} q^n`: `b = β/h²` in s⁻².
    pub b: f64,
    /// Equivalent damping of the centred form: `s = (1 - c̃)/(2h)` in s⁻¹.
    pub s: f64,
}

impl ModeCoefficients {
    /// Exact-scheme coefficients for angular frequency `omega` (rad/s, ≥ 0), damping `sigma`
    /// (s⁻¹, ≥ 0) and step `h` (s, > 0). Finite for all such inputs.
    pub fn new(omega: f64, sigma: f64, h: f64) -> Self {
        let k = DampedTwoStep::new(omega, sigma, h);
        Self {
            c: k.c,
            c_tilde: k.c_tilde,
            beta: k.beta,
            a: 0.5 * (1.0 + k.c_tilde),
            b: k.beta / (h * h),
            s: k.one_minus_c_tilde / (2.0 * h),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn energy_weights_match_the_centred_form() {
        // The recursion itself is tested with the kernel (schemes::two_step). Here: the
        // centred form's weights, a - bh²/4 = (1 + c̃ + c)/4 ≥ 0 and b ≥ 0 in every regime
        // (1e-15: round-off of terms of size ≤ 1), finite for huge over-damping.
        let h = 0.05;
        for &(omega, sigma) in &[
            (10.0, 0.0),
            (10.0, 1.0),
            (10.0, 10.0),
            (10.0, 30.0),
            (0.0, 2.0),
        ] {
            let co = ModeCoefficients::new(omega, sigma, h);
            let lhs = co.a - co.b * h * h / 4.0;
            assert!(
                (lhs - (1.0 + co.c_tilde + co.c) / 4.0).abs() < 1e-15,
                "{omega} {sigma}"
            );
            assert!(lhs >= 0.0 && co.b >= 0.0);
            assert!((co.s - (1.0 - co.c_tilde) / (2.0 * h)).abs() < 1e-13);
        }
        let co = ModeCoefficients::new(1.0, 1e6, 1.0);
        assert!(co.c.is_finite() && co.c_tilde == 0.0 && co.s.is_finite());
    }
}
