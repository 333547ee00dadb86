//! What every voice shares: the physical mapping's inputs ([`Physics`]), the note's pitch
//! ratio, the release rate and the output ceiling (see the module doc of [`super`]).
//!
//! Plain functions and `Copy` data, audio thread.

use crate::engine::params::{ParamId, ParamValues};
use crate::engine::tuning::KeyTuning;

/// Largest normalised output of one voice (pickup velocity over the model's velocity
/// reference, see [`crate::engine::PLATE_VELOCITY_REF`]): a voice past it is treated as diverged
/// (silenced, its chunk dropped, counted in [`crate::engine::Engine::diverged_voices`]). 1e5 is 100 km/s at a
/// plate pickup (400 km/s on a string): above the fastest longitudinal wave the parameter
/// table allows, `√(E_max / ρ_min) = √(5e11 / 500) ≈ 31.6 km/s`, so the strain would exceed 1
/// and no elastic model holds. Voices get there only by divergence of a conditionally stable
/// scheme or by parametric pumping (stiffness or tension automated faster than the voice
/// rings); without the ceiling their output reached inf in f32 before their f64 state
/// overflowed (found by `tests/robustness/soak.rs`).
pub const VOICE_CEILING: f64 = 1e5;

/// Everything the physical mapping reads, from the parameter snapshot and controllers.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Physics {
    pub values: ParamValues,
    /// Pitch bend in semitones.
    pub bend: f32,
    /// The pitch of every key.
    pub tuning: KeyTuning,
    /// The highest price (s per step) a new note's model may have (the CPU governor's cap,
    /// `engine/governor.rs`; infinite while the governor is off or the note fits).
    pub price_cap: f64,
    /// The host's tempo (beats per minute; `None`: none given), for the drone's cycle.
    pub tempo: Option<f64>,
}

/// Pitch ratio of `key` to the root key: `2^((p(key) - root + bend + note)/12) · a4/440`,
/// `p` the key table (`p(k) = k` in 12-TET; see the module doc of [`super`]), `bend` the
/// channel's, `note` the note's own tuning expression (semitones).
pub(crate) fn pitch_ratio(p: &Physics, key: u8, note: f32) -> f64 {
    let v = &p.values;
    let semis = p.tuning.pitch(key) - v.get(ParamId::RootKey) as f64 + p.bend as f64 + note as f64;
    (v.get(ParamId::TuningA4) as f64 / 440.0) * (semis / 12.0).exp2()
}

/// Output level of `key` from the `key_level` tracking (linear gain): `key_level` dB per
/// octave away from the root key, so 1 at the root.
pub(crate) fn key_level_gain(v: &ParamValues, key: u8) -> f64 {
    let octaves = (key as f64 - v.get(ParamId::RootKey) as f64) / 12.0;
    10f64.powf(v.get(ParamId::KeyLevel) as f64 * octaves / 20.0)
}

/// Release decay rate `σ = ln(1000) / T60` (1/s): amplitude down 60 dB in `T60`.
pub(crate) fn release_sigma(v: &ParamValues) -> f64 {
    1000f64.ln() / v.get(ParamId::ReleaseT60) as f64
}
