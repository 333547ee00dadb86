//! Butcher tableaus as constant data, and checks of their algebraic properties (SEED.md
//! section 2).
//!
//! A Runge-Kutta method with `s` stages applied to `ẏ = f(y)` is
//! `Y_i = y_n + h Σ_j a_ij f(Y_j)`, `y_{n+1} = y_n + h Σ_i b_i f(Y_i)`, with nodes
//! `c_i = Σ_j a_ij` (J. C. Butcher, "Numerical Methods for Ordinary Differential Equations",
//! 2008; E. Hairer, C. Lubich, G. Wanner, "Geometric Numerical Integration", 2nd ed. 2006,
//! section II.1, hereafter HLW).
//!
//! The order conditions checked here are the tree conditions of HLW Theorem III.1.5 (Butcher
//! 1964) for orders 1 to 4. The quadratic-invariant condition `b_i a_ij + b_j a_ji = b_i b_j`
//! is HLW Theorem IV.2.2 (Cooper 1987); by HLW Theorem VI.4.3 every RK method satisfying it is
//! symplectic.
//!
//! All items are immutable `const`/`static` data and pure functions: any thread may use them.

/// `√3 / 6` to double precision (Gauss 2-stage nodes and coefficients).
const SQRT3_OVER_6: f64 = 0.288_675_134_594_812_9;

/// Largest number of stages among the tableaus of this module (sizes fixed scratch arrays).
pub const MAX_STAGES: usize = 4;

/// A Runge-Kutta method as data: `s` stages, coefficients `a` (row-major `s × s`), weights
/// `b`, nodes `c`, and its classical order.
///
/// Immutable; the tables below are `static` and shared by every thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ButcherTableau {
    /// Identifier used on the command line (`midpoint`, `heun`, `rk4`, `rk38`, `gauss1`,
    /// `gauss2`).
    pub name: &'static str,
    /// Number of stages `s` (1 to [`MAX_STAGES`]).
    pub stages: usize,
    /// Classical order of accuracy `p` claimed by the literature (checked by unit tests against
    /// [`ButcherTableau::satisfied_order`]).
    pub order: u32,
    /// Stage coefficients `a_ij`, row-major, length `s²` (dimensionless).
    pub a: &'static [f64],
    /// Weights `b_i`, length `s` (dimensionless).
    pub b: &'static [f64],
    /// Nodes `c_i = Σ_j a_ij`, length `s` (fractions of the step).
    pub c: &'static [f64],
}

/// Explicit midpoint rule (Runge 1895), order 2: HLW section II.1.1; Butcher (2008), chapter 2.
pub static EXPLICIT_MIDPOINT: ButcherTableau = ButcherTableau {
    name: "midpoint",
    stages: 2,
    order: 2,
    a: &[0.0, 0.0, 0.5, 0.0],
    b: &[0.0, 1.0],
    c: &[0.0, 0.5],
};

/// Heun's method (explicit trapezoidal rule), order 2: Butcher (2008), chapter 2 (Heun 1900).
pub static HEUN: ButcherTableau = ButcherTableau {
    name: "heun",
    stages: 2,
    order: 2,
    a: &[0.0, 0.0, 1.0, 0.0],
    b: &[0.5, 0.5],
    c: &[0.0, 1.0],
};

/// Classical fourth-order Runge-Kutta method (Kutta 1901): HLW Table II.1.1 (left).
pub static RK4: ButcherTableau = ButcherTableau {
    name: "rk4",
    stages: 4,
    order: 4,
    #[rustfmt::skip]
    a: &[
        0.0, 0.0, 0.0, 0.0,
        0.5, 0.0, 0.0, 0.0,
        0.0, 0.5, 0.0, 0.0,
        0.0, 0.0, 1.0, 0.0,
    ],
    b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    c: &[0.0, 0.5, 0.5, 1.0],
};

/// Kutta's 3/8 rule, order 4: HLW Table II.1.1 (right).
pub static RK38: ButcherTableau = ButcherTableau {
    name: "rk38",
    stages: 4,
    order: 4,
    #[rustfmt::skip]
    a: &[
        0.0, 0.0, 0.0, 0.0,
        1.0 / 3.0, 0.0, 0.0, 0.0,
        -1.0 / 3.0, 1.0, 0.0, 0.0,
        1.0, -1.0, 1.0, 0.0,
    ],
    b: &[0.125, 0.375, 0.375, 0.125],
    c: &[0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0],
};

