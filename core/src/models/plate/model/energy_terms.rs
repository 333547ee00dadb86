//! The plate's discrete energy bookkeeping (the terms and the power balance of
//! [`super::super`]'s energy identity), updated at every step on the audio thread.

use super::PlateModel;
use crate::models::plate::coupling::ModalCoupling;
use crate::models::plate::partial_sums::lane_sums;

impl<C: ModalCoupling + ?Sized> PlateModel<C> {
    /// Adds this step's dissipated energy and external work (uses `q(n+1)`, `q(n-1)`), with
    /// `closure` (J) the truncation closure's part, and the energy the SAV relaxation removed
    /// (counted as dissipated; the physical part is kept as the next step's relaxation budget).
    pub(super) fn update_power(&mut self, force: f64, closure: f64) {
        let before = self.energy.dissipated;
        let (h, rho_h, n) = (self.h, self.rho_h, self.q.len());
        let (qn, qp) = (&self.q_next[..n], &self.q_prev[..n]);
        let (c, fw) = (&self.c_eff[..n], &self.force_weights[..n]);
        // With δ_s = q_s(n+1) - q_s(n-1), the centred velocity is δ_s / 2h.
        let [diss, pw] = lane_sums(n, |s| {
            let d = qn[s] - qp[s];
            [c[s] * d * d, fw[s] * d]
        });
        let inv_2h = 0.5 / h;
        self.energy.dissipated += h * rho_h * diss * inv_2h * inv_2h + closure;
        self.energy.closure += closure;
        self.energy.work += h * force * pw * inv_2h;
        if self.hand.c > 0.0 {
            self.hand_power();
        }
        self.step_dissipated = self.energy.dissipated - before;
        if let Some(sav) = self.sav.as_mut() {
            let removed = sav.take_relaxed();
            self.energy.dissipated += removed;
            self.energy.relaxed += removed;
        }
    }

    /// Recomputes `t`, `v`, `u` from `q(n)`, `q(n-1)`, `Ĥ(q(n), q(n-1))`.
    pub(super) fn update_stored_energy(&mut self, reset_accumulators: bool) {
        let (h, rho_h, n) = (self.h, self.rho_h, self.q.len());
        let (q, qp, w2) = (&self.q[..n], &self.q_prev[..n], &self.omega_sq[..n]);
        let [t, v] = lane_sums(n, |s| {
            let d = q[s] - qp[s];
            [d * d, w2[s] * q[s] * qp[s]]
        });
        self.energy.kinetic = 0.5 * rho_h * t / (h * h);
        self.energy.linear = 0.5 * rho_h * v;
        self.energy.nonlinear = match &self.sav {
            Some(sav) => 0.5 * sav.psi * sav.psi,
            None => self
                .u_coef
                .iter()
                .zip(&self.b_half)
                .map(|(c, b)| c * b * b)
                .sum(),
        };
        if reset_accumulators {
            self.energy.dissipated = 0.0;
            self.energy.hand_dissipated = 0.0;
            self.energy.relaxed = 0.0;
            self.energy.closure = 0.0;
            self.energy.work = 0.0;
            self.energy.step = 0;
        }
    }
}
