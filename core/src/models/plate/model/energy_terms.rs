//! The plate's discrete energy bookkeeping (the terms and the power balance of
//! [`super::super`]'s energy identity), updated at every step on the audio thread.

use super::PlateModel;
use crate::models::plate::coupling::ModalCoupling;

impl<C: ModalCoupling + ?Sized> PlateModel<C> {
    /// Adds this step's dissipated energy and external work (uses `q(n+1)`, `q(n-1)`).
    pub(super) fn update_power(&mut self, force: f64) {
        let (h, rho_h) = (self.h, self.rho_h);
        let (mut diss, mut pw) = (0.0, 0.0);
        for s in 0..self.q.len() {
            let v = (self.q_next[s] - self.q_prev[s]) / (2.0 * h);
            diss += self.c_eff[s] * v * v;
            pw += self.force_weights[s] * v;
        }
        self.energy.dissipated += h * rho_h * diss;
        self.energy.work += h * force * pw;
        if self.hand.c > 0.0 {
            self.hand_power();
        }
    }

    /// Recomputes `t`, `v`, `u` from `q(n)`, `q(n-1)`, `Ĥ(q(n), q(n-1))`.
    pub(super) fn update_stored_energy(&mut self, reset_accumulators: bool) {
        let (h, rho_h) = (self.h, self.rho_h);
        let (mut t, mut v) = (0.0, 0.0);
        for s in 0..self.q.len() {
            let dq = (self.q[s] - self.q_prev[s]) / h;
            t += dq * dq;
            v += self.omega_sq[s] * self.q[s] * self.q_prev[s];
        }
        self.energy.kinetic = 0.5 * rho_h * t;
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
            self.energy.work = 0.0;
            self.energy.step = 0;
        }
    }
}