/// Gauss method with one stage, the implicit midpoint rule, order 2: HLW section II.1.3,
/// Table II.1.2 (`s = 1`).
pub static GAUSS1: ButcherTableau = ButcherTableau {
    name: "gauss1",
    stages: 1,
    order: 2,
    a: &[0.5],
    b: &[1.0],
    c: &[0.5],
};

/// Gauss method with two stages, order 4, nodes `c = ½ ∓ √3/6`: HLW Table II.1.2 (`s = 2`).
pub static GAUSS2: ButcherTableau = ButcherTableau {
    name: "gauss2",
    stages: 2,
    order: 4,
    a: &[0.25, 0.25 - SQRT3_OVER_6, 0.25 + SQRT3_OVER_6, 0.25],
    b: &[0.5, 0.5],
    c: &[0.5 - SQRT3_OVER_6, 0.5 + SQRT3_OVER_6],
};

/// Every tableau of this module, in the order of the method factory.
pub static ALL_TABLEAUS: [&ButcherTableau; 6] =
    [&EXPLICIT_MIDPOINT, &HEUN, &RK4, &RK38, &GAUSS1, &GAUSS2];

/// Highest order whose conditions [`ButcherTableau::order_residual`] can check.
pub const MAX_CHECKED_ORDER: u32 = 4;

impl ButcherTableau {
    /// `a_ij` (0-based indices).
    #[inline]
    pub fn a(&self, i: usize, j: usize) -> f64 {
        self.a[i * self.stages + j]
    }

    /// Whether the method is explicit (`a_ij = 0` for `j ≥ i`).
    pub fn is_explicit(&self) -> bool {
        (0..self.stages).all(|i| (i..self.stages).all(|j| self.a(i, j) == 0.0))
    }

    /// Whether the array lengths agree with `stages` and all entries are finite.
    pub fn is_well_formed(&self) -> bool {
        let s = self.stages;
        (1..=MAX_STAGES).contains(&s)
            && self.a.len() == s * s
            && self.b.len() == s
            && self.c.len() == s
            && self
                .a
                .iter()
                .chain(self.b)
                .chain(self.c)
                .all(|x| x.is_finite())
    }

    /// Largest `|c_i - Σ_j a_ij|` (the row-sum simplifying assumption, HLW (II.1.9)).
    pub fn row_sum_residual(&self) -> f64 {
        (0..self.stages)
            .map(|i| {
                let row: f64 = (0..self.stages).map(|j| self.a(i, j)).sum();
                (self.c[i] - row).abs()
            })
            .fold(0.0, f64::max)
    }

    /// `Σ_j a_ij g_j` for a vector `g` of length `s` indexed by stage.
    fn a_times(&self, i: usize, g: impl Fn(usize) -> f64) -> f64 {
        (0..self.stages).map(|j| self.a(i, j) * g(j)).sum()
    }

    /// Largest absolute residual among the order conditions of exactly order `p` (1 to 4),
    /// HLW Table III.1.1:
    ///
    /// - p = 1: `Σ b_i = 1`;
    /// - p = 2: `Σ b_i c_i = 1/2`;
    /// - p = 3: `Σ b_i c_i² = 1/3`, `Σ b_i a_ij c_j = 1/6`;
    /// - p = 4: `Σ b_i c_i³ = 1/4`, `Σ b_i c_i a_ij c_j = 1/8`, `Σ b_i a_ij c_j² = 1/12`,
    ///   `Σ b_i a_ij a_jk c_k = 1/24`.
    ///
    /// Returns `None` for `p` outside `1..=4`.
    pub fn order_residual(&self, p: u32) -> Option<f64> {
        let s = self.stages;
        let b = self.b;
        let c = self.c;
        let sum_b = |g: &dyn Fn(usize) -> f64| -> f64 { (0..s).map(|i| b[i] * g(i)).sum() };
        let residuals: [f64; 4] = match p {
            1 => [sum_b(&|_| 1.0) - 1.0, 0.0, 0.0, 0.0],
            2 => [sum_b(&|i| c[i]) - 0.5, 0.0, 0.0, 0.0],
            3 => [
                sum_b(&|i| c[i] * c[i]) - 1.0 / 3.0,
                sum_b(&|i| self.a_times(i, |j| c[j])) - 1.0 / 6.0,
                0.0,
                0.0,
            ],
            4 => [
                sum_b(&|i| c[i] * c[i] * c[i]) - 0.25,
                sum_b(&|i| c[i] * self.a_times(i, |j| c[j])) - 0.125,
                sum_b(&|i| self.a_times(i, |j| c[j] * c[j])) - 1.0 / 12.0,
                sum_b(&|i| self.a_times(i, |j| self.a_times(j, |k| c[k]))) - 1.0 / 24.0,
            ],
            _ => return None,
        };
        Some(residuals.iter().map(|r| r.abs()).fold(0.0, f64::max))
    }

