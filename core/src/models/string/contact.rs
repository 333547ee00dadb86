//! The contact law and the per-node scalar solve of the discrete-gradient contact force.
//!
//! Potential `ψ(η) = K/(α+1) [η]_+^{α+1}` (J/m), force density `ψ'(η) = K [η]_+^α` (N/m),
//! `η = g - u` the penetration (SEED.md 3.2, Issanchou et al. 2017 eq. (9)-(10)).
//! The discrete gradient at node i is `f = Φ(r) = (ψ(η⁻ + r) - ψ(η⁻)) / r`, `r = η^{n+1} - η^{n-1}`,
//! `η⁻ = η^{n-1}`; `Φ(0) = ψ'(η⁻)`.
//!
//! The scheme gives, at a node, `η^{n+1} = η_free - k f` with `k = h²/μ` and the free
//! penetration `η_free = g - u_free` (see the module doc of `string` for why this is exact and
//! pointwise). With `b = η_free - η⁻` the unknown `r` solves
//! `G(r) = r + k Φ(r) - b = 0`.
//! `ψ` is convex, so `Φ` is non-decreasing and `Φ ≥ 0`: `G' ≥ 1`, the root is unique and lies in
//! `[b - kΦ(b), b]`. When `η⁻ ≤ 0` and `η_free ≤ 0` the root is `r = b` with `f = 0` (no
//! contact), found without iterating.
//!
//! Solver: Newton-Raphson from the upper end `r = b`, safeguarded by the bracket (a Newton
//! iterate outside the current bracket is replaced by the bracket's midpoint, i.e. a bisection
//! step). Stops when a step moves `r` by at most `NEWTON_TOL · max(|b|, |r|, |η⁻|)`; after
//! [`NEWTON_CAP`] iterations the bracket's midpoint is used (the root is known to lie in the
//! bracket) and the cap hit is counted.
//!
//! `Φ` is evaluated without cancellation: both penetrations positive uses
//! `ψ(η⁻+r) - ψ(η⁻) = K/(α+1) (η⁻)^{α+1} expm1((α+1) ln_1p(r/η⁻))`, which is accurate for any
//! tiny `r` (the `r → 0` limit `ψ'(η⁻)` comes out of it); otherwise one of the two values is
//! zero and `|r|` is at least the other penetration.
//!
//! Runs on the audio thread: no allocation, at most `NEWTON_CAP` iterations per node.

use crate::error::{check_closed, check_positive, ParamError};

/// Iteration cap of the per-node Newton solve.
pub const NEWTON_CAP: usize = 50;

/// Relative step tolerance of the Newton solve (see the module doc). Newton converges
/// quadratically, so the error left after the last accepted step is of order its square; the
/// residual's round-off is a few ulps of the same scale, so 1e-13 is reachable.
pub const NEWTON_TOL: f64 = 1e-13;

/// Penalty contact law `f = K [η]_+^α`.
///
/// Built on the control thread; evaluated by the audio thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLaw {
    /// Penalty stiffness `K` in N/m^(α+1) (> 0).
    pub stiffness: f64,
    /// Exponent `α` (dimensionless, in [1, 10]; `α ≥ 1` keeps ψ twice differentiable).
    pub exponent: f64,
}

impl ContactLaw {
    /// The lecture's values (SEED.md 3.2): `K = 1e13`, `α = 1.5`.
    pub fn lecture() -> Self {
        Self {
            stiffness: 1e13,
            exponent: 1.5,
        }
    }

