//! The real-time soak (issue 7, "Real-time safety under load"): one seeded random driver
//! plays the engine as a hostile host would, for a bounded wall time, and checks it.
//!
//! Every block: every parameter that applies without a rebuild is set to a random value over
//! its whole range (its minimum and maximum exactly, one draw in five); a note storm (note-ons
//! and note-offs at [`SoakConfig::notes_per_second`] on all 128 keys, velocities 0 to 1, pitch
//! bend, mod wheel, sustain, now and then all-notes-off / all-sound-off); a block length from
//! 1 to the activation's maximum (up to 8192). Between blocks, by turns: bursts of changes to
//! the rebuild parameters (model, modes, in-plane modes, simulation rate, scheme, polyphony,
//! positions, material, contact law) that make the worker rebuild and hand over a bank, and
//! host sample-rate changes between 22.05 and 192 kHz (deactivate, activate, as a host does).
//!
//! Checks (each a [`SoakFailure`]): every output sample finite and within
//! [`LEVEL_BOUND`] times the largest output gain set since the start (a bound that holds
//! because the engine silences any voice past [`VOICE_CEILING`]); every requested rebuild
//! arrives (the engine's bank takes the requested signature) or is refused by the worker with
//! an error message, within [`SoakConfig::rebuild_timeout`]; activations succeed. The caller's
//! `process` closure wraps [`Engine::process_events`] (the test and the example put
//! `assert_no_alloc` around it, so an allocation inside `process` aborts the run). The block
//! time over the block's real-time duration is recorded, not checked (shared machines).
//!
//! Threads: [`run`] drives the engine from the calling thread (standing in for both the
//! host's main thread and its audio thread); the engine's worker thread builds banks.

mod draw;
mod quality;
mod summary;

pub use draw::{Draw, Storm, StormCounts, EXTREME_CHANCE};
pub use quality::{needs_rebuild, Signature};
pub use summary::{SoakFailure, SoakSummary, WorstBlock};

use noether_core::engine::{
    Engine, Event, ParamId, SharedParams, MAX_VOICES, PARAMS, VOICE_CEILING,
};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Output bound before the output gain, in the engine's normalised units (plates: pickup
/// velocity / 1 m/s; strings: / 4 m/s), derived from the engine's structure: each voice's
/// output stays within [`VOICE_CEILING`] (past it the engine silences the voice and drops its
/// chunk), at most [`MAX_VOICES`] voices sound in a bank, two banks sound during a handover
/// (the old one faded by a factor ≤ 1), and the resampler's kernel has an ℓ1 norm below 2
/// (1.91 at the 0.9 cutoff, 1.78 at the lowest rate ratios: computed from its definition in
/// `engine::resample`). So `|out| ≤ 2 · 2 · 16 · VOICE_CEILING · g` with `g` the largest
/// output gain set since the start (the smoothed gain is a running average of the targets).
/// The soak prints the largest level it saw, so the margin is visible.
pub const LEVEL_BOUND: f64 = 2.0 * 2.0 * MAX_VOICES as f64 * VOICE_CEILING;

/// Host rates a re-activation picks from (Hz); one draw in five is uniform in
/// 22 050..192 000 instead.
pub const HOST_RATES: [f64; 7] = [
    22_050.0, 44_100.0, 48_000.0, 88_200.0, 96_000.0, 176_400.0, 192_000.0,
];

/// Maximum block sizes a re-activation picks from (the host's promise; blocks are drawn in
/// `1..=max`).
pub const MAX_BLOCKS: [usize; 5] = [64, 512, 1024, 4096, 8192];

/// How the soak runs. Plain data, any thread.
#[derive(Debug, Clone)]
pub struct SoakConfig {
    /// Seed of every random choice.
    pub seed: u64,
    /// Wall time after which no new burst or re-activation starts (a pending rebuild is
    /// still waited for).
    pub duration: Duration,
    /// Longest wall time a requested rebuild may take to arrive or be refused.
    pub rebuild_timeout: Duration,
    /// Mean note-ons per second of host time (as many note-offs).
    pub notes_per_second: f64,
    /// Largest `modes` a burst sets (the table allows 400).
    pub max_modes: usize,
    /// Largest `in_plane_modes` a burst sets (the table allows 200).
    pub max_in_plane: usize,
    /// Largest polyphony a burst sets (the table allows 16).
    pub max_polyphony: usize,
    /// Highest simulation rate a burst sets (Hz; the table allows 400 kHz).
    pub max_sim_rate: f64,
    /// Load budget: bursts keep `modes · polyphony · sim_rate` (mode-steps per second of
    /// audio) at most this, lowering polyphony first, then modes.
    pub budget: f64,
}