    /// Highest `p ≤ 4` such that all order conditions of orders `1..=p` hold to `tol`
    /// (absolute), i.e. the order the tableau provably has up to 4 (0 if even consistency
    /// fails). Assumes the row-sum condition, see [`Self::row_sum_residual`].
    pub fn satisfied_order(&self, tol: f64) -> u32 {
        (1..=MAX_CHECKED_ORDER)
            .take_while(|&p| self.order_residual(p).is_some_and(|r| r <= tol))
            .last()
            .unwrap_or(0)
    }

    /// Largest `|b_i a_ij + b_j a_ji - b_i b_j|` over all `i, j`: zero exactly when the method
    /// conserves all quadratic invariants and is therefore symplectic (HLW Theorems IV.2.2 and
    /// VI.4.3).
    pub fn quadratic_invariant_residual(&self) -> f64 {
        let s = self.stages;
        let mut worst = 0.0_f64;
        for i in 0..s {
            for j in 0..s {
                let m = self.b[i] * self.a(i, j) + self.b[j] * self.a(j, i) - self.b[i] * self.b[j];
                worst = worst.max(m.abs());
            }
        }
        worst
    }

    /// Whether [`Self::quadratic_invariant_residual`] is below `1e-15` (the coefficients are
    /// stored to double precision, so an exact condition shows up as rounding residue only).
    pub fn conserves_quadratic_invariants(&self) -> bool {
        self.quadratic_invariant_residual() <= 1e-15
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Coefficients are rationals or `√3/6` rounded to double: residues of exact conditions are
    /// a few ulps of quantities of size ≤ 1, so 1e-14 separates "holds" from "fails" (failed
    /// conditions miss by at least 1/72 for these tableaus).
    const TOL: f64 = 1e-14;

    #[test]
    fn tableaus_are_well_formed_with_consistent_nodes() {
        for t in ALL_TABLEAUS {
            assert!(t.is_well_formed(), "{}", t.name);
            assert!(t.row_sum_residual() <= TOL, "{}", t.name);
        }
    }

    #[test]
    fn each_tableau_has_exactly_its_claimed_order() {
        for t in ALL_TABLEAUS {
            assert_eq!(t.satisfied_order(TOL), t.order, "{}", t.name);
            if t.order < MAX_CHECKED_ORDER {
                // The next order must fail clearly, not by rounding.
                let r = t.order_residual(t.order + 1).unwrap();
                assert!(r > 1e-3, "{}: order {} residual {r}", t.name, t.order + 1);
            }
        }
        assert_eq!(RK4.order_residual(5), None);
        assert_eq!(RK4.order_residual(0), None);
    }

    #[test]
    fn only_gauss_methods_satisfy_the_quadratic_invariant_condition() {
        for t in ALL_TABLEAUS {
            let gauss = t.name.starts_with("gauss");
            assert_eq!(t.conserves_quadratic_invariants(), gauss, "{}", t.name);
            assert_eq!(t.is_explicit(), !gauss, "{}", t.name);
            if !gauss {
                assert!(t.quadratic_invariant_residual() > 1e-2, "{}", t.name);
            }
        }
    }

    #[test]
    fn broken_tableau_loses_order() {
        // RK4 with a_32 perturbed: order 2 conditions only involve b and c, so they still hold,
        // while the order 3 condition Σ b_i a_ij c_j = 1/6 fails.
        static BROKEN: ButcherTableau = ButcherTableau {
            name: "broken",
            stages: 4,
            order: 4,
            #[rustfmt::skip]
            a: &[
                0.0, 0.0, 0.0, 0.0,
                0.5, 0.0, 0.0, 0.0,
                0.1, 0.4, 0.0, 0.0,
                0.0, 0.0, 1.0, 0.0,
            ],
            b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
            c: &[0.0, 0.5, 0.5, 1.0],
        };
        assert_eq!(BROKEN.satisfied_order(TOL), 2);
    }
}
