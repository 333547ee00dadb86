//! Implicit Runge-Kutta methods (the Gauss collocation methods) built from a
//! [`ButcherTableau`], with a simplified Newton solver for the stage equations.
//!
//! Stage equations in increment form (Hairer-Wanner, "Solving ODEs II", section IV.8; HLW
//! section VIII.6): `Z_i = h Σ_j a_ij f(y_n + Z_j)`, then `y_{n+1} = y_n + h Σ_i b_i f(y_n + Z_i)`.
//!
//! Solver (per step, all on preallocated scratch):
//! - predictor `Z_i = c_i h f(y_n)`;
//! - [`StageSolver::Newton`] (default): simplified Newton with the Jacobian `J = f'(y_n)`
//!   frozen for the step, matrix `I - h A ⊗ J` (size `s·2n`) factored once by LU with partial
//!   pivoting; iteration `(I - h A⊗J) ΔZ = -Z + h (A⊗I) F(Z)`;
//! - [`StageSolver::FixedPoint`]: `Z ← h (A⊗I) F(Z)` (for systems without a usable Jacobian;
//!   converges for `h L |A| < 1`, L the Lipschitz constant of `f`).
//!
//! Convergence: `‖ΔZ‖_∞ ≤ tol · max(‖y_n‖_∞, ‖Z‖_∞)` with `tol` =
//! [`DEFAULT_TOLERANCE`] (1e-14), or `ΔZ = 0`, within at most [`DEFAULT_MAX_ITERATIONS`] (50)
//! iterations. Defined fallbacks, each counted in [`StepperStats::solver_failures`]:
//! - zero or non-finite pivot in the LU (singular `I - h A⊗J`, or non-finite Jacobian): the
//!   step switches to fixed-point iteration (with the remaining iteration budget);
//! - iteration cap reached, or an iterate becomes non-finite: the last finite iterate is
//!   accepted and the step completes with it.
//!
//! The Gauss methods conserve every quadratic invariant (HLW Theorem IV.2.2) and are
//! symplectic (HLW Theorem VI.4.3), up to the solver tolerance and rounding.

use super::butcher::ButcherTableau;
use super::runge_kutta::{assert_dims, check_dof};
use super::{HamiltonianSystem, OneStepMethod};
use crate::error::ParamError;
use crate::schemes::StepperStats;

/// Largest number of degrees of freedom an implicit method may be built for: the Newton
/// matrix has `(2 s n)²` entries and its LU costs `O((2 s n)³)` per step.
pub const MAX_IMPLICIT_DOF: usize = 256;

/// Default relative tolerance on the stage increment `ΔZ` (see the module docs).
pub const DEFAULT_TOLERANCE: f64 = 1e-14;

/// Default cap on solver iterations per step.
pub const DEFAULT_MAX_ITERATIONS: u32 = 50;

/// How the stage equations are solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum StageSolver {
    /// Simplified Newton with the system's Jacobian at `y_n` (preferred).
    #[default]
    Newton,
    /// Fixed-point iteration (no Jacobian needed; slower, needs small `h`).
    FixedPoint,
}

