//! The exact damped two-step coefficients: one kernel for the one-oscillator lab
//! ([`super::exact`]), the modal plate (`models::plate::params`) and the modal string
//! (`models::string::exact`).
//!
//! Lecture: SEED.md §1.2 (exact scheme of the damped oscillator) and §3.2 (the same per mode,
//! `C_ii`, `C̃_ii`). For `q̈ + 2σ q̇ + ω² q = 0` (`σ ≥ 0`, `ω ≥ 0`) the free solutions are
//! `e^{r t}`, `r = -σ ± √(σ²-ω²)`, so the samples `q^n = q(nh)` satisfy exactly
//! `q^{n+1} - C q^n + C̃ q^{n-1} = 0`, `C = e^{-σh}(e^{λh} + e^{-λh}) = 2e^{-σh}K`,
//! `C̃ = e^{-2σh}`, with `K = cos(ω_d h)`, `ω_d = √(ω²-σ²)` (under-damped), `K = 1` (critical),
//! `K = cosh(λh)`, `λ = √(σ²-ω²)` (over-damped). With `ξ = σ/ω` this is the lecture's
//! `a1 = C`, `a2 = C̃`.
//!
//! [`DampedTwoStep`] holds, for every `ω ≥ 0`, `σ ≥ 0`, `h > 0`, finite and without
//! cancellation or overflow:
//! - `C`, `C̃`, `1 - C̃ = -expm1(-2σh)`;
//! - `β = 1 - C + C̃ = (1 - e^{r₁h})(1 - e^{r₂h}) ≥ 0`, the coefficient of the difference form
//!   `Δ^{n+1} = C̃ Δ^n - β q^n` (`Δ^n = q^n - q^{n-1}`), evaluated as
//!   `expm1(-σh)² + 4e^{-σh} sin²(ω_d h/2)` (under-damped), `expm1(-σh)²` (critical),
//!   `expm1(-(σ-λ)h) expm1(-(σ+λ)h)` with `σ - λ = ω²/(σ+λ)` (over-damped). `ω² - σ²` is formed
//!   as `(ω-σ)(ω+σ)`; no branch divides by `ω_d` or `λ`;
//! - the equivalent centred (θ = 1) form `δ_tt q + 2σ̃ δ_{t.} q + Ω̃² q = 0` (divide the
//!   recursion by `h²(1 + C̃)/2`): `σ̃h = (1 - C̃)/(1 + C̃) = tanh(σh)` and
//!   `h²Ω̃² = 2β/(1 + C̃) = 2(cosh(σh) - K)/cosh(σh)` ([`DampedTwoStep::sigma_tilde`],
//!   [`DampedTwoStep::omega_tilde_sq`]; the plate's `c̃ = 2σ̃`, `ω̃² = Ω̃²`).
//!
//! [`Propagator`] is the exact free solution over one interval `t ≥ 0`
//! (`e^{-σt}K(t)`, `e^{-σt}(1 - K(t))`, `e^{-σt}S(t)` with `S = sin(ω_d t)/(ω_d t)` or
//! `sinh(λt)/(λt)`), from which [`first_increment`] gives the exact start `q(h) - q(0)`.
//!
//! Pure functions, callable from any thread; the models call them at build time, on retune
//! and on reset (never per sample).

/// Exact damped two-step coefficients of one mode (module documentation).
///
/// Plain `Copy` data, computed once per mode and step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DampedTwoStep {
    /// Time step `h` (time units, > 0).
    pub h: f64,
    /// `C = 2e^{-σh}K` (dimensionless; the lecture's `a1`).
    pub c: f64,
    /// `C̃ = e^{-2σh}` (dimensionless; the lecture's `a2`).
    pub c_tilde: f64,
    /// `1 - C̃ = -expm1(-2σh)` (dimensionless, ≥ 0).
    pub one_minus_c_tilde: f64,
    /// `β = 1 - C + C̃`, cancellation-free (dimensionless, ≥ 0).
    pub beta: f64,
}