    /// Checks `K > 0` and `1 ≤ α ≤ 10`.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_positive("contact.stiffness", self.stiffness)?;
        check_closed("contact.exponent", self.exponent, 1.0, 10.0)?;
        Ok(())
    }

    /// `x^α` for `x > 0`: `x √x` for the lecture's `α = 1.5` (a correctly rounded square root
    /// and one product, within an ulp or two of `powf` and several times cheaper), else `powf`.
    #[inline]
    fn pow_alpha(&self, x: f64) -> f64 {
        if self.exponent == 1.5 {
            x * x.sqrt()
        } else {
            x.powf(self.exponent)
        }
    }

    /// Potential `ψ(η)` in J/m.
    pub fn psi(&self, eta: f64) -> f64 {
        if eta > 0.0 {
            self.stiffness / (self.exponent + 1.0) * eta * self.pow_alpha(eta)
        } else {
            0.0
        }
    }

    /// Force density `ψ'(η) = K [η]_+^α` in N/m.
    pub fn force(&self, eta: f64) -> f64 {
        if eta > 0.0 {
            self.stiffness * self.pow_alpha(eta)
        } else {
            0.0
        }
    }

    /// `ψ''(η) = K α [η]_+^{α-1}` in N/m².
    fn stiffness_at(&self, eta: f64) -> f64 {
        if eta > 0.0 {
            self.stiffness * self.exponent * self.pow_alpha(eta) / eta
        } else {
            0.0
        }
    }

    /// Discrete gradient `Φ(r) = (ψ(x + r) - ψ(x)) / r` (N/m), `Φ(0) = ψ'(x)`.
    pub fn divided_difference(&self, x: f64, r: f64) -> f64 {
        let y = x + r;
        if r == 0.0 {
            return self.force(x);
        }
        if x > 0.0 && y > 0.0 {
            let p = self.exponent + 1.0;
            let t = r / x;
            // (ψ(y) - ψ(x)) / r = K/p · x^p · expm1(p ln(1+t)) / (t x)
            let ratio = if self.exponent == 1.5 {
                // ((1+t)^{5/2} - 1)/t with s = √(1+t): s⁵ - 1 = (s - 1)(s⁴ + s³ + s² + s + 1)
                // and s - 1 = t/(s + 1), so the ratio is (s⁴ + s³ + s² + s + 1)/(s + 1),
                // free of cancellation for any t > -1 (5/2 at t = 0) and one square root.
                let s = (1.0 + t).sqrt();
                (((s + 1.0) * s + 1.0) * s * s + s + 1.0) / (s + 1.0)
            } else {
                (p * t.ln_1p()).exp_m1() / t
            };
            self.stiffness / p * self.pow_alpha(x) * ratio
        } else {
            (self.psi(y) - self.psi(x)) / r
        }
    }

    /// `Φ'(r)` (N/m²), used only as the Newton slope: Taylor form `ψ''(x)(1/2 + (α-1)t/3)`,
    /// `t = r/x`, when `|r| < 1e-4 x`, else `(ψ'(x+r) - Φ(r))/r`; clamped at ≥ 0 (Φ is
    /// non-decreasing).
    pub(crate) fn divided_difference_slope(&self, x: f64, r: f64, phi: f64) -> f64 {
        if x > 0.0 && r.abs() < 1e-4 * x {
            self.stiffness_at(x) * (0.5 + (self.exponent - 1.0) * (r / x) / 3.0)
        } else {
            ((self.force(x + r) - phi) / r).max(0.0)
        }
    }
}

/// Result of one node's solve.
///
/// Produced and consumed on the audio thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointSolution {
    /// `r = η^{n+1} - η^{n-1}` in m.
    pub r: f64,
    /// Contact force density `f^n = Φ(r)` in N/m (≥ 0).
    pub force: f64,
    /// Newton iterations used (0 when no contact was possible).
    pub iterations: usize,
    /// Whether the cap was hit (the bracket midpoint was used).
    pub capped: bool,
}

/// Solves `r + k Φ(r) = b` at one node with `η⁻ = eta_prev` (m), `k = h²/μ` (m·s²/kg... i.e.
/// m²/N per unit force density), see the module doc.
pub fn solve_point(law: &ContactLaw, eta_prev: f64, b: f64, k: f64) -> PointSolution {
    let phi_b = law.divided_difference(eta_prev, b);
    if phi_b == 0.0 {
        // Both penetrations ≤ 0: G(b) = 0 exactly.
        return PointSolution {
            r: b,
            force: 0.0,
            iterations: 0,
            capped: false,
        };
    }
    let mut hi = b;
    let mut lo = b - k * phi_b;
    let mut r = hi;
    let mut phi = phi_b;
    for it in 1..=NEWTON_CAP {
        let g = r + k * phi - b;
        if g == 0.0 {
            return PointSolution {
                r,
                force: phi,
                iterations: it,
                capped: false,
            };
        }
        if g > 0.0 {
            hi = r;
        } else {
            lo = r;
        }
        let slope = 1.0 + k * law.divided_difference_slope(eta_prev, r, phi);
        let step = g / slope;
        let scale = b.abs().max(r.abs()).max(eta_prev.abs());
        if step.abs() <= NEWTON_TOL * scale {
            // Converged: the Newton correction is below tolerance (it may round to `r`
            // itself, which is why this test comes before the bracket test).
            let r = r - step;
            return PointSolution {
                r,
                force: law.divided_difference(eta_prev, r),
                iterations: it,
                capped: false,
            };
        }
        let mut next = r - step;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        r = next;
        phi = law.divided_difference(eta_prev, r);
        if hi - lo <= NEWTON_TOL * scale {
            return PointSolution {
                r,
                force: phi,
                iterations: it,
                capped: false,
            };
        }
    }
    let r = 0.5 * (lo + hi);
    PointSolution {
        r,
        force: law.divided_difference(eta_prev, r),
        iterations: NEWTON_CAP,
        capped: true,
    }
}

