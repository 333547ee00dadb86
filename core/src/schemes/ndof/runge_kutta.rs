//! Explicit Runge-Kutta methods built from a [`ButcherTableau`] (HLW section II.1.1; Butcher
//! 2008, chapter 3).
//!
//! `k_i = f(y_n + h Σ_{j<i} a_ij k_j)`, `y_{n+1} = y_n + h Σ_i b_i k_i`. None of these methods is
//! symplectic (their tableaus fail `b_i a_ij + b_j a_ji = b_i b_j`, HLW Theorem VI.4.3).

use super::butcher::ButcherTableau;
use super::{HamiltonianSystem, OneStepMethod};
use crate::error::ParamError;

/// Largest number of degrees of freedom a method may be built for (bounds scratch memory).
pub const MAX_EXPLICIT_DOF: usize = 1 << 20;

/// An explicit Runge-Kutta method for states of one fixed dimension `2n`.
///
/// Built (and scratch allocated) on any thread, then owned and stepped by one thread; `step`
/// does not allocate and does `s` vector-field evaluations.
#[derive(Debug, Clone)]
pub struct ExplicitRungeKutta {
    /// The method's coefficients (static data).
    tableau: &'static ButcherTableau,
    /// State dimension `2n`.
    dim: usize,
    /// Stage derivatives `k_1..k_s`, stage-major, length `s · 2n`.
    k: Vec<f64>,
    /// Stage argument `y_n + h Σ_j a_ij k_j`, length `2n`.
    stage_state: Vec<f64>,
}

impl ExplicitRungeKutta {
    /// Builds the method for `degrees_of_freedom = n` positions (state length `2n`).
    ///
    /// Errors: `tableau` if it is malformed or not explicit; `degrees_of_freedom` outside
    /// `[1, 2^20]`.
    pub fn new(
        tableau: &'static ButcherTableau,
        degrees_of_freedom: usize,
    ) -> Result<Self, ParamError> {
        if !tableau.is_well_formed() || !tableau.is_explicit() {
            return Err(ParamError::new(
                "tableau",
                tableau.name,
                "a well-formed explicit tableau (a_ij = 0 for j >= i)",
            ));
        }
        check_dof(degrees_of_freedom, MAX_EXPLICIT_DOF)?;
        let dim = 2 * degrees_of_freedom;
        Ok(Self {
            tableau,
            dim,
            k: vec![0.0; tableau.stages * dim],
            stage_state: vec![0.0; dim],
        })
    }

    /// The tableau this method was built from.
    pub fn tableau(&self) -> &'static ButcherTableau {
        self.tableau
    }
}

/// Checks `degrees_of_freedom` against `[1, max]`.
pub(super) fn check_dof(degrees_of_freedom: usize, max: usize) -> Result<usize, ParamError> {
    if (1..=max).contains(&degrees_of_freedom) {
        Ok(degrees_of_freedom)
    } else {
        Err(ParamError::new(
            "degrees_of_freedom",
            degrees_of_freedom,
            format!("integer in [1, {max}]"),
        ))
    }
}

/// Panics with a clear message if the state or the system does not match the dimension the
/// method was built for (a programming error, not a user input error).
pub(super) fn assert_dims(name: &str, dim: usize, system: &dyn HamiltonianSystem, y: &[f64]) {
    assert!(
        y.len() == dim && 2 * system.degrees_of_freedom() == dim,
        "{name}: built for state length {dim}, got state length {} and system `{}` with {} \
         degrees of freedom",
        y.len(),
        system.name(),
        system.degrees_of_freedom()
    );
}

impl OneStepMethod for ExplicitRungeKutta {
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
        let dim = self.dim;
        let t = self.tableau;
        for i in 0..t.stages {
            self.stage_state.copy_from_slice(y);
            for j in 0..i {
                let a = t.a(i, j);
                if a != 0.0 {
                    let kj = &self.k[j * dim..(j + 1) * dim];
                    for (s, &kv) in self.stage_state.iter_mut().zip(kj) {
                        *s += h * a * kv;
                    }
                }
            }
            system.vector_field(&self.stage_state, &mut self.k[i * dim..(i + 1) * dim]);
        }
        for i in 0..t.stages {
            let b = t.b[i];
            if b != 0.0 {
                let ki = &self.k[i * dim..(i + 1) * dim];
                for (yv, &kv) in y.iter_mut().zip(ki) {
                    *yv += h * b * kv;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::butcher::{GAUSS1, RK4};
    use super::super::systems::LinearChain;
    use super::*;

    #[test]
    fn rejects_implicit_tableau_and_zero_dof() {
        assert_eq!(
            ExplicitRungeKutta::new(&GAUSS1, 2).unwrap_err().field,
            "tableau"
        );
        assert_eq!(
            ExplicitRungeKutta::new(&RK4, 0).unwrap_err().field,
            "degrees_of_freedom"
        );
    }

    #[test]
    fn rk4_matches_its_stability_polynomial_on_a_harmonic_oscillator() {
        // One mass between two walls with k = 1/2: ω = 1. RK4 applied to ẏ = Ay gives
        // y_1 = R(hA) y_0 with R(z) = 1 + z + z²/2 + z³/6 + z⁴/24; for A = [[0,1],[-1,0]],
        // R(hA) = [[c, s], [-s, c]] with c = 1 - h²/2 + h⁴/24, s = h - h³/6. Rounding only:
        // 1e-15.
        let sys = LinearChain::new(1, 0.5).unwrap();
        let mut m = ExplicitRungeKutta::new(&RK4, 1).unwrap();
        let h: f64 = 0.3;
        let mut y = [1.0, 0.0];
        m.step(&sys, h, &mut y);
        let c = 1.0 - h * h / 2.0 + h.powi(4) / 24.0;
        let s = h - h.powi(3) / 6.0;
        assert!(
            (y[0] - c).abs() < 1e-15 && (y[1] + s).abs() < 1e-15,
            "{y:?}"
        );
    }
}
