//! The drone voices of a bank: the tanpura drone as a scene's `[tanpura]` table
//! (`engine/model_spec.rs`), tuned by ear at its Sa (the root key) and at the anchor keys
//! [`DRONE_ANCHORS`] around it, so that every key within an octave of the root sounds its Sa
//! in tune (`models::tanpura::key_map`), built once and copied into every voice. The drone is
//! alias-free (`TanpuraSpec::alias_free`: each string steps its modes under 0.9 of the
//! Nyquist frequency).
//!
//! **Cost.** Each tuning by ear simulates every string plucked alone for two passes of a
//! second (`models::tanpura::tune`), so a new drone takes its worker about 32 s of CPU (25
//! tunings of four strings stepping 135 to 162 modes at 48 kHz), 16 s on two threads. The tuning is saved in the modal cache's
//! directory (`models::tanpura::tuning_cache`), so the same drone builds again in
//! milliseconds. Meanwhile a live host hears the drone's preview ([`drone_preview`]): the
//! same strings tuned by their tensions alone, within a few cents, played until the tuned
//! bank arrives.
//!
//! **Price.** Under the CPU governor the worker times one voice playing the root key
//! (`engine/cost_trial.rs`); the drone's mode count is the user's, never reduced (fewer
//! modes move the jivari's grid node and the tuning with it), so a drone over its share is
//! reported by the governor's counts, not thinned.
//!
//! Worker thread (allocates).

use super::cost_trial::Jobs;
pub use super::drone_tuning::{DroneTuning, DRONE_TUNING_BUDGET};
use super::model_spec::drone_spec;
use super::network_bank::{self, planned_anchors, priced_voices, prior_step_seconds};
use super::params::ParamValues;
use super::voice::{DroneVoice, Voice, VoiceModel};
use crate::error::ParamError;
use crate::modal::circular::default_cache_dir;
use crate::models::tanpura::tune::{LISTEN_TO, TUNE_PASSES};
use crate::models::tanpura::{Tanpura, TanpuraSpec};

/// The keys, in semitones from the root, at which the worker tunes the drone by ear besides
/// the root itself: every key within an octave; the retune interpolates between them
/// (`models::tanpura::key_map`). Each key is tuned: the alias-free drone steps the modes
/// under its band limit at each key, so a key a semitone higher drops a few, and the pitch
/// moves by steps between keys (anchors six semitones apart left +7 1.7 cents off,
/// `tests/engine/drone.rs`).
pub const DRONE_ANCHORS: [f64; 24] = [
    -12.0, -11.0, -10.0, -9.0, -8.0, -7.0, -6.0, -5.0, -4.0, -3.0, -2.0, -1.0, 1.0, 2.0, 3.0, 4.0,
    5.0, 6.0, 7.0, 8.0, 9.0, 10.0, 11.0, 12.0,
];

/// How `spec` is tuned within [`DRONE_TUNING_BUDGET`]: by ear at every anchor, at the root
/// only, or by the tensions (module doc). Any thread.
fn tuning_plan(spec: &TanpuraSpec) -> DroneTuning {
    let full = tuning_seconds(spec, 1 + DRONE_ANCHORS.len());
    let root = tuning_seconds(spec, 1);
    network_bank::tuning_plan(spec.tune_by_ear, full, root, DRONE_TUNING_BUDGET)
}

/// The prior CPU time (s) of tuning `spec` by ear at `keys` keys: every string plucked alone
/// for `TUNE_PASSES` passes of `LISTEN_TO` s of the whole network, at the prior price of a step.
fn tuning_seconds(spec: &TanpuraSpec, keys: usize) -> f64 {
    let sim_seconds = (TUNE_PASSES * spec.strings * keys) as f64 * LISTEN_TO;
    let grid = spec.strings * spec.modes;
    sim_seconds * spec.sim_rate * prior_step_seconds(stepped_modes(spec), grid)
}