/// An implicit Runge-Kutta method (in practice Gauss 1 or 2) for states of one fixed dimension.
///
/// Built (scratch allocated) on any thread, then owned and stepped by one thread; `step` does
/// not allocate and runs at most `max_iterations` solver iterations.
#[derive(Debug, Clone)]
pub struct ImplicitRungeKutta {
    /// The method's coefficients (static data).
    tableau: &'static ButcherTableau,
    /// State dimension `m = 2n`.
    dim: usize,
    /// Stage solver in use.
    solver: StageSolver,
    /// Relative tolerance on `‖ΔZ‖_∞`.
    tolerance: f64,
    /// Iteration cap per step.
    max_iterations: u32,
    /// Stage increments `Z_i`, stage-major, length `s·m`.
    z: Vec<f64>,
    /// Stage derivatives `F_i = f(y_n + Z_i)`, length `s·m`.
    f: Vec<f64>,
    /// Newton right-hand side, then increment `ΔZ`, length `s·m`.
    rhs: Vec<f64>,
    /// Stage argument `y_n + Z_i`, length `m`.
    stage_state: Vec<f64>,
    /// Jacobian `f'(y_n)`, row-major `m × m`.
    jac: Vec<f64>,
    /// Newton matrix `I - h A⊗J`, overwritten by its LU factors, row-major `(s m)²` (empty for
    /// fixed-point).
    lu: Vec<f64>,
    /// Row permutation of the LU factorisation, length `s·m` (empty for fixed-point).
    perm: Vec<usize>,
    /// Solver counters since build.
    stats: StepperStats,
}

impl ImplicitRungeKutta {
    /// Builds the method with simplified Newton, tolerance 1e-14 and 50 iterations per step.
    ///
    /// Errors: `tableau` if malformed or explicit (use [`super::runge_kutta::ExplicitRungeKutta`]);
    /// `degrees_of_freedom` outside `[1, 256]`.
    pub fn new(
        tableau: &'static ButcherTableau,
        degrees_of_freedom: usize,
    ) -> Result<Self, ParamError> {
        Self::with_solver(
            tableau,
            degrees_of_freedom,
            StageSolver::Newton,
            DEFAULT_TOLERANCE,
            DEFAULT_MAX_ITERATIONS,
        )
    }

    /// Builds the method with an explicit solver choice, relative `tolerance` (in
    /// `[1e-16, 1e-3]`) and `max_iterations` (in `[1, 1000]`).
    pub fn with_solver(
        tableau: &'static ButcherTableau,
        degrees_of_freedom: usize,
        solver: StageSolver,
        tolerance: f64,
        max_iterations: u32,
    ) -> Result<Self, ParamError> {
        if !tableau.is_well_formed() || tableau.is_explicit() {
            return Err(ParamError::new(
                "tableau",
                tableau.name,
                "a well-formed implicit tableau",
            ));
        }
        check_dof(degrees_of_freedom, MAX_IMPLICIT_DOF)?;
        let tolerance = crate::error::check_closed("tolerance", tolerance, 1e-16, 1e-3)?;
        if !(1..=1000).contains(&max_iterations) {
            return Err(ParamError::new(
                "max_iterations",
                max_iterations,
                "integer in [1, 1000]",
            ));
        }
        let m = 2 * degrees_of_freedom;
        let sm = tableau.stages * m;
        let newton = solver == StageSolver::Newton;
        Ok(Self {
            tableau,
            dim: m,
            solver,
            tolerance,
            max_iterations,
            z: vec![0.0; sm],
            f: vec![0.0; sm],
            rhs: vec![0.0; sm],
            stage_state: vec![0.0; m],
            jac: if newton { vec![0.0; m * m] } else { Vec::new() },
            lu: if newton {
                vec![0.0; sm * sm]
            } else {
                Vec::new()
            },
            perm: if newton { vec![0; sm] } else { Vec::new() },
            stats: StepperStats::default(),
        })
    }

