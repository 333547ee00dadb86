//! The CPU governor's prices, measured (`engine/governor.rs`): before a bank goes to a live
//! host, the worker times one of its voices playing a note, so the first notes a player
//! strikes are priced by this machine's own clock rather than by a guess.
//!
//! **A trial** starts the voice on the root key at full strength (velocity 1 and the mod
//! wheel's full depth: the hardest strike or pluck a note can make), and runs it as the voice
//! pool runs it: one job ([`Voice::run`], then [`Voice::run_above`]) per chunk of host
//! samples ([`Jobs`]), the chunk's simulation and above-band samples, for
//! [`TRIAL_SECONDS`] of audio, in thread CPU time (the load of other threads does not
//! count). The jobs must be the engine's own: a job has costs of its own besides its steps,
//! and a trial of longer jobs priced a rectangle's step at half of what the engine's jobs
//! then took (docs/robustness.md). The worst load is taken over windows of
//! [`WINDOW_SECONDS`] (about a host block). The attack is where a strike's mallet or a string's
//! bridge contact is densest, so the trial errs on the costly side. A trial far beyond real
//! time stops once it has spent [`TRIAL_CPU_LIMIT`] times its audio's duration: its price is
//! known well enough by then.
//!
//! **Plates** are timed tier by tier, smallest first (the voice's
//! [`super::voice::PlateVoice::trial_tier`]), until a tier costs more than twice the most a
//! voice may cost: no note takes the larger tiers, whose prices are extrapolated from the
//! last measured one in proportion to their prior prices (their work). **Strings** are one
//! model: `engine/string_bank.rs` times it and fits its mode count to the share.
//!
//! Worker thread (allocates the trial's buffers). A plate of 2000 modes, where a tier
//! beyond the share takes at most `TRIAL_CPU_LIMIT · TRIAL_SECONDS`, costs a few tenths of a
//! second of trials on a bank build of seconds.

use super::params::{ParamId, ParamValues};
use super::tuning::KeyTuning;
use super::voice::{Physics, Voice, VoiceModel};
use crate::clock::thread_cpu_time;

/// Audio timed by one trial (s): the attack, where the contact is densest.
pub(crate) const TRIAL_SECONDS: f64 = 0.06;

/// Audio per timed window (s): about a host block of 256 samples at 48 kHz.
pub(crate) const WINDOW_SECONDS: f64 = 0.005;

/// A trial stops once its CPU time passes this many times its audio's duration.
pub(crate) const TRIAL_CPU_LIMIT: f64 = 4.0;

/// A plate tier whose trial costs more than this many times a voice's share ends the
/// tier-by-tier trial (no note takes it, nor any larger tier).
const BEYOND_SHARE: f64 = 2.0;

/// A trial's result.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TrialLoad {
    /// Load over the whole trial: seconds of work per second of audio.
    pub mean: f64,
    /// Load in the costliest window.
    pub worst: f64,
    /// Seconds per simulation step (the governor's price).
    pub price: f64,
}

/// How the engine runs a bank's voice jobs (`engine/mix.rs`): the rates, the chunk and the
/// pickups' gain. Worker thread.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Jobs {
    /// Host rate (Hz).
    pub host: f64,
    /// Simulation rate (Hz).
    pub sim: f64,
    /// Rate of the band above the simulation (Hz; 0 for strings).
    pub above: f64,
    /// Host samples per job (the engine's chunk, `bank::CHUNK`).
    pub chunk: usize,
    /// The bank's output scale (1 / its velocity reference).
    pub gain: f64,
}

