//! A note's excitation, committed at the voice's first step after its note-on: a force pulse
//! or a mallet on a plate, a pluck on a string, shaped by the note's brightness and its own
//! values of the per-note parameters ([`super::modulation`]). Deferring it to the first step
//! lets expressions and modulations sent with the note-on (the same sample) shape the note's
//! own strike, as a host sends them right after the note-on that names the note.
//!
//! Threads: the audio thread or a voice job's worker; no allocation.

use super::modulation::{bright_factor, bright_hardness, bright_pluck};
use super::plate::PlateVoice;
use super::string::StringVoice;
use crate::engine::params::{ParamId, ParamValues};
use crate::models::plate::RaisedCosine;
use crate::models::string::TrianglePluck;

/// The excitation of the last note-on, waiting for the voice's next step.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PendingStrike {
    /// Velocity after the curve, times the mod wheel's factor (0 strikes nothing).
    pub amount: f64,
    /// A fresh note (strings: the pluck resets the string; a re-pluck adds to its motion).
    pub fresh: bool,
    /// The parameter values at the note-on (global values; the note's own are applied at
    /// the commit).
    pub values: ParamValues,
}

/// Commits `s` on plate voice `pv` with the note's values `v` (its own values applied) and
/// brightness `bright`. Returns `false` if the excitation was refused.
pub(super) fn commit_plate(
    pv: &mut PlateVoice,
    s: &PendingStrike,
    v: ParamValues,
    bright: f32,
) -> bool {
    let mut v = v;
    let amount = s.amount;
    if v.index_of(ParamId::Exciter) == 1 {
        // The mallet: velocity sets the impact speed (level and timbre). A zero speed
        // (velocity or wheel at 0) strikes nothing, as a zero force would.
        let hardness = bright_hardness(v.get(ParamId::MalletHardness) as f64, bright);
        v.0[ParamId::MalletHardness.index()] = hardness as f32;
        pv.place_strike(v.get(ParamId::StrikeRadius) as f64);
        let speed = v.get(ParamId::MalletSpeed) as f64 * amount;
        return speed <= 0.0 || pv.launch_mallet(&v, speed).is_ok();
    }
    pv.mallet.drop_mallet();
    pv.place_strike(v.get(ParamId::StrikeRadius) as f64);
    let peak = v.get(ParamId::StrikeForce) as f64 * amount;
    let info = ParamId::StrikeDuration.info();
    let duration = (v.get(ParamId::StrikeDuration) as f64 * bright_factor(bright))
        .clamp(info.min as f64, info.max as f64);
    match RaisedCosine::new(duration, peak) {
        Ok(pulse) => {
            pv.strike = Some(pulse);
            pv.strike_step = 0;
            true
        }
        Err(_) => false,
    }
}

/// Commits `s` on string voice `sv` (as [`commit_plate`]).
pub(super) fn commit_string(
    sv: &mut StringVoice,
    s: &PendingStrike,
    v: ParamValues,
    bright: f32,
) -> bool {
    let l = sv.model.params().length;
    let at = bright_pluck(v.get(ParamId::PluckPosition) as f64, bright);
    let pluck = TrianglePluck {
        position: at * l,
        amplitude: v.get(ParamId::PluckAmplitude) as f64 * s.amount,
    };
    if s.fresh {
        // `pluck` resets the string: count the contact statistics first.
        sv.cap_hits_seen = 0;
        sv.model.pluck(&pluck).is_ok()
    } else {
        // A sounding string is plucked again on its motion (no reset, no click).
        sv.model.add_pluck(&pluck).is_ok()
    }
}