    /// The tableau this method was built from.
    pub fn tableau(&self) -> &'static ButcherTableau {
        self.tableau
    }

    /// The stage solver in use.
    pub fn solver(&self) -> StageSolver {
        self.solver
    }

    /// Evaluates `F_i = f(y + Z_i)` for every stage.
    fn eval_stages(&mut self, system: &dyn HamiltonianSystem, y: &[f64]) {
        let m = self.dim;
        for i in 0..self.tableau.stages {
            for ((s, &yv), &zv) in self
                .stage_state
                .iter_mut()
                .zip(y)
                .zip(&self.z[i * m..(i + 1) * m])
            {
                *s = yv + zv;
            }
            system.vector_field(&self.stage_state, &mut self.f[i * m..(i + 1) * m]);
        }
    }

    /// Writes `h (A⊗I) F` (minus `Z` when `minus_z`) into `rhs`.
    fn residual(&mut self, h: f64, minus_z: bool) {
        let m = self.dim;
        let t = self.tableau;
        for i in 0..t.stages {
            let out = &mut self.rhs[i * m..(i + 1) * m];
            if minus_z {
                for (o, &zv) in out.iter_mut().zip(&self.z[i * m..(i + 1) * m]) {
                    *o = -zv;
                }
            } else {
                out.fill(0.0);
            }
            for j in 0..t.stages {
                let a = h * t.a(i, j);
                for (o, &fv) in out.iter_mut().zip(&self.f[j * m..(j + 1) * m]) {
                    *o += a * fv;
                }
            }
        }
    }

    /// Assembles `I - h A⊗J` and factors it in place; `false` on a zero or non-finite pivot.
    fn factor_newton_matrix(&mut self, h: f64) -> bool {
        let m = self.dim;
        let s = self.tableau.stages;
        let sm = s * m;
        for bi in 0..s {
            for bj in 0..s {
                let a = h * self.tableau.a(bi, bj);
                for r in 0..m {
                    let row = (bi * m + r) * sm + bj * m;
                    for c in 0..m {
                        let id = if bi == bj && r == c { 1.0 } else { 0.0 };
                        self.lu[row + c] = id - a * self.jac[r * m + c];
                    }
                }
            }
        }
        lu_factor(&mut self.lu, &mut self.perm, sm)
    }
}

/// In-place LU factorisation with partial pivoting of the row-major `n × n` matrix `a`
/// (Doolittle, unit lower factor stored below the diagonal). `perm[k]` is the original row now
/// at position `k`. Returns `false` (leaving `a` partly factored) on a zero or non-finite pivot.
pub fn lu_factor(a: &mut [f64], perm: &mut [usize], n: usize) -> bool {
    for (k, p) in perm.iter_mut().enumerate().take(n) {
        *p = k;
    }
    for k in 0..n {
        let (mut piv, mut best) = (k, a[k * n + k].abs());
        for r in k + 1..n {
            let v = a[r * n + k].abs();
            if v > best {
                piv = r;
                best = v;
            }
        }
        if best == 0.0 || !best.is_finite() {
            return false;
        }
        if piv != k {
            for c in 0..n {
                a.swap(k * n + c, piv * n + c);
            }
            perm.swap(k, piv);
        }
        let inv = 1.0 / a[k * n + k];
        for r in k + 1..n {
            let l = a[r * n + k] * inv;
            a[r * n + k] = l;
            if l != 0.0 {
                for c in k + 1..n {
                    a[r * n + c] -= l * a[k * n + c];
                }
            }
        }
    }
    true
}

/// Solves `A x = b` in place (`x` overwrites `b`) with factors from [`lu_factor`]; `work` is
/// scratch of length `n`.
pub fn lu_solve(lu: &[f64], perm: &[usize], n: usize, b: &mut [f64], work: &mut [f64]) {
    for k in 0..n {
        work[k] = b[perm[k]];
    }
    for r in 0..n {
        let mut s = work[r];
        for c in 0..r {
            s -= lu[r * n + c] * work[c];
        }
        work[r] = s;
    }
    for r in (0..n).rev() {
        let mut s = work[r];
        for c in r + 1..n {
            s -= lu[r * n + c] * work[c];
        }
        work[r] = s / lu[r * n + r];
    }
    b[..n].copy_from_slice(&work[..n]);
}

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |acc, x| acc.max(x.abs()))
}