impl DampedTwoStep {
    /// Coefficients for angular frequency `omega` (≥ 0), decay rate `sigma` (≥ 0, the `σ` of
    /// `2σ q̇`) and step `h` (> 0). Inputs are not validated (callers validate); finite for all
    /// such finite inputs.
    pub fn new(omega: f64, sigma: f64, h: f64) -> Self {
        let p = propagator(omega, sigma, h);
        let em = (-sigma * h).exp_m1();
        let disc = (omega - sigma) * (omega + sigma);
        let beta = if disc >= 0.0 {
            // (1 - e^{-σh})² + 2e^{-σh}(1 - K): two non-negative terms.
            em * em + 2.0 * p.decay_one_minus_cos
        } else {
            // (1 - e^{r₁h})(1 - e^{r₂h}), r₁ = -(σ - λ) = -ω²/(σ + λ), r₂ = -(σ + λ).
            let fast = sigma + (-disc).sqrt();
            (-(omega * omega / fast) * h).exp_m1() * (-fast * h).exp_m1()
        };
        Self {
            h,
            c: 2.0 * p.decay_cos,
            c_tilde: (-2.0 * sigma * h).exp(),
            one_minus_c_tilde: -(-2.0 * sigma * h).exp_m1(),
            beta,
        }
    }

    /// `σ̃ = (1 - C̃)/((1 + C̃)h) = tanh(σh)/h` (per time unit): damping of the equivalent
    /// centred form (module documentation).
    pub fn sigma_tilde(&self) -> f64 {
        self.one_minus_c_tilde / ((1.0 + self.c_tilde) * self.h)
    }

    /// `Ω̃² = 2β/((1 + C̃)h²)` ((rad per time unit)²): stiffness of the equivalent centred form.
    pub fn omega_tilde_sq(&self) -> f64 {
        2.0 * self.beta / ((1.0 + self.c_tilde) * self.h * self.h)
    }
}

/// Exact free propagator of `q̈ + 2σ q̇ + ω² q = 0` over an interval `t ≥ 0`:
/// `q(t) = q0 decay_cos + (v0 + σ q0) t decay_sinc`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Propagator {
    /// `e^{-σt}K(t)`: `K = cos(ω_d t)`, `1`, `cosh(λt)` (under-, critically, over-damped).
    pub decay_cos: f64,
    /// `e^{-σt}(1 - K(t))`, formed without cancellation (`2sin²(x/2)`, `-2sinh²(x/2)`).
    pub decay_one_minus_cos: f64,
    /// `e^{-σt}S(t)`: `S = sin(ω_d t)/(ω_d t)`, `1`, `sinh(λt)/(λt)`.
    pub decay_sinc: f64,
}

