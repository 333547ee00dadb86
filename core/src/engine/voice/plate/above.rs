//! The band above a plate voice's simulation, per note: the plate's linear modes from the top
//! of the note's tier up to [`ceiling_hz`] of the rate they run at (data in
//! [`crate::engine::voice::above`]), run at the bank's above rate (the host rate up to 48 kHz,
//! [`crate::engine::above_mix`]), fed with exactly the energy the tier's truncation closure absorbs
//! and the energy the mallet's contact gives the modes above (the contact residual's,
//! [`crate::models::plate::contact_residual`]; [`crate::models::plate::extension`]). Their frequencies, damping law and pickups are the
//! note's own, continued past the tier; the pickups and the strike sit at the bank's radii (a
//! note's own pickup or strike radius moves only the simulated band).
//!
//! Threads: the audio thread or the voice's job, without allocation.

use super::{Frame, PlateVoice, VOICE_CEILING};
use crate::modal::scaling::flexural_rigidity;
use crate::models::plate::contact_residual::ContactResidual;
use crate::models::plate::extension::ceiling_hz;
use crate::models::source::EnergyTerms;
use std::f64::consts::TAU;

impl PlateVoice {
    /// The band above the note's tier: the listed modes from the tier's count on, under the
    /// ceiling, with the note's `ω = λ² scale` and damping `law(ω)`, and pickups `Φ̂_e / a`
    /// in the note's frame. Audio thread: O(N_e), no allocation.
    pub(super) fn retune_above(
        &mut self,
        scale: f64,
        law: impl Fn(f64) -> f64,
        a: f64,
        rho_h: f64,
    ) {
        let modes = &self.data.above;
        // The band above starts at the first mode the note does not keep in motion
        // (`kept.rs`): the tier's top modes past it on a nonlinear plate, the next mode of
        // the list otherwise.
        let from = self
            .kept_modes(self.data.tiers[self.tier].0)
            .min(modes.list.len());
        let ceiling = TAU * ceiling_hz(self.above.rate);
        let mut k = 0;
        for &l2 in &modes.list.lambda2[from..] {
            let w = l2 * scale;
            if w >= ceiling {
                break;
            }
            self.above.omega[k] = w;
            self.above.damping[k] = law(w);
            k += 1;
        }
        let h = 1.0 / self.above.rate;
        let above = &mut self.above;
        above
            .bank
            .retune(&above.omega[..k], &above.damping[..k], rho_h, h);
        let inv_a = 1.0 / a;
        // The strike sits at angle 0 of a mirror frame (and at the bank's point of a fixed
        // one): no rotation, and the shares ignore the common `1/a`.
        above.bank.set_strike(&modes.strike[from..from + k]);
        for c in 0..2 {
            let phi = &modes.pickups[c][from..from + k];
            let w = above.bank.pickup_weights_mut(c);
            match &self.data.frame {
                Frame::Mirror { pickup_angles, .. } => {
                    let d = pickup_angles[c] - self.angle;
                    for (e, (w, &x)) in w.iter_mut().zip(phi).enumerate() {
                        let n = modes.list.cosine_order(from + e).unwrap_or(0);
                        *w = x * (f64::from(n) * d).cos() * inv_a;
                    }
                }
                Frame::Fixed { .. } => {
                    for (w, &x) in w.iter_mut().zip(phi) {
                        *w = x * inv_a;
                    }
                }
            }
        }
    }

    /// The residual of the modes above the note's band at the mallet's contact
    /// ([`crate::models::plate::contact_residual`]), for a plate of Young's modulus `e` (Pa),
    /// thickness `h` (m) and surface density `rho_h` (kg/m²) on the tier's first `n` modes:
    /// on with the band above and the `strike_above` parameter (the modes the band continues
    /// are the ones the contact feels), off otherwise. Audio thread, O(n).
    pub(super) fn set_residual(&mut self, e: f64, h: f64, rho_h: f64, n: usize) {
        let kept = self.kept_modes(n);
        let d = flexural_rigidity(e, h, self.data.poisson);
        let (k, r) = if self.above.on && self.above.contact && kept > 0 {
            ContactResidual::for_plate(d, rho_h, self.omega[kept - 1]).unwrap_or((0.0, 0.0))
        } else {
            (0.0, 0.0)
        };
        // Non-negative and finite by construction, so this cannot fail.
        let _ = self.models[self.tier].set_contact_residual(k, r);
    }

    /// Modes of the note's band above (0 while the `band_above` parameter is off).
    pub(super) fn above_modes(&self) -> usize {
        if self.above.on {
            self.above.bank.len()
        } else {
            0
        }
    }

    /// Angular frequency (rad/s) of the band above's highest mode (0 without one).
    pub(super) fn above_top(&self) -> f64 {
        match self.above_modes() {
            0 => 0.0,
            n => self.above.omega[n - 1],
        }
    }

    /// The voice's energy terms (J): the tier model's, with its band above's as the scene
    /// voice counts them (stored and pending energy in `above`, the closure's share of the
    /// dissipation replaced by the band's own losses), so the power balance closes over both.
    /// Audio thread; O(N_e) while the band is awake.
    pub fn energy_terms(&self) -> EnergyTerms {
        let mut e: EnergyTerms = self.model().energy().into();
        if !self.above.idle {
            self.above.bank.energy().fold_into(&mut e);
        }
        e
    }

    /// Runs the band above for `left.len()` samples at its rate with the energy the closure
    /// absorbed and the contact residual took from the strike since the last call, adding
    /// `gain ·` its pickups; `false` past [`VOICE_CEILING`]. Skipped (O(1)) while nothing was
    /// ever received or struck, or the band is off. Audio thread or the voice's job; no
    /// allocation, O(N_e) per sample when it runs.
    pub fn run_above(&mut self, left: &mut [f32], right: &mut [f32], gain: f64) -> bool {
        let model = &mut self.models[self.tier];
        let (absorbed, struck) = (model.take_absorbed(), model.take_struck());
        let above = &mut self.above;
        if !above.on || above.bank.is_empty() || (above.idle && absorbed <= 0.0 && struck <= 0.0) {
            return true;
        }
        above.idle = false;
        let mut ok = true;
        above.bank.run(absorbed, struck, left.len(), |k, o| {
            let (a, b) = (gain * o[0], gain * o[1]);
            ok &= a.abs() <= VOICE_CEILING && b.abs() <= VOICE_CEILING;
            left[k] += a as f32;
            right[k] += b as f32;
        });
        ok
    }
}