impl OneStepMethod for ImplicitRungeKutta {
    fn name(&self) -> &'static str {
        self.tableau.name
    }

    fn order(&self) -> u32 {
        self.tableau.order
    }

    fn is_symplectic(&self) -> bool {
        self.tableau.conserves_quadratic_invariants()
    }

    fn step(&mut self, system: &dyn HamiltonianSystem, h: f64, y: &mut [f64]) {
        assert_dims(self.tableau.name, self.dim, system, y);
        let m = self.dim;
        let s = self.tableau.stages;
        let sm = s * m;
        // Predictor Z_i = c_i h f(y_n); f(y_n) goes through `rhs` as scratch.
        system.vector_field(y, &mut self.rhs[..m]);
        for i in 0..s {
            let c = self.tableau.c[i] * h;
            for (zv, &fv) in self.z[i * m..(i + 1) * m].iter_mut().zip(&self.rhs[..m]) {
                *zv = c * fv;
            }
        }
        let mut newton = self.solver == StageSolver::Newton;
        let mut failed = false;
        if newton {
            system.vector_field_jacobian(y, &mut self.jac);
            if !self.factor_newton_matrix(h) {
                newton = false;
                failed = true;
            }
        }
        let y_scale = max_abs(y);
        let mut converged = false;
        let mut iterations = 0_u32;
        while iterations < self.max_iterations {
            iterations += 1;
            self.eval_stages(system, y);
            self.residual(h, true);
            if newton {
                // `f` is free until the next evaluation: use it as the solve's work vector.
                lu_solve(&self.lu, &self.perm, sm, &mut self.rhs, &mut self.f);
            }
            let dz = max_abs(&self.rhs[..sm]);
            if !dz.is_finite() {
                break;
            }
            let candidate_ok = self
                .z
                .iter()
                .zip(&self.rhs)
                .all(|(z, d)| (z + d).is_finite());
            if !candidate_ok {
                break;
            }
            for (zv, &d) in self.z.iter_mut().zip(&self.rhs) {
                *zv += d;
            }
            if dz == 0.0 || dz <= self.tolerance * y_scale.max(max_abs(&self.z)) {
                converged = true;
                break;
            }
        }
        if !converged {
            failed = true;
        }
        // y_{n+1} = y_n + h Σ b_i f(y_n + Z_i), with F at the final stages.
        self.eval_stages(system, y);
        for i in 0..s {
            let b = h * self.tableau.b[i];
            for (yv, &fv) in y.iter_mut().zip(&self.f[i * m..(i + 1) * m]) {
                *yv += b * fv;
            }
        }
        self.stats.solver_iterations += u64::from(iterations);
        self.stats.max_iterations_per_step = self.stats.max_iterations_per_step.max(iterations);
        if failed {
            self.stats.solver_failures += 1;
        }
    }

    fn stats(&self) -> StepperStats {
        self.stats
    }
}

#[cfg(test)]
mod tests {
    use super::super::butcher::{GAUSS1, GAUSS2, RK4};
    use super::super::systems::{LinearChain, Pendulum};
    use super::*;

    #[test]
    fn lu_solves_a_system_needing_pivoting() {
        // [[0, 2, 1], [1, 1, 0], [3, 0, 1]] x = b with x = [1, -2, 3]; rounding only: 1e-14.
        let mut a = vec![0.0, 2.0, 1.0, 1.0, 1.0, 0.0, 3.0, 0.0, 1.0];
        let mut perm = vec![0; 3];
        assert!(lu_factor(&mut a, &mut perm, 3));
        let mut b = vec![-1.0, -1.0, 6.0];
        let mut w = vec![0.0; 3];
        lu_solve(&a, &perm, 3, &mut b, &mut w);
        for (x, e) in b.iter().zip([1.0, -2.0, 3.0]) {
            assert!((x - e).abs() < 1e-14, "{b:?}");
        }
        let mut singular = vec![1.0, 2.0, 2.0, 4.0];
        assert!(!lu_factor(&mut singular, &mut perm[..2], 2));
    }

