//! What the drone's and the sitar's banks share (`engine/drone_bank.rs`,
//! `engine/sitar_bank.rs`): the prior price of a string-network step, the choice of how far a
//! network is tuned by ear within its worker's budget, and the priced copies of one built
//! instrument that become the bank's voices.
//!
//! Worker thread (allocates).

use super::cost_trial::{time_note, Jobs};
use super::drone_tuning::DroneTuning;
use super::governor::PRIOR_SECONDS_PER_UNIT;
use super::params::ParamValues;
use super::voice::Voice;
use crate::models::network::StringNetwork;

/// Prior work units of one network step per string mode: the bridge solve evaluates every
/// jawari string's contact about three times a step (two Newton iterations and the commit)
/// on top of the modal passes (docs/performance.md, "The tanpura drone": 0.41 of a core for
/// 4 × 480 modes at 48 kHz, 8.5 µs a step, 2.2 units of [`PRIOR_SECONDS_PER_UNIT`] per
/// string mode).
pub(super) const UNITS_PER_STRING_MODE: f64 = 2.5;

/// The prior CPU time (s) of one step of a network whose strings step `stepped` modes in all
/// on grids of `grid` nodes in all (`grid = stepped` unless band-limited): a stepped mode
/// costs [`UNITS_PER_STRING_MODE`], and a grid node beyond them 0.4 of that (the stored
/// rows' fold and the modal correction run over the whole grid; calibrated on the
/// alias-free factory drone, whose tuning by ear at 25 keys, 9.6e6 steps of 590 stepped
/// modes on grids of 1920, took 55 s of CPU on 2026-11-29: 5.7 µs a step against this
/// estimate's 5.6 µs).
pub(super) fn prior_step_seconds(stepped: usize, grid: usize) -> f64 {
    let beyond = grid.saturating_sub(stepped) as f64;
    PRIOR_SECONDS_PER_UNIT * UNITS_PER_STRING_MODE * (stepped as f64 + 0.4 * beyond)
}

/// How a network is tuned within `budget` s of CPU: by ear at every anchor when its full
/// tuning (`full` s, estimated) fits, at its open notes only when those (`open` s) fit, by
/// its tensions otherwise or when tuning by ear was not `asked` for. Any thread.
pub(super) fn tuning_plan(asked: bool, full: f64, open: f64, budget: f64) -> DroneTuning {
    if !asked {
        DroneTuning::Tensions { asked }
    } else if full <= budget {
        DroneTuning::ByEar
    } else if open <= budget {
        DroneTuning::RootOnly
    } else {
        DroneTuning::Tensions { asked }
    }
}

/// The keys a `tuning` plan tunes by ear besides the open notes (all of `anchors`, or none at
/// the root only or by the tensions), and whether it tunes by ear at all.
pub(super) fn planned_anchors(
    tuning: DroneTuning,
    anchors: &'static [f64],
) -> (&'static [f64], bool) {
    match tuning {
        DroneTuning::ByEar => (anchors, true),
        DroneTuning::RootOnly => (&[], true),
        DroneTuning::Tensions { .. } => (&[], false),
    }
}

/// `voices_n` voices made by `voice` (given its price, s of CPU a step) of the instrument
/// whose network is `network`: at the prior price of its stepped modes, or when `share` says the CPU governor is
/// on at the price a trial of one voice playing the root key measures
/// (`engine/cost_trial.rs`). Worker thread.
pub(super) fn priced_voices(
    network: &StringNetwork,
    voice: impl Fn(f64) -> Voice,
    v: &ParamValues,
    jobs: Jobs,
    voices_n: usize,
    share: Option<f64>,
) -> Vec<Voice> {
    let stepped: usize = network.strings().iter().map(|s| s.stepped_modes()).sum();
    let grid: usize = network.strings().iter().map(|s| s.params().modes()).sum();
    let prior = prior_step_seconds(stepped, grid);
    let mut price = prior;
    if share.is_some() {
        let mut trial = voice(prior);
        if let Some(load) = time_note(&mut trial, v, jobs) {
            price = load.price;
        }
    }
    (0..voices_n).map(|_| voice(price)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plan's four outcomes at the edges of the budget (a cost exactly at the budget
    /// fits).
    #[test]
    fn the_plan_follows_the_budget() {
        assert_eq!(tuning_plan(true, 10.0, 2.0, 10.0), DroneTuning::ByEar);
        assert_eq!(tuning_plan(true, 10.5, 10.0, 10.0), DroneTuning::RootOnly);
        assert_eq!(
            tuning_plan(true, 30.0, 10.5, 10.0),
            DroneTuning::Tensions { asked: true }
        );
        assert_eq!(
            tuning_plan(false, 1.0, 1.0, 10.0),
            DroneTuning::Tensions { asked: false }
        );
    }
}
