//! The sitar voices of a bank: the sitar with its taraf as a scene's `[sitar]` table
//! (`engine/model_spec.rs`), every string tuned by ear at Sa (the root key) and the played
//! string at the anchor keys [`SITAR_ANCHORS`] around it, so that every key within an
//! octave of the root sounds its fret in tune, built once and copied into every voice.
//!
//! **Cost.** Each tuning by ear simulates the whole network for two passes of a second
//! (`models::tanpura::tune`): every string at its open note and the played string at each
//! anchor, 76 s of simulation at 192 kHz for the factory sitar (about as many seconds of
//! CPU), shared among the tuning threads. The tuning is saved in the modal cache's directory (as the drone's,
//! `models::tanpura::tuning_cache`), so the same sitar builds again in milliseconds.
//! Meanwhile a live host hears the preview ([`sitar_preview`]): the same strings tuned by
//! their tensions alone, within a few cents.
//!
//! **Price.** Under the CPU governor the worker times one voice playing the root key
//! (`engine/cost_trial.rs`), as for the drone; the mode counts are never reduced.
//!
//! Worker thread (allocates).

use super::cost_trial::Jobs;
use super::drone_tuning::{DroneTuning, SITAR_TUNING_BUDGET};
use super::model_spec::sitar_spec;
use super::network_bank::{self, planned_anchors, priced_voices, prior_step_seconds};
use super::params::ParamValues;
use super::voice::{SitarVoice, Voice, VoiceModel};
use crate::error::ParamError;
use crate::modal::circular::default_cache_dir;
use crate::models::sitar::{Sitar, SitarSpec};
use crate::models::tanpura::tune::{LISTEN_TO, TUNE_PASSES};

/// The keys, in semitones from the root, at which the worker tunes the played string by ear
/// besides its open note: every key within an octave. A note between them (a bend, another
/// tuning) takes the interpolated correction, and every key beyond the octave the correction
/// of the octave's end. Each key is tuned: the bridges' modes bend the played string's pitch
/// by up to 11 cents between keys tuned four or two semitones apart (near the main bridge's
/// 190 Hz and 480 Hz modes: `tests/engine/sitar.rs`).
pub const SITAR_ANCHORS: [f64; 24] = [
    -12.0, -11.0, -10.0, -9.0, -8.0, -7.0, -6.0, -5.0, -4.0, -3.0, -2.0, -1.0, 1.0, 2.0, 3.0, 4.0,
    5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0,
];

/// The string modes of `spec`: every string's.
fn string_modes(spec: &SitarSpec) -> usize {
    (0..spec.strings()).map(|i| spec.geometry(i).2).sum()
}

/// The prior CPU time (s) of tuning `spec` by ear with `frets` anchor keys: the network
/// simulated for `TUNE_PASSES` passes of `LISTEN_TO` s per string and per fret.
fn tuning_seconds(spec: &SitarSpec, frets: usize) -> f64 {
    let sim_seconds = (TUNE_PASSES * (spec.strings() + frets)) as f64 * LISTEN_TO;
    let modes = string_modes(spec);
    sim_seconds * spec.sim_rate * prior_step_seconds(modes, modes)
}

/// How `spec` is tuned within [`SITAR_TUNING_BUDGET`]: by ear at every anchor, at the open
/// notes only, or by the tensions. Any thread.
fn tuning_plan(spec: &SitarSpec) -> DroneTuning {
    let full = tuning_seconds(spec, SITAR_ANCHORS.len());
    let open = tuning_seconds(spec, 0);
    network_bank::tuning_plan(spec.tune_by_ear, full, open, SITAR_TUNING_BUDGET)
}

/// The sitar voices of a bank for the parameters `v` run as `jobs` says, `voices_n` copies
/// of one sitar, priced by a trial when `share` says the CPU governor is on. Worker thread.
pub(super) fn sitar_voices(
    v: &ParamValues,
    jobs: Jobs,
    voices_n: usize,
    share: Option<f64>,
) -> Result<(Vec<Voice>, DroneTuning), ParamError> {
    let mut spec = sitar_spec(v, jobs.sim);
    let tuning = tuning_plan(&spec);
    let (anchors, by_ear) = planned_anchors(tuning, &SITAR_ANCHORS);
    spec.tune_by_ear = by_ear;
    let dir = default_cache_dir();
    let (sitar, _) = Sitar::build_cached(&spec, anchors, Some(&dir))?;
    Ok((voices_of(sitar, v, jobs, voices_n, share), tuning))
}

/// [`sitar_voices`] tuned by the strings' tensions alone: the preview a live host plays
/// while the tuned sitar builds. Worker thread; milliseconds.
pub(super) fn sitar_preview(
    v: &ParamValues,
    jobs: Jobs,
    voices_n: usize,
) -> Result<Vec<Voice>, ParamError> {
    let mut spec = sitar_spec(v, jobs.sim);
    spec.tune_by_ear = false;
    let (sitar, _) = Sitar::build_cached(&spec, &[], None)?;
    Ok(voices_of(sitar, v, jobs, voices_n, None))
}

/// `voices_n` voices of `sitar`, priced (module doc). Worker thread.
fn voices_of(
    sitar: Sitar,
    v: &ParamValues,
    jobs: Jobs,
    voices_n: usize,
    share: Option<f64>,
) -> Vec<Voice> {
    let voice = |price| {
        Voice::new(VoiceModel::Sitar(Box::new(SitarVoice::new(
            sitar.clone(),
            price,
        ))))
    };
    priced_voices(sitar.network(), voice, v, jobs, voices_n, share)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The factory sitar (a 300-mode played string, 11 taraf of 48 modes and two chikari at
    /// 192 kHz) is tuned at every anchor within the budget (the estimate within 20 % of the
    /// 76 s of CPU its tuning measures); at 400 kHz with 4000 modes only by its tensions, so
    /// no build waits minutes; off stays off.
    #[test]
    fn the_tuning_fits_its_budget() {
        let factory = SitarSpec {
            chikari: 2,
            ..SitarSpec::at(277.18, 277.18)
        };
        let estimate = tuning_seconds(&factory, SITAR_ANCHORS.len());
        assert!((61.0..92.0).contains(&estimate), "{estimate} s");
        assert_eq!(tuning_plan(&factory), DroneTuning::ByEar);
        let top = SitarSpec {
            modes: 4000,
            sim_rate: 400_000.0,
            ..factory.clone()
        };
        assert_eq!(tuning_plan(&top), DroneTuning::Tensions { asked: true });
        let off = SitarSpec {
            tune_by_ear: false,
            ..factory
        };
        assert_eq!(tuning_plan(&off), DroneTuning::Tensions { asked: false });
    }
}