    #[test]
    fn implicit_midpoint_on_linear_oscillator_matches_cayley_transform() {
        // Gauss1 on ẏ = Ay is y1 = (I - hA/2)⁻¹(I + hA/2) y0: for ω = 1, the rotation by
        // angle 2 atan(h/2). Newton is exact in one iteration for linear f (the second one
        // confirms ΔZ ≈ 0). Rounding only: 1e-15.
        let sys = LinearChain::new(1, 0.5).unwrap();
        let mut m = ImplicitRungeKutta::new(&GAUSS1, 1).unwrap();
        let h: f64 = 0.4;
        let mut y = [1.0, 0.0];
        m.step(&sys, h, &mut y);
        let th = 2.0 * (h / 2.0).atan();
        assert!((y[0] - th.cos()).abs() < 1e-15 && (y[1] + th.sin()).abs() < 1e-15);
        let st = m.stats();
        assert!(st.max_iterations_per_step <= 2, "{st:?}");
        assert_eq!(st.solver_failures, 0);
    }

    #[test]
    fn newton_and_fixed_point_agree_and_count_iterations() {
        // Both solve the same stage equations to 1e-14 relative: the results agree to a few
        // rounding units of the state (size ~1): 1e-13. Fixed-point converges linearly with
        // rate ~h·ω·|A| ≈ 0.05, so it needs more iterations than Newton.
        let sys = Pendulum::new(1.0).unwrap();
        let mut newton = ImplicitRungeKutta::new(&GAUSS2, 1).unwrap();
        let mut fixed =
            ImplicitRungeKutta::with_solver(&GAUSS2, 1, StageSolver::FixedPoint, 1e-14, 50)
                .unwrap();
        let (mut y1, mut y2) = ([2.0, 0.3], [2.0, 0.3]);
        for _ in 0..100 {
            newton.step(&sys, 0.1, &mut y1);
            fixed.step(&sys, 0.1, &mut y2);
        }
        assert!((y1[0] - y2[0]).abs() < 1e-13 && (y1[1] - y2[1]).abs() < 1e-13);
        let (sn, sf) = (newton.stats(), fixed.stats());
        assert_eq!(sn.solver_failures + sf.solver_failures, 0);
        assert!(sn.solver_iterations < sf.solver_iterations, "{sn:?} {sf:?}");
        assert!(sn.max_iterations_per_step <= 10, "{sn:?}");
    }

    #[test]
    fn iteration_cap_uses_fallback_and_counts_failure() {
        // Fixed-point with one iteration allowed cannot reach 1e-14 from the predictor at
        // h = 0.5: the step completes with the last iterate and counts one failure.
        let sys = Pendulum::new(1.0).unwrap();
        let mut m =
            ImplicitRungeKutta::with_solver(&GAUSS2, 1, StageSolver::FixedPoint, 1e-14, 1).unwrap();
        let mut y = [1.0, 0.0];
        m.step(&sys, 0.5, &mut y);
        assert!(y.iter().all(|v| v.is_finite()));
        assert_eq!(m.stats().solver_failures, 1);
        assert_eq!(m.stats().max_iterations_per_step, 1);
    }

    #[test]
    fn rejects_bad_parameters() {
        assert_eq!(
            ImplicitRungeKutta::new(&RK4, 1).unwrap_err().field,
            "tableau"
        );
        assert_eq!(
            ImplicitRungeKutta::new(&GAUSS2, MAX_IMPLICIT_DOF + 1)
                .unwrap_err()
                .field,
            "degrees_of_freedom"
        );
        let e = ImplicitRungeKutta::with_solver(&GAUSS1, 1, StageSolver::Newton, 0.0, 5);
        assert_eq!(e.unwrap_err().field, "tolerance");
        let e = ImplicitRungeKutta::with_solver(&GAUSS1, 1, StageSolver::Newton, 1e-12, 0);
        assert_eq!(e.unwrap_err().field, "max_iterations");
    }
}
