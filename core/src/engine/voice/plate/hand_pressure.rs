//! The player's hand on a plate voice: its weights, `c_max` and pressure on the tier in use
//! (placement and design in [`crate::engine::voice::hand_placement`]).
//!
//! Threads: audio thread, no allocation.

use super::PlateVoice;
use crate::engine::voice::hand_placement::hand_c_max;

impl PlateVoice {
    /// The hand of the tier in use: weights `Φ̂_s / a` at the hand point, zero from the kept
    /// limit on ([`PlateVoice::kept_limit`]) as the strike's and the pickups' (the exact scheme
    /// aliases the modes above `0.45 fs`, and a damper coupling them to the heard ones would
    /// damp by aliased velocities; a nonlinear note's modes from `0.36 fs` are overdamped),
    /// `c_max` for the note ([`hand_c_max`]) and `c = pressure · c_max`. Audio thread,
    /// O(N_Φ), no allocation.
    pub(super) fn write_hand(&mut self, a: f64, rho_h: f64) {
        let (n, _) = self.data.tiers[self.tier];
        let wmax = self.kept_limit();
        let model = &mut self.models[self.tier];
        let inv_a = 1.0 / a;
        for ((w, &x), &om) in model
            .hand_weights_mut()
            .iter_mut()
            .zip(&self.hand_w)
            .zip(&self.omega)
        {
            *w = if om < wmax { x * inv_a } else { 0.0 };
        }
        self.hand_c_max = hand_c_max(rho_h, &model.hand_weights()[..n]);
        self.apply_pressure();
    }

    /// Sets the player's hand pressure `pressure` (0 to 1, clamped; 0 lifts the hand): the
    /// hand's damper coefficient becomes `pressure · c_max`. O(1) when unchanged or applied;
    /// audio thread, no allocation.
    pub fn set_pressure(&mut self, pressure: f64) {
        let p = pressure.clamp(0.0, 1.0);
        if p != self.pressure {
            self.pressure = p;
            self.apply_pressure();
        }
    }

    /// `c = pressure · c_max` on the tier in use.
    fn apply_pressure(&mut self) {
        let c = self.pressure * self.hand_c_max;
        // `c` is finite and ≥ 0 by construction (`hand_c_max` is), so this cannot refuse.
        let _ = self.models[self.tier].set_hand_damping(c);
    }
}
