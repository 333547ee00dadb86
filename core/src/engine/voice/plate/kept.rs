//! The modes a note keeps in motion: on a nonlinear plate, a tier's modes at or above
//! [`NONLINEAR_BAND_FRACTION`]` fs` are overdamped, so they follow their forcing
//! quasi-statically and never oscillate near the step's Nyquist phase, where the in-plane
//! stress would pump them through the time step's aliasing.
//!
//! **Why.** A tier holds every mode under the band `B` and up to `√2` times as many (the tiers
//! are half an octave of modes apart, `engine/voice/plate.rs`), so at a key where the band
//! cuts a tier, its top modes reach `√2 B` in frequency: past `0.36 fs`, past the Nyquist
//! frequency even at the band's rate. The rate rule ([`crate::engine::plate_sim_rate`]) keeps
//! the modes under `B` clear of the aliased parametric resonance; the modes above it are not
//! what the note promised, so they take no part in its dynamics: their damping is
//! [`FROZEN_DAMPING_RATIO`]` ω` (fifty times critical), their weights (strike, pickups, hand)
//! are zero, and the band above the simulation starts at the first of them. Measured on the
//! 80 N gong on key 72 (a tier of 361 modes to 7.5 kHz, band 6 kHz) at velocity 127: with
//! those modes free, its 4-8 kHz band sat 16-28 dB under the total for three seconds where
//! its cascade (2-4 kHz) stays 84-100 dB under (docs/ACCURACY.md, the time step's aliasing).
//! A linear plate keeps every mode under [`HEARD_FRACTION`]` fs`, as before: without a stress
//! nothing pumps its modes.
//!
//! **Why `0.36`.** A step of the schemes with an exact linear part advances a mode of
//! pulsation `ω` by the phase `ωh` per step, however close to `π`. The in-plane stress modulates every mode's
//! stiffness, and a stiffness modulated at `Ω` pumps a mode parametrically when `Ωh = 2ωh`
//! modulo `2π` (the sampled Mathieu equation): besides the physical resonance `Ω = 2ω`, the
//! alias `Ω = 2π fs - 2ω`. For a top mode at `0.45 fs` that alias lies at `0.1 fs` (1.3 kHz
//! at 13.4 kHz), right in the stress of a loud note, whose strong part lies at the
//! differences of the low modes' frequencies: the top modes then fill from the first
//! milliseconds with a band the plate does not have. The lecture's gong struck at 80 N
//! (`gong-80N`, band 6 kHz, velocity 127) showed it at 4-8 kHz, 45-67 dB under the total from
//! the stroke on, where at 16.7, 20.1 and 26.8 kHz that band stays at -92 to -103 dB for six
//! seconds (the cascade itself stops near 3 kHz); resolved to 14 kHz at 31.2 kHz it put
//! nearly all of the note's energy into a 10-13 kHz band from the stroke (docs/ACCURACY.md,
//! the time step's aliasing). At `0.36 fs` the top mode's alias lies at `0.28 fs` (4.7 kHz
//! at 16.7 kHz), above the stress's strong part. The energy-conserving schemes keep the
//! energy bounded, so nothing blows up: the error is heard, not seen in a balance.
//!
//! Energy: an overdamped mode is a mode with a large damping, so the step stays the scheme's
//! (centred, dissipative) and its losses are counted as the damping's, to round-off.
//!
//! Threads: audio thread, no allocation.

use super::{band_fraction, PlateVoice};
#[cfg(doc)]
use super::{HEARD_FRACTION, NONLINEAR_BAND_FRACTION};
use std::f64::consts::TAU;

/// Damping of a mode a nonlinear note does not keep in motion, as a multiple of its angular
/// frequency (module doc): `c = 100 ω`, fifty times critical. It then creeps toward its
/// quasi-static response at the rate `ω / 100` (from 0 at a fresh note: its static deflection
/// under the stress, far under the band's motion) and cannot oscillate.
pub const FROZEN_DAMPING_RATIO: f64 = 100.0;

impl PlateVoice {
    /// The angular frequency (rad/s) from which the note's modes are not kept in motion:
    /// [`NONLINEAR_BAND_FRACTION`]` · 2π fs` on a nonlinear plate, [`HEARD_FRACTION`]`· 2π fs`
    /// (where the strike and the pickups stop) on a linear one. Audio thread.
    pub(super) fn kept_limit(&self) -> f64 {
        band_fraction(self.data.linear) * TAU * self.fs
    }

    /// Writes the damping of the tier's first `n` modes from their angular frequencies
    /// (already written) and the note's damping law `law` (1/s of rad/s): the law's under
    /// [`Self::kept_limit`], [`FROZEN_DAMPING_RATIO`]` ω` at or above it on a nonlinear plate.
    /// Audio thread, O(n).
    pub(super) fn write_damping(&mut self, n: usize, law: impl Fn(f64) -> f64) {
        let (kept, frozen) = (self.kept_limit(), !self.data.linear);
        for (c, &w) in self.damping[..n].iter_mut().zip(&self.omega[..n]) {
            *c = if frozen && w >= kept {
                FROZEN_DAMPING_RATIO * w
            } else {
                law(w)
            };
        }
    }

    /// How many of the tier's first `n` modes (sorted by frequency) are kept in motion.
    /// Audio thread, O(n).
    pub(super) fn kept_modes(&self, n: usize) -> usize {
        let limit = self.kept_limit();
        self.omega[..n].iter().take_while(|&&w| w < limit).count()
    }
}
