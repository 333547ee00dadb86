//! The rest shape of a plate voice (a curved plate: a dome, a boss): the note's `a_k` from the
//! bank's unit projections, set on the tier in use when it changes.
//!
//! A shape given in plate thicknesses scales with the note: on a plate of size `L` and
//! thickness `h` a rise `H = dome · h` has `a_k = L ∫ w0 Φ̂_k dŜ = L h · dome · â_k`
//! ([`crate::models::plate::rest_shape`]), so the curvature parameter `κ = 2H/h` is the same at
//! every key and a note's spectrum stays a pure rescaling of the root key's (the key scales `h`).
//!
//! Threads: audio thread, no allocation.

use super::PlateVoice;
use crate::engine::params::{ParamId, ParamValues};

impl PlateVoice {
    /// Sets the rest shape of the tier in use for size `a` (m) and the note's thickness `h` (m):
    /// `a_k = a h (dome · â_dome,k + boss · â_boss,k)`, only when its amplitudes differ from
    /// those last set on that model (a flat note, dome = boss = 0, never calls the model: the
    /// flat plate bit for bit). Audio thread: O(N_Φ) plus, on a change, two passes over the
    /// tier's coupling tensor ([`crate::models::plate::PlateModel::set_rest_shape`]); no
    /// allocation.
    pub(super) fn set_shape(&mut self, v: &ParamValues, a: f64, h: f64) {
        let lh = a * h;
        let amp = (
            lh * v.get(ParamId::Dome) as f64,
            lh * v.get(ParamId::Boss) as f64,
        );
        if amp == self.rest_set[self.tier] {
            return;
        }
        let (n, _) = self.data.tiers[self.tier];
        let (dome, boss) = (&self.data.shape_dome, &self.data.shape_boss);
        for ((r, &d), &b) in self.rest[..n].iter_mut().zip(dome).zip(boss) {
            *r = amp.0 * d + amp.1 * b;
        }
        // Finite by construction (finite parameters and projections), so this cannot refuse.
        if self.models[self.tier]
            .set_rest_shape(&self.rest[..n])
            .is_ok()
        {
            self.rest_set[self.tier] = amp;
        }
    }
}
