//! Störmer-Verlet (leap-frog) for separable systems `H = ½|p|² + V(q)` (SEED.md section 2;
//! HLW section I.1.4 and Theorem VI.3.4).
//!
//! Velocity-Verlet form on `y = [q; p]` with the force `f = -∇V`:
//! `p_{n+½} = p_n + (h/2) f(q_n)`, `q_{n+1} = q_n + h p_{n+½}`,
//! `p_{n+1} = p_{n+½} + (h/2) f(q_{n+1})`. Eliminating `p` gives
//! `q_{n+1} - 2 q_n + q_{n-1} = h² f(q_n)`. Order 2, symmetric, symplectic; linearly stable for
//! `h ω ≤ 2`.
//!
//! Separability is checked in two places: [`StormerVerlet::for_system`] probes the system
//! (through [`HamiltonianSystem::separable_force`]) and returns a [`ParamError`] if it is not
//! separable; [`OneStepMethod::step`] panics with an explicit message if called on a
//! non-separable system (a programming error once the constructor check is bypassed).

use super::runge_kutta::{assert_dims, check_dof, MAX_EXPLICIT_DOF};
use super::{HamiltonianSystem, OneStepMethod};
use crate::error::ParamError;

/// Störmer-Verlet for states of one fixed dimension `2n` (unit masses).
///
/// Built on any thread, owned and stepped by one thread; `step` does two force evaluations and
/// no allocation.
#[derive(Debug, Clone)]
pub struct StormerVerlet {
    /// Number of positions `n`.
    n: usize,
    /// Force scratch `f(q)`, length `n`.
    force: Vec<f64>,
}

impl StormerVerlet {
    /// Builds the method for `degrees_of_freedom = n` positions without seeing the system
    /// (the factory path); the error names `degrees_of_freedom` (in `[1, 2^20]`). A
    /// non-separable system then makes `step` panic: prefer [`Self::for_system`].
    pub fn new(degrees_of_freedom: usize) -> Result<Self, ParamError> {
        let n = check_dof(degrees_of_freedom, MAX_EXPLICIT_DOF)?;
        Ok(Self {
            n,
            force: vec![0.0; n],
        })
    }

    /// Builds the method for `system`, checking it is separable by probing
    /// `separable_force` at `q = 0`. Error field `system` (value: the system's name) if not.
    pub fn for_system(system: &dyn HamiltonianSystem) -> Result<Self, ParamError> {
        let mut method = Self::new(system.degrees_of_freedom())?;
        let probe_q = vec![0.0; method.n];
        if !system.separable_force(&probe_q, &mut method.force) {
            return Err(ParamError::new(
                "system",
                system.name(),
                "a separable system H = ½|p|² + V(q) (stormer-verlet needs separable_force)",
            ));
        }
        Ok(method)
    }

    /// Writes `f(q)` into the scratch, panicking clearly if the system is not separable.
    fn eval_force(&mut self, system: &dyn HamiltonianSystem, q: &[f64]) {
        assert!(
            system.separable_force(q, &mut self.force),
            "stormer-verlet: system `{}` is not separable (H = ½|p|² + V(q) required)",
            system.name()
        );
    }
}

impl OneStepMethod for StormerVerlet {
    fn name(&self) -> &'static str {
        "stormer-verlet"
    }

    fn order(&self) -> u32 {
        2
    }

    fn is_symplectic(&self) -> bool {
        true
    }

    fn step(&mut self, system: &dyn HamiltonianSystem, h: f64, y: &mut [f64]) {
        assert_dims("stormer-verlet", 2 * self.n, system, y);
        let n = self.n;
        let half = 0.5 * h;
        self.eval_force(system, &y[..n]);
        let (q, p) = y.split_at_mut(n);
        for ((qi, pi), &fi) in q.iter_mut().zip(p.iter_mut()).zip(&self.force) {
            *pi += half * fi;
            *qi += h * *pi;
        }
        self.eval_force(system, &y[..n]);
        for (pi, &fi) in y[n..].iter_mut().zip(&self.force) {
            *pi += half * fi;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::systems::Pendulum;
    use super::*;

    #[test]
    fn satisfies_the_two_step_recurrence() {
        // q_{n+1} - 2 q_n + q_{n-1} = h² f(q_n) holds up to rounding of O(1) quantities: 1e-14.
        let sys = Pendulum::new(1.3).unwrap();
        let mut m = StormerVerlet::for_system(&sys).unwrap();
        let h = 0.2;
        let mut y = [1.0, 0.5];
        let mut qs = vec![y[0]];
        for _ in 0..20 {
            m.step(&sys, h, &mut y);
            qs.push(y[0]);
        }
        for w in qs.windows(3) {
            let f = -1.3_f64 * 1.3 * w[1].sin();
            assert!((w[2] - 2.0 * w[1] + w[0] - h * h * f).abs() < 1e-14);
        }
    }
}