/// Counters of the contact solves.
///
/// Updated by the audio thread in `step`; read by any thread after the run (copy).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactStats {
    /// `histogram[k]` = number of node-steps whose solve took `k` Newton iterations
    /// (`k = 0`: no contact possible, closed form), `k = 0..=NEWTON_CAP`.
    pub histogram: [u64; NEWTON_CAP + 1],
    /// Node-steps that hit the iteration cap (fallback: bracket midpoint).
    pub cap_hits: u64,
    /// Largest penetration `η^{n+1}` seen, in m (0 if never in contact).
    pub max_penetration: f64,
    /// Steps during which at least one node had a non-zero contact force.
    pub contact_steps: u64,
}

impl Default for ContactStats {
    fn default() -> Self {
        Self {
            histogram: [0; NEWTON_CAP + 1],
            cap_hits: 0,
            max_penetration: 0.0,
            contact_steps: 0,
        }
    }
}

impl ContactStats {
    /// Largest iteration count any node-step needed.
    pub fn max_iterations(&self) -> usize {
        self.histogram.iter().rposition(|&c| c > 0).unwrap_or(0)
    }

    /// Total node-steps solved.
    pub fn node_steps(&self) -> u64 {
        self.histogram.iter().sum()
    }

    /// Mean iterations over the node-steps that needed at least one.
    pub fn mean_iterations_in_contact(&self) -> f64 {
        let (n, s) = self
            .histogram
            .iter()
            .enumerate()
            .skip(1)
            .fold((0u64, 0u64), |(n, s), (k, &c)| (n + c, s + c * k as u64));
        if n == 0 {
            0.0
        } else {
            s as f64 / n as f64
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn divided_difference_is_accurate_for_tiny_steps() {
        let law = ContactLaw::lecture();
        let x = 1e-7;
        for &r in &[1e-30, 1e-20, 1e-12, -1e-12] {
            let d = law.divided_difference(x, r);
            // Taylor series of Φ to second order: ψ'(x)[1 + (α/2)t + α(α-1)/6 t²], t = r/x.
            let (a, t) = (law.exponent, r / x);
            let want = law.force(x) * (1.0 + 0.5 * a * t + a * (a - 1.0) / 6.0 * t * t);
            assert!((d / want - 1.0).abs() < 1e-14, "r={r}: {d} vs {want}");
        }
        assert_eq!(law.divided_difference(-1e-7, 5e-8), 0.0);
    }

    /// The α = 1.5 square-root forms equal the general `powf`/`expm1`/`ln_1p` forms to a few
    /// ulps: tolerance 1e-14 relative (each side is a handful of correctly rounded operations;
    /// the general form's `expm1(p ln1p t)` amplifies the ulp of `ln1p` by `p = 2.5`).
    #[test]
    fn square_root_forms_match_the_general_law() {
        let law = ContactLaw::lecture();
        let (k, a, p) = (law.stiffness, law.exponent, law.exponent + 1.0);
        for &x in &[1e-9f64, 3.7e-7, 2e-5, 1e-3] {
            let f = k * x.powf(a);
            assert!((law.force(x) / f - 1.0).abs() < 1e-14, "force at {x}");
            let psi = k / p * x.powf(p);
            assert!((law.psi(x) / psi - 1.0).abs() < 1e-14, "psi at {x}");
            let s2 = k * a * x.powf(a - 1.0);
            assert!(
                (law.stiffness_at(x) / s2 - 1.0).abs() < 1e-14,
                "stiffness at {x}"
            );
            for &t in &[-0.999f64, -0.5, -1e-6, 1e-9, 0.3, 1.0, 40.0, 1e6] {
                let general = k / p * x.powf(a) * ((p * f64::ln_1p(t)).exp_m1() / t);
                let fast = law.divided_difference(x, t * x);
                assert!(
                    (fast / general - 1.0).abs() < 1e-14,
                    "x={x} t={t}: {fast} {general}"
                );
            }
        }
    }

    #[test]
    fn solve_point_satisfies_the_scalar_equation() {
        // Residual of r + kΦ(r) = b below 1e-13 of the scale, for soft and very stiff cases.
        let law = ContactLaw::lecture();
        for &(eta_prev, b, k) in &[
            (0.0, 1e-6, 2e-10),
            (1e-7, -3e-7, 2e-10),
            (-1e-6, 2e-5, 3.7e-7),
            (2e-6, 1e-5, 3.7e-7),
            (1e-9, 1e-3, 1e-4),
        ] {
            let s = solve_point(&law, eta_prev, b, k);
            let res = s.r + k * s.force - b;
            let scale = b.abs().max(s.r.abs()).max(eta_prev.abs());
            assert!(!s.capped && res.abs() <= 1e-12 * scale, "{s:?} res {res}");
        }
    }
}
