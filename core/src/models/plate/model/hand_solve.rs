//! The player's hand on [`PlateModel`]: placement, the closed-form solve with the step and its
//! energy (equations in [`crate::models::plate::hand_damper`]).

use super::{check_weights, PlateModel};
use crate::error::{check_non_negative, ParamError};
use crate::models::plate::coupling::ModalCoupling;
use crate::models::plate::linalg::dot;
use crate::models::plate::sav::SavCoefficients;

impl<C: ModalCoupling + ?Sized> PlateModel<C> {
    /// Puts the hand at the point with mode values `weights` = `Φ_s(x_h)` (1/m, length `N_Φ`)
    /// with damper coefficient `c` (N·s/m, ≥ 0; 0 lifts the hand). Errors name the field
    /// (`hand_weights`, `hand_damping`), the value and the allowed range; on error nothing
    /// changes. No allocation; the thread that owns the model.
    pub fn set_hand(&mut self, weights: &[f64], c: f64) -> Result<(), ParamError> {
        check_weights("hand_weights", weights, self.q.len())?;
        check_non_negative("hand_damping", c)?;
        self.hand.weights.copy_from_slice(weights);
        self.set_hand_damping(c)
    }

    /// Sets the hand's damper coefficient `c` (N·s/m, finite, ≥ 0; 0 lifts the hand) at the
    /// current hand point. Errors name `hand_damping`. No allocation, O(1); audio thread.
    pub fn set_hand_damping(&mut self, c: f64) -> Result<(), ParamError> {
        self.hand.c = check_non_negative("hand_damping", c)?;
        if c == 0.0 {
            self.hand.force = 0.0;
        }
        Ok(())
    }

    /// The hand point's weights `Φ_s(x_h)` (1/m), writable in place (no validation: keep them
    /// finite). Audio thread.
    pub fn hand_weights_mut(&mut self) -> &mut [f64] {
        &mut self.hand.weights
    }

    /// The hand point's weights `Φ_s(x_h)` (1/m).
    pub fn hand_weights(&self) -> &[f64] {
        &self.hand.weights
    }

    /// The hand's damper coefficient `c` (N·s/m); 0 when no hand rests on the plate.
    pub fn hand_damping(&self) -> f64 {
        self.hand.c
    }

    /// The hand's force `F_h(n-1) = -c δ_{t.}w_h` of the last step (N); 0 without a hand.
    pub fn hand_force(&self) -> f64 {
        self.hand.force
    }

    /// The response of this step's `q(n+1)` to a unit force (1 N) at the hand point (`hand`)
    /// or at the force point, into `hand.z` or `f` (units of `q` per N), after the force-free
    /// step has run (it uses that step's `g` (SAV) or factorisation (conservative)); returns
    /// `g·z` for SAV, 0 otherwise. Audio thread: `O(N_Φ)` (one back-substitution for the
    /// conservative schemes), no allocation.
    pub(super) fn unit_response(&mut self, hand: bool) -> f64 {
        let h2_over_rho_h = self.h * self.h / self.rho_h;
        let (weights, z) = if hand {
            (&self.hand.weights, &mut self.hand.z)
        } else {
            (&self.force_weights, &mut self.f)
        };
        if let Some(sav) = self.sav.as_ref() {
            let k = SavCoefficients {
                inv_a: &self.inv_a,
                b: &self.b,
                force_weights: weights,
                u_coef: &self.u_coef,
                h2_over_rho_h,
            };
            return sav.unit_response(&k, z);
        }
        match self.solver.as_mut() {
            None => {
                for ((z, &ia), &phi) in z.iter_mut().zip(&self.inv_a).zip(weights) {
                    *z = h2_over_rho_h * ia * phi;
                }
            }
            Some(solver) => {
                for (r, &phi) in self.r.iter_mut().zip(weights) {
                    *r = h2_over_rho_h * phi;
                }
                solver.solve_factored(&self.inv_a, &self.r, z);
            }
        }
        0.0
    }

    /// Applies the hand to the step in `q_next` (the force-free or pulse-forced `q*(n+1)`):
    /// `F_h0 = -γ (w_h* - w_h(n-1)) / (1 + γ c_hh)`, `q(n+1) = q* + F_h0 z_h` (and `ψ` for SAV).
    /// With `mallet`, also turns the force point's response `f` into `z_f + k z_h` and returns
    /// `(F_h0, k, k g·z_h)` so the caller can add the mallet force (module docs); `hand.force`
    /// is set to `F_h0`. The caller refreshes `Ĥ(q(n+1), q(n))` for the non-SAV schemes.
    /// Audio thread: `O(N_Φ)` plus one back-substitution, no allocation.
    pub(super) fn apply_hand(&mut self, mallet: bool) -> (f64, f64, f64) {
        let gzh = self.unit_response(true);
        let hw = &self.hand.weights;
        let w_star = dot(hw, &self.q_next);
        let w_prev = dot(hw, &self.q_prev);
        let chh = dot(hw, &self.hand.z);
        let gamma = self.hand.c / (2.0 * self.h);
        let den = 1.0 + gamma * chh;
        let fh0 = -gamma * (w_star - w_prev) / den;
        let k = if mallet {
            -gamma * dot(hw, &self.f) / den
        } else {
            0.0
        };
        for (q, &z) in self.q_next.iter_mut().zip(&self.hand.z) {
            *q += fh0 * z;
        }
        if mallet {
            for (zf, &z) in self.f.iter_mut().zip(&self.hand.z) {
                *zf += k * z;
            }
        }
        if let Some(sav) = self.sav.as_mut() {
            sav.psi += 0.5 * fh0 * gzh;
        }
        self.hand.force = fh0;
        (fh0, k, k * gzh)
    }

    /// The hand's share of this step's power: adds `-h F_h δ_{t.}w_h` (J) to the dissipated
    /// energy (uses `q(n+1)`, `q(n-1)`). Called only with the hand on.
    pub(super) fn hand_power(&mut self) {
        let hw = &self.hand.weights;
        let v = (dot(hw, &self.q_next) - dot(hw, &self.q_prev)) / (2.0 * self.h);
        let e = -self.h * self.hand.force * v;
        self.energy.dissipated += e;
        self.energy.hand_dissipated += e;
    }

    /// After a force was added to `q(n+1)`: flushes the decayed modes and recomputes
    /// `Ĥ(q(n+1), q(n))` (the non-SAV schemes; SAV carries `ψ` instead).
    pub(super) fn refresh_b_next(&mut self) {
        if self.sav.is_none() {
            crate::models::flush_tiny(&mut self.q_next);
            self.update_b_next();
        }
    }
}
