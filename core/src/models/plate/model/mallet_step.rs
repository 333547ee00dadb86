//! The plate step under a [`Mallet`]'s contact force (equations and solve in
//! [`crate::models::plate::mallet`]): the force-free step, the response `z` to a unit force,
//! one scalar solve, and `q(n+1) += F z`.

use super::{Diverged, PlateModel};
use crate::error::ParamError;
use crate::models::plate::coupling::ModalCoupling;
use crate::models::plate::linalg::dot;
use crate::models::plate::mallet::Mallet;

impl<C: ModalCoupling + ?Sized> PlateModel<C> {
    /// Launches `mallet` at `speed` (m/s, > 0) towards the plate at the force point (the
    /// weights of [`Self::set_force_weights`]), from just short of the plate's current surface
    /// there: a strike on a sounding plate meets the moving plate, nothing is reset. Errors:
    /// `speed` not positive and finite, or a mallet built for another time step (field
    /// `mallet.h`). No allocation; the thread that owns the plate.
    pub fn launch_mallet(&self, mallet: &mut Mallet, speed: f64) -> Result<(), ParamError> {
        if mallet.h() != self.h {
            return Err(ParamError::new(
                "mallet.h",
                mallet.h(),
                format!("the plate's time step h = {}", self.h),
            ));
        }
        // The contact point moves with the residual of the modes above (if on).
        let w = dot(&self.force_weights, &self.q) + self.residual.u();
        let w_prev = dot(&self.force_weights, &self.q_prev) + self.residual.u_prev();
        mallet.launch(speed, w, w_prev)
    }

    /// Sets the residual of the modes above the truncation at the mallet's contact: a spring
    /// `k` (N/m) and a dashpot `r` (N·s/m) in parallel, in series with the plate
    /// ([`crate::models::plate::contact_residual`]; `ContactResidual::for_plate` gives them
    /// for a plate); `(0, 0)` turns it off (the default). Errors name the field. No
    /// allocation; the thread that owns the plate.
    pub fn set_contact_residual(&mut self, k: f64, r: f64) -> Result<(), ParamError> {
        self.residual.set(k, r)
    }

    /// The energy the contact residual's dashpot took since the last call (J, ≥ 0; 0 while
    /// it is off): what the band above the simulation receives from the strike
    /// ([`crate::models::plate::extension`]). No allocation.
    pub fn take_struck(&mut self) -> f64 {
        self.residual.take_dissipated()
    }

    /// Advances one step `n → n + 1` with the force `F(n)` of `mallet`'s felt on the plate at
    /// the force point, solved jointly with the mallet's motion (energy conserving, see
    /// [`crate::models::plate::mallet`]), and with the player's hand (if any, see
    /// [`Self::set_hand`]) eliminated from the scalar solve; a mallet not yet launched exerts
    /// no force. Pickups, energy and divergence as [`Self::step`] (the plate's
    /// [`super::PlateEnergy::work`] counts the mallet's work). Audio thread: no allocation; the plate step plus `O(N_Φ)`
    /// (`O(N_Φ N_Ψ)` or `O(N_Φ²)` for the conservative schemes' extra back-substitution).
    pub fn step_with_mallet(&mut self, mallet: &mut Mallet) -> Result<(), Diverged> {
        if !mallet.is_active() || self.diverged {
            return self.step(0.0);
        }
        // Force-free q*(n+1), then z = ∂q(n+1)/∂F into `f`.
        if self.scheme_step(0.0).is_err() {
            return Err(self.fail());
        }
        let mut sav_gz = self.unit_response(false);
        // The hand (if any) eliminated: F_h = F_h0 + k F, q* and z shifted (see `hand`).
        let hand = self.hand.c > 0.0;
        let (mut hand_k, mut fh0) = (0.0, 0.0);
        if hand {
            let (f0, k, kgz) = self.apply_hand(true);
            (fh0, hand_k) = (f0, k);
            sav_gz += kgz;
        }
        // The residual of the modes above (if on) in series: more compliance at the contact.
        let (u_star, c_u) = self.residual.predict(self.h);
        let w_star = dot(&self.force_weights, &self.q_next) + u_star;
        let compliance = dot(&self.force_weights, &self.f) + c_u;
        let w_prev = dot(&self.force_weights, &self.q_prev) + self.residual.u_prev();
        let force = mallet.contact_step(w_star, compliance, w_prev);
        self.residual.advance(self.h, force);
        if force != 0.0 {
            for (q, &z) in self.q_next.iter_mut().zip(&self.f) {
                *q += force * z;
            }
            if let Some(sav) = self.sav.as_mut() {
                sav.psi += 0.5 * force * sav_gz;
            }
        }
        if hand {
            self.hand.force = fh0 + hand_k * force;
        }
        if force != 0.0 || hand {
            self.refresh_b_next();
        }
        self.finish_step(force)
    }
}