impl SoakConfig {
    /// The bounded soak of `cargo test` (`tests/robustness/soak.rs`): `duration` of wall time,
    /// up to 40 modes, 10 in-plane modes, 8 voices, simulation rates up to 400 kHz, budget 40
    /// modes × 4 voices × 48 kHz.
    pub fn quick(seed: u64, duration: Duration) -> Self {
        Self {
            seed,
            duration,
            rebuild_timeout: Duration::from_secs(30),
            notes_per_second: 300.0,
            max_modes: 40,
            max_in_plane: 10,
            max_polyphony: 8,
            max_sim_rate: 400_000.0,
            budget: 40.0 * 4.0 * 48_000.0,
        }
    }
}

/// Where the driver is between blocks.
enum Phase {
    /// Plain blocks; then a burst or a re-activation.
    Idle { blocks: u32 },
    /// Intermediate burst steps left.
    Burst { steps: u32 },
    /// A rebuild was requested at `since`; `quiet` is when the worker was last seen idle
    /// with an error set (a refusal once that has lasted [`REFUSAL_QUIET`]).
    Waiting {
        want: Signature,
        since: Instant,
        quiet: Option<Instant>,
    },
}

/// How long the worker must stay idle with an error set, after a request, before the soak
/// counts the request refused (the worker starts a build 30 ms after the last change; 1 s
/// leaves room for a worker thread starved on a loaded machine).
const REFUSAL_QUIET: Duration = Duration::from_secs(1);

fn signature(e: &Engine) -> Option<Signature> {
    Some(Signature {
        model: e.model()?,
        sim_rate: e.sim_rate()?,
        polyphony: e.polyphony(),
    })
}