/// The [`Propagator`] for `omega ≥ 0`, `sigma ≥ 0`, `t ≥ 0`: finite for all such inputs (the
/// over-damped `e^{-σt}cosh(λt)` is `(e^{-(σ-λ)t} + e^{-(σ+λ)t})/2` with `σ - λ = ω²/(σ+λ)`, so
/// nothing overflows), no branch divides by `ω_d` or `λ`.
pub fn propagator(omega: f64, sigma: f64, t: f64) -> Propagator {
    // ω² - σ² without cancellation.
    let disc = (omega - sigma) * (omega + sigma);
    let e = (-sigma * t).exp();
    let (decay_cos, decay_one_minus_cos, decay_sinc) = if disc > 0.0 {
        let x = disc.sqrt() * t;
        let half = (0.5 * x).sin();
        (e * x.cos(), 2.0 * e * half * half, e * sinc(x))
    } else if disc < 0.0 {
        let lam = (-disc).sqrt();
        let x = lam * t;
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
    };
    Propagator {
        decay_cos,
        decay_one_minus_cos,
        decay_sinc,
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

/// Exact free increment over one step from `q(0) = q0`, `q̇(0) = v0`:
/// `q(h) - q0 = q0 (expm1(-σh) - e^{-σh}(1 - K)) + (v0 + σ q0) h e^{-σh} S`, formed without
/// cancellation. With `σ = 0`, `v0 = 0`: `q0 + Δ = q0 cos(ωh)`.
pub fn first_increment(omega: f64, sigma: f64, h: f64, q0: f64, v0: f64) -> f64 {
    let p = propagator(omega, sigma, h);
    q0 * ((-sigma * h).exp_m1() - p.decay_one_minus_cos) + (v0 + sigma * q0) * h * p.decay_sinc
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `q(t)` from the propagator (fine for moderate σt, ωt).
    fn closed(omega: f64, sigma: f64, t: f64, q0: f64, v0: f64) -> f64 {
        let p = propagator(omega, sigma, t);
        q0 * p.decay_cos + (v0 + sigma * q0) * t * p.decay_sinc
    }

    #[test]
    fn coefficients_match_the_lecture_and_each_other() {
        // SEED 1.2 / 3.2 by direct evaluation (a few ulps at these moderate arguments), and the
        // centred form: σ̃h = tanh(σh), h²Ω̃² = 2(cosh σh - K)/cosh σh (1e-13 relative).
        for &(w, s, h) in &[
            (1.0_f64, 0.0_f64, 0.1_f64),
            (1.0, 0.15, 2.0),
            (5.0, 6.0, 0.05),
            (2.0, 2.0, 0.3),
            (0.0, 3.0, 0.2),
            (3.0, 0.0, 10.0),
        ] {
            let k = if w > s {
                ((w * w - s * s).sqrt() * h).cos()
            } else {
                ((s * s - w * w).sqrt() * h).cosh()
            };
            let t = DampedTwoStep::new(w, s, h);
            let want_c = 2.0 * (-s * h).exp() * k;
            assert!(
                (t.c - want_c).abs() < 1e-14 * (1.0 + want_c.abs()),
                "{w} {s} {h}"
            );
            assert!((t.c_tilde - (-2.0 * s * h).exp()).abs() < 1e-16);
            assert!((t.beta - (1.0 - t.c + t.c_tilde)).abs() < 1e-14);
            assert!((t.sigma_tilde() * h - (s * h).tanh()).abs() < 1e-15);
            let ch = (s * h).cosh();
            let want = 2.0 * (ch - k) / ch;
            let got = t.omega_tilde_sq() * h * h;
            assert!((got - want).abs() <= 1e-13 * want.abs(), "{got} {want}");
        }
    }

    #[test]
    fn beta_keeps_its_digits_at_small_steps() {
        // ωh = 6e-4 (a string's fundamental at 2 MHz): β = 4sin²(ωh/2) ≈ 3.6e-7 to a few ulps,
        // where 1 - C + C̃ would keep only ~9 digits. Over-damped with σ - λ ≪ σ likewise:
        // β = (1 - e^{-x})(1 - e^{-y}), x = (σ-λ)h ≈ 5e-6 (series to x³: relative error x³/24),
        // y = (σ+λ)h ≈ 20.
        let w = 6e-4_f64;
        let t = DampedTwoStep::new(w, 0.0, 1.0);
        let want = 4.0 * (0.5 * w).sin().powi(2);
        assert!((t.beta - want).abs() < 4e-16 * want, "{} {want}", t.beta);
        let (w, s, h) = (1.0_f64, 1e3_f64, 1e-2_f64);
        let t = DampedTwoStep::new(w, s, h);
        let lam = ((s - w) * (s + w)).sqrt();
        let x = w * w / (s + lam) * h;
        let want = (x - x * x / 2.0 + x * x * x / 6.0) * (1.0 - (-(s + lam) * h).exp());
        assert!((t.beta - want).abs() < 1e-15 * want, "{} {want}", t.beta);
    }

    #[test]
    fn two_step_recursion_reproduces_samples_in_all_regimes() {
        // Under-, critically and over-damped, σ within 1e-12 of ω (no 0/0), ω = 0: the
        // recursion must reproduce the propagator's samples to round-off (1e-12 relative to q0
        // over 40 steps).
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
            let co = DampedTwoStep::new(omega, sigma, h);
            assert!(co.c.is_finite() && co.omega_tilde_sq().is_finite() && co.beta >= 0.0);
            let (q0, v0) = (1.0, 0.3);
            let mut d = first_increment(omega, sigma, h, q0, v0);
            let mut q = q0 + d;
            assert!((q - closed(omega, sigma, h, q0, v0)).abs() < 1e-15);
            for n in 2..40 {
                d = co.c_tilde * d - co.beta * q;
                q += d;
                let want = closed(omega, sigma, n as f64 * h, q0, v0);
                assert!((q - want).abs() < 1e-12, "ω={omega} σ={sigma} n={n}");
            }
            assert!((co.beta - (1.0 + co.c_tilde - co.c)).abs() < 1e-15 * 4.0);
        }
    }

    #[test]
    fn huge_overdamping_stays_finite() {
        let co = DampedTwoStep::new(1.0, 1e6, 1.0);
        assert!(co.c.is_finite() && co.c_tilde == 0.0 && co.beta.is_finite());
        assert!(co.sigma_tilde().is_finite() && co.omega_tilde_sq().is_finite());
        assert!(first_increment(1.0, 1e6, 1.0, 1.0, 0.0).is_finite());
        let co = DampedTwoStep::new(1e6, 1e3, 1.0);
        assert!(co.omega_tilde_sq().is_finite() && co.sigma_tilde() == 1.0);
    }
}