/// The modes `spec`'s strings step at the root, all together: every mode, or for an
/// alias-free drone those under its band limit at the strings' nominal tensions (the keys
/// below the root step more, those above fewer). Any thread (allocates the strings' specs).
fn stepped_modes(spec: &TanpuraSpec) -> usize {
    let all = spec.strings * spec.modes;
    let band = spec.band_limit();
    if !band.is_finite() {
        return all;
    }
    match spec.network(&vec![1.0; spec.strings]) {
        Ok(config) => config
            .strings
            .iter()
            .map(|s| s.config.params.modes_below(band))
            .sum(),
        Err(_) => all,
    }
}

/// The drone voices of a bank for the parameters `v` run as `jobs` says, `voices_n` copies of
/// one drone, priced by a trial when `share` says the CPU governor is on. Worker thread.
pub(super) fn drone_voices(
    v: &ParamValues,
    jobs: Jobs,
    voices_n: usize,
    share: Option<f64>,
) -> Result<(Vec<Voice>, DroneTuning), ParamError> {
    let mut spec = drone_spec(v, jobs.sim);
    let tuning = tuning_plan(&spec);
    let (anchors, by_ear) = planned_anchors(tuning, &DRONE_ANCHORS);
    spec.tune_by_ear = by_ear;
    let dir = default_cache_dir();
    let (drone, _) = Tanpura::build_cached(&spec, anchors, Some(&dir))?;
    Ok((voices_of(drone, v, jobs, voices_n, share), tuning))
}

/// [`drone_voices`] tuned by the strings' tensions alone (no tuning by ear): the preview a live
/// host plays while the tuned drone builds. Worker thread; milliseconds.
pub(super) fn drone_preview(
    v: &ParamValues,
    jobs: Jobs,
    voices_n: usize,
) -> Result<Vec<Voice>, ParamError> {
    let mut spec = drone_spec(v, jobs.sim);
    spec.tune_by_ear = false;
    let drone = Tanpura::build(&spec)?;
    Ok(voices_of(drone, v, jobs, voices_n, None))
}

/// `voices_n` voices of `drone`, priced (module doc). Worker thread.
fn voices_of(
    drone: Tanpura,
    v: &ParamValues,
    jobs: Jobs,
    voices_n: usize,
    share: Option<f64>,
) -> Vec<Voice> {
    let voice = |price| {
        Voice::new(VoiceModel::Drone(Box::new(DroneVoice::new(
            drone.clone(),
            price,
        ))))
    };
    priced_voices(drone.network(), voice, v, jobs, voices_n, share)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The factory drone (alias-free, 4 strings on grids of 480 at 48 kHz) is tuned at every
    /// anchor within the budget (the estimate, 54 s, is within 10 % of the 55 s of CPU its
    /// tuning measures); at 96 kHz only its root fits; six strings of 2000 modes at 400 kHz
    /// (the quality parameters' top) are tuned by their tensions, so no build waits minutes;
    /// off stays off.
    #[test]
    fn the_tuning_fits_its_budget() {
        let factory = TanpuraSpec {
            modes: 480,
            sim_rate: 48_000.0,
            alias_free: true,
            ..TanpuraSpec::at(138.59)
        };
        let estimate = tuning_seconds(&factory, 1 + DRONE_ANCHORS.len());
        assert!((49.5..60.0).contains(&estimate), "{estimate} s");
        assert_eq!(tuning_plan(&factory), DroneTuning::ByEar);
        let fast = TanpuraSpec {
            sim_rate: 96_000.0,
            ..factory.clone()
        };
        assert_eq!(tuning_plan(&fast), DroneTuning::RootOnly);
        let top = TanpuraSpec {
            strings: 6,
            modes: 2000,
            sim_rate: 400_000.0,
            ..factory.clone()
        };
        assert_eq!(tuning_plan(&top), DroneTuning::Tensions { asked: true });
        let off = TanpuraSpec {
            tune_by_ear: false,
            ..factory
        };
        assert_eq!(tuning_plan(&off), DroneTuning::Tensions { asked: false });
    }
}