/// Runs the soak; `process` must call `engine.process_events(events, left, right)` (wrapped
/// as the caller likes). Returns the summary, or the first failed check with the summary so
/// far. Allocates (engine, banks, buffers) outside `process` only.
pub fn run<F>(cfg: &SoakConfig, mut process: F) -> Result<SoakSummary, Box<SoakFailure>>
where
    F: FnMut(&mut Engine, &[Event], &mut [f32], &mut [f32]),
{
    let start = Instant::now();
    let mut d = Draw::new(cfg.seed);
    let params = Arc::new(SharedParams::new());
    // Start cheap: the default gong at 16 modes, 4 in-plane modes, 16 kHz, 2 voices.
    for (id, x) in [
        (ParamId::Modes, 16.0),
        (ParamId::InPlaneModes, 4.0),
        (ParamId::SimRate, 16_000.0),
        (ParamId::Polyphony, 2.0),
    ] {
        params
            .set(id, x)
            .map_err(|e| fail(&SoakSummary::new(cfg), e))?;
    }
    let (mut e, handle) = Engine::new(params.clone());
    let mut s = SoakSummary::new(cfg);
    let mut storm = Storm::new(cfg.notes_per_second);
    let (mut l, mut r) = (vec![0.0f32; 8192], vec![0.0f32; 8192]);
    let mut events: Vec<Event> = Vec::with_capacity(4096);
    let mut rate = d.pick(&HOST_RATES);
    let mut max_block = d.pick(&MAX_BLOCKS);
    e.activate(rate, max_block)
        .map_err(|err| fail(&s, format!("activation at {rate} Hz: {err}")))?;
    s.note_rate(rate);
    let mut gain_hi = 1.0f64;
    let mut bank = e.bank_id();
    let mut phase = Phase::Idle { blocks: 20 };
    let mut buildable = true;
    loop {
        let late = start.elapsed() >= cfg.duration;
        phase = match phase {
            Phase::Idle { blocks: 0 } if late => break,
            Phase::Idle { blocks: 0 } => {
                // Re-activation rebuilds from the current parameters: only when they built.
                if buildable && d.chance(0.3) {
                    // A host sample-rate change: deactivate, activate at the new rate.
                    rate = if d.chance(0.2) {
                        d.between(22_050.0, 192_000.0).round()
                    } else {
                        d.pick(&HOST_RATES)
                    };
                    max_block = d.pick(&MAX_BLOCKS);
                    e.deactivate();
                    let t = Instant::now();
                    e.activate(rate, max_block)
                        .map_err(|err| fail(&s, format!("activation at {rate} Hz: {err}")))?;
                    s.activation_wall = s.activation_wall.max(t.elapsed());
                    s.rate_changes += 1;
                    s.note_rate(rate);
                    bank = e.bank_id();
                    Phase::Idle {
                        blocks: 10 + d.below(200) as u32,
                    }
                } else {
                    Phase::Burst {
                        steps: d.below(6) as u32,
                    }
                }
            }
            Phase::Burst { steps: 0 } => {
                let want = quality::finish(&mut d, &params, cfg, signature(&e))
                    .map_err(|err| fail(&s, err))?;
                s.param_writes += 7;
                s.rebuilds_requested += 1;
                Phase::Waiting {
                    want,
                    since: Instant::now(),
                    quiet: None,
                }
            }
            Phase::Burst { steps } => {
                let writes = quality::step(&mut d, &params).map_err(|err| fail(&s, err))?;
                s.param_writes += writes;
                Phase::Burst { steps: steps - 1 }
            }
            Phase::Waiting { want, since, quiet } => {
                if signature(&e) == Some(want) {
                    s.rebuilds_arrived += 1;
                    buildable = true;
                    s.rebuild_wait = s.rebuild_wait.max(since.elapsed());
                    Phase::Idle {
                        blocks: 10 + d.below(200) as u32,
                    }
                } else if handle.is_rebuilding() || handle.last_error().is_none() {
                    if since.elapsed() > cfg.rebuild_timeout {
                        return Err(fail(
                            &s,
                            format!(
                                "rebuild to {want} requested {:.1} s ago never arrived (bank in \
                                 use: {:?}, worker error: {:?})",
                                since.elapsed().as_secs_f64(),
                                signature(&e),
                                handle.last_error()
                            ),
                        ));
                    }
                    Phase::Waiting {
                        want,
                        since,
                        quiet: None,
                    }
                } else {
                    let q = quiet.unwrap_or_else(Instant::now);
                    if q.elapsed() >= REFUSAL_QUIET {
                        s.refusal(want, handle.last_error().unwrap_or_default());
                        buildable = false;
                        Phase::Idle {
                            blocks: 10 + d.below(200) as u32,
                        }
                    } else {
                        Phase::Waiting {
                            want,
                            since,
                            quiet: Some(q),
                        }
                    }
                }
            }
            idle @ Phase::Idle { .. } => idle,
        };
        // Automation of every parameter that applies without a rebuild.
        let v = params.snapshot();
        for p in PARAMS.iter().filter(|p| !needs_rebuild(p, &v)) {
            params.set(p.id, d.value(p)).map_err(|err| fail(&s, err))?;
            s.param_writes += 1;
        }
        gain_hi = gain_hi.max(10f64.powf(params.get(ParamId::Gain) as f64 / 20.0));
        let n = d.block(max_block);
        storm.fill(&mut d, n, rate, &mut events);
        let (bl, br) = (&mut l[..n], &mut r[..n]);
        let t = Instant::now();
        process(&mut e, &events, bl, br);
        let spent = t.elapsed();
        let finite = bl.iter().chain(br.iter()).all(|x| x.is_finite());
        let peak = bl
            .iter()
            .chain(br.iter())
            .fold(0.0f64, |m, &x| m.max(x.abs() as f64));
        s.block(n, rate, spent, peak / gain_hi, &e);
        if !finite || peak > LEVEL_BOUND * gain_hi {
            let what = if finite {
                format!("output {peak:e} above the bound {LEVEL_BOUND:e} × gain {gain_hi}")
            } else {
                "non-finite output".to_string()
            };
            return Err(fail(
                &s,
                format!(
                    "{what} in a block of {n} at {rate} Hz; bank {:?}, {} voices sounding; \
                     parameters {}",
                    signature(&e),
                    e.active_voices(),
                    describe(&params.snapshot())
                ),
            ));
        }
        if e.bank_id() != bank {
            bank = e.bank_id();
            s.handovers += 1;
        }
        if let Phase::Idle { blocks } = &mut phase {
            *blocks = blocks.saturating_sub(1);
        }
    }
    s.finish(&e, &handle, storm.counts, start.elapsed());
    Ok(s)
}

/// `key=value` for every parameter (failure messages).
fn describe(v: &noether_core::engine::ParamValues) -> String {
    PARAMS
        .iter()
        .map(|p| format!("{}={}", p.key, v.get(p.id)))
        .collect::<Vec<_>>()
        .join(" ")
}

fn fail(s: &SoakSummary, why: impl std::fmt::Display) -> Box<SoakFailure> {
    Box::new(SoakFailure {
        message: why.to_string(),
        summary: s.clone(),
    })
}