/// Times `voice` (of a bank for `v`, run as `jobs` says) playing one note at full strength;
/// the voice is left silent. `None` where the thread clock is missing or the note is
/// refused (then nothing is priced by measurement). Worker thread.
pub(crate) fn time_note(voice: &mut Voice, v: &ParamValues, jobs: Jobs) -> Option<TrialLoad> {
    let p = Physics {
        values: *v,
        bend: 0.0,
        tuning: KeyTuning::default(),
        price_cap: f64::INFINITY,
        tempo: None,
    };
    let key = v.get(ParamId::RootKey).round().clamp(0.0, 127.0) as u8;
    let start = |voice: &mut Voice| voice.start(&p, key, 1.0, 1.0, 0);
    if !start(voice) {
        voice.reset();
        return None;
    }
    // A chunk's samples as the engine's mix asks for them (`engine/mix.rs`), the fraction
    // carried from chunk to chunk.
    let per_chunk = |rate: f64| jobs.chunk as f64 * rate / jobs.host;
    let longest = |rate: f64| per_chunk(rate).ceil() as usize + 1;
    let (mut l, mut r) = (
        vec![0.0f32; longest(jobs.sim)],
        vec![0.0f32; longest(jobs.sim)],
    );
    let (mut al, mut ar) = (
        vec![0.0f32; longest(jobs.above)],
        vec![0.0f32; longest(jobs.above)],
    );
    let chunk_seconds = jobs.chunk as f64 / jobs.host;
    let chunks = ((TRIAL_SECONDS / chunk_seconds).ceil() as usize).max(1);
    let per_window = ((WINDOW_SECONDS / chunk_seconds).round() as usize).max(1);
    let (mut sim_at, mut above_at) = (0.0f64, 0.0f64);
    let (mut total, mut window, mut worst) = (0.0f64, 0.0f64, 0.0f64);
    let (mut steps, mut ran) = (0usize, 0usize);
    for c in 0..chunks {
        let m = ((sim_at + per_chunk(jobs.sim)).floor() - sim_at.floor()) as usize;
        let n = ((above_at + per_chunk(jobs.above)).floor() - above_at.floor()) as usize;
        sim_at += per_chunk(jobs.sim);
        above_at += per_chunk(jobs.above);
        let t0 = thread_cpu_time()?;
        let ok = voice.run(&mut l[..m], &mut r[..m], jobs.gain)
            && voice.run_above(&mut al[..n], &mut ar[..n], jobs.gain);
        let spent = thread_cpu_time()?.saturating_sub(t0).as_secs_f64();
        total += spent;
        window += spent;
        steps += m;
        ran += 1;
        if (c + 1) % per_window == 0 {
            worst = worst.max(window);
            window = 0.0;
        }
        // A note the model refuses mid-way (a diverging trial) starts again: the price is
        // that of running, not of a silent voice.
        if !ok {
            voice.reset();
            if !start(voice) {
                break;
            }
        }
        if total > TRIAL_CPU_LIMIT * TRIAL_SECONDS {
            break;
        }
    }
    // A trial stopped within its first window: that part is its worst.
    let (worst, worst_chunks) = if ran < per_window {
        (total, ran.max(1))
    } else {
        (worst, per_window)
    };
    voice.reset();
    Some(TrialLoad {
        mean: total / (ran as f64 * chunk_seconds),
        worst: worst / (worst_chunks as f64 * chunk_seconds),
        price: total / steps.max(1) as f64,
    })
}

/// Prices every tier of the plate `voice` (of a bank for `v`, run as `jobs` says) by trials,
/// smallest first, up to the first tier beyond [`BEYOND_SHARE`] times `share` (seconds of work
/// per second of audio); larger tiers are extrapolated in proportion to their prior prices.
/// `None` for a string voice or where nothing could be timed. Worker thread.
pub(crate) fn plate_prices(
    voice: &mut Voice,
    v: &ParamValues,
    jobs: Jobs,
    share: f64,
) -> Option<Vec<f64>> {
    let VoiceModel::Plate(pv) = &voice.model else {
        return None;
    };
    let prior = pv.data.tier_price.clone();
    let mut prices = prior.clone();
    // The largest tier measured so far.
    let mut last = None;
    for t in (0..prior.len()).rev() {
        set_trial_tier(voice, Some(t));
        let load = time_note(voice, v, jobs);
        set_trial_tier(voice, None);
        let Some(load) = load else { break };
        prices[t] = load.price;
        last = Some(t);
        if load.mean > BEYOND_SHARE * share {
            break;
        }
    }
    let last = last?;
    for u in 0..last {
        prices[u] = prices[last] * prior[u] / prior[last];
    }
    Some(prices)
}

/// Sets a plate voice's trial tier (no-op for strings).
fn set_trial_tier(voice: &mut Voice, tier: Option<usize>) {
    if let VoiceModel::Plate(pv) = &mut voice.model {
        pv.trial_tier = tier;
    }
}
