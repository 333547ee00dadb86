//! The string voices of a bank: the instrument's string as a scene's `[string]` specification
//! (one vocabulary, one table of ranges), and, under the CPU governor, the mode count that
//! keeps one voice within its share of real time.
//!
//! **Fitting a string to the budget.** A plate's note can start on a narrower tier of its
//! bank; a string voice is one model, so its cost is fitted when the bank is built. The worker
//! times a trial voice (`engine/cost_trial.rs`: the root key plucked at full strength, the
//! attack's contact included, in windows of about a host block, in thread CPU time). Its load
//! (seconds of work per second of audio) must stay within the voice's share, on average and
//! within [`WORST_WINDOW`] times it in the worst window. A trial over it is timed up to
//! [`RETIMES`] times more and the lowest figures kept, so disturbed windows do not thin the
//! string. If it is still over, the mode count comes down in proportion (the step is
//! `O(N log N)` or `O(N · rows)`, nearly linear in `N`) with a margin and the trial runs again,
//! at most [`FIT_ATTEMPTS`] trials. The reduction is reported with
//! the bank ([`ModesFitted`]), and the last trial's price per step goes with every voice (the
//! governor's note-on check, `engine/governor.rs`). Off the governor (offline renders) the
//! string keeps every mode it asks for.
//!
//! Worker thread (allocates; a trial takes at most `TRIAL_CPU_LIMIT · TRIAL_SECONDS` of CPU
//! time, 0.24 s: a string within its share takes one trial, a fit at most
//! `FIT_ATTEMPTS · (1 + RETIMES)`, a few seconds, while the last bank plays).

use super::cost_trial::{time_note, Jobs, TrialLoad};
use super::kinds::ModelKind;
use super::memory::{FitReason, ModesFitted};
use super::model_spec::string_spec;
use super::params::{ParamId, ParamValues};
use super::voice::{StringVoice, Voice, VoiceModel};
use crate::error::ParamError;
use crate::models::string::{StiffString, StringConfig, ValetteLosses};

/// The worst window may cost this many times the voice's share (the governor's target: no
/// block above twice real time).
pub(crate) const WORST_WINDOW: f64 = 2.0;

/// Further timings of a mode count whose trial is over the share, before it is reduced.
pub(crate) const RETIMES: usize = 3;

/// Trials at most (each after a reduction).
pub(crate) const FIT_ATTEMPTS: usize = 5;

/// Share of the proportional reduction kept as margin (the cost is not exactly linear in
/// the mode count).
const FIT_MARGIN: f64 = 0.85;

/// Fewest modes a fitted string keeps.
pub(crate) const MIN_FITTED_MODES: usize = 16;

/// The string voices of a bank of `kind` for the parameters `v` at `jobs.sim` (Hz), and the
/// fitted mode count if `share` (the largest load of one voice, seconds per second) made the
/// worker reduce it. Worker thread.
pub(super) fn string_voices(
    kind: ModelKind,
    v: &ParamValues,
    jobs: Jobs,
    voices_n: usize,
    share: Option<f64>,
) -> Result<(Vec<Voice>, Option<ModesFitted>), ParamError> {
    let sim_rate = jobs.sim;
    let wanted = v.index_of(ParamId::Modes).max(1);
    let mut modes = wanted;
    let mut config = string_config(kind, v, modes, sim_rate)?;
    // The measured price of a step of the string as built (`None`: not measured).
    let mut price = None;
    if let Some(share) = share {
        for attempt in 1..=FIT_ATTEMPTS {
            let mut trial = string_voice(&config)?;
            let Some(mut load) = time_note(&mut trial, v, jobs) else {
                break;
            };
            let over = |l: &TrialLoad| l.mean > share || l.worst > WORST_WINDOW * share;
            // A trial is thread CPU time on a shared machine: a disturbed window (a burst of
            // page faults on a fresh model's pages, a hypervisor or a host taking the core)
            // makes a cheap string look too costly. Before reducing, time it again, up to
            // `RETIMES` times, keeping the lower of each figure: interference only adds time,
            // so the minimum is the string's own cost, and a string that is too costly is too
            // costly every time.
            for _ in 0..RETIMES {
                if !over(&load) {
                    break;
                }
                let Some(again) = time_note(&mut trial, v, jobs) else {
                    break;
                };
                load = TrialLoad {
                    mean: load.mean.min(again.mean),
                    worst: load.worst.min(again.worst),
                    price: load.price.min(again.price),
                };
            }
            price = Some(load.price);
            let scale = (share / load.mean).min(WORST_WINDOW * share / load.worst);
            if scale >= 1.0 || modes <= MIN_FITTED_MODES || attempt == FIT_ATTEMPTS {
                break;
            }
            modes = ((modes as f64 * scale * FIT_MARGIN) as usize).max(MIN_FITTED_MODES);
            config = string_config(kind, v, modes, sim_rate)?;
        }
    }
    let mut voices = Vec::with_capacity(voices_n);
    for _ in 0..voices_n {
        let mut voice = string_voice(&config)?;
        if let (Some(price), VoiceModel::String(sv)) = (price, &mut voice.model) {
            sv.price = price;
        }
        voices.push(voice);
    }
    let fitted = (modes < wanted).then_some(ModesFitted {
        wanted: wanted as u32,
        built: modes as u32,
        reason: FitReason::Cpu,
    });
    Ok((voices, fitted))
}

/// A silent string voice of `config`. Worker thread.
fn string_voice(config: &StringConfig) -> Result<Voice, ParamError> {
    let model = StiffString::new(config)?;
    Ok(Voice::new(VoiceModel::String(Box::new(StringVoice::new(
        model,
        ValetteLosses::default(),
    )))))
}

/// The instrument's string for `v` with `modes` modes at `sim_rate`, validated.
fn string_config(
    kind: ModelKind,
    v: &ParamValues,
    modes: usize,
    sim_rate: f64,
) -> Result<StringConfig, ParamError> {
    let spec = string_spec(kind, v, modes, sim_rate);
    spec.validate()?;
    Ok(spec.config())
}
