//! The soak's driver loop ([`run`]): blocks, note storms, bursts of rebuild parameters and
//! re-activations, each block checked as the module docs of [`super`] describe.
//!
//! Threads: [`run`] drives the engine from the calling thread (standing in for both the
//! host's main thread and its audio thread); the engine's worker thread builds banks.

use super::draw::{Draw, Storm};
use super::quality::{self, needs_rebuild, signature, Signature};
use super::summary::{SoakFailure, SoakSummary};
use super::{SoakConfig, CEILING, CEILING_ROUNDING, HOST_RATES, MAX_BLOCKS};
use noether_core::engine::{Engine, Event, KeyTuning, ParamId, SharedParams, KEY_COUNT, PARAMS};
use std::sync::Arc;
use std::time::{Duration, Instant};

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

/// Runs the soak; `process` must call `engine.process_events(events, left, right)` (wrapped
/// as the caller likes). Returns the summary, or the first failed check with the summary so
/// far. Allocates (engine, banks, buffers) outside `process` only.
pub fn run<F>(cfg: &SoakConfig, mut process: F) -> Result<SoakSummary, Box<SoakFailure>>
where
    F: FnMut(&mut Engine, &[Event], &mut [f32], &mut [f32]),
{
    let start = Instant::now();
    let mut d = Draw::new(cfg.seed);
    // The choices of the blocks played while a rebuild is pending (see the module doc).
    let mut dw = Draw::new(cfg.seed ^ 0x9e37_79b9_7f4a_7c15);
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
    let mut bank = e.bank_id();
    let mut phase = Phase::Idle { blocks: 20 };
    // The last burst asked for split steps: `dome` and `boss` stay at 0 until the next burst.
    let mut flat = false;
    let mut buildable = true;
    loop {
        if start.elapsed() > cfg.wall_limit {
            return Err(fail(
                &s,
                format!(
                    "wall-time limit {:.0} s passed after {} of {} blocks (a hung or far too \
                     slow engine)",
                    cfg.wall_limit.as_secs_f64(),
                    s.blocks - s.wait_blocks,
                    cfg.blocks
                ),
            ));
        }
        let done = s.blocks - s.wait_blocks >= cfg.blocks;
        phase = match phase {
            Phase::Idle { blocks: 0 } if done => break,
            Phase::Idle { blocks: 0 } => {
                // Re-activation rebuilds from the current parameters, or keeps the last
                // good model when they do not build.
                if d.chance(0.3) {
                    // A host sample-rate change: deactivate, activate at the new rate.
                    rate = if d.chance(0.2) {
                        d.between(8_000.0, 384_000.0).round()
                    } else {
                        d.pick(&HOST_RATES)
                    };
                    max_block = d.pick(&MAX_BLOCKS);
                    e.deactivate();
                    let t = Instant::now();
                    let refused = e
                        .activate(rate, max_block)
                        .map_err(|err| fail(&s, format!("activation at {rate} Hz: {err}")))?;
                    // A set the worker already refused (counted then) is refused again and
                    // the last good model rebuilt instead; any other refusal is a failure.
                    if let (Some(err), true) = (refused, buildable) {
                        return Err(fail(
                            &s,
                            format!("activation at {rate} Hz refused a set that built: {err}"),
                        ));
                    }
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
                let (want, keep_flat) = quality::finish(&mut d, &params, cfg, signature(&e))
                    .map_err(|err| fail(&s, err))?;
                flat = keep_flat;
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
        let waiting = matches!(phase, Phase::Waiting { .. });
        let dd = if waiting { &mut dw } else { &mut d };
        let v = params.snapshot();
        for p in PARAMS.iter().filter(|p| !needs_rebuild(p, &v)) {
            let x = dd.value(p);
            // A bank asked for split steps keeps its plate flat (the curved plate's kernel does
            // not split).
            let x = if flat && matches!(p.id, ParamId::Dome | ParamId::Boss) {
                0.0
            } else {
                x
            };
            params.set(p.id, x).map_err(|err| fail(&s, err))?;
            s.param_writes += 1;
        }
        // Now and then a new key table (each key within a semitone of 12-TET, about one in
        // eight unmapped), published from this host thread like a GUI loading a Scala file.
        if dd.chance(0.01) {
            let hz: [Option<f64>; KEY_COUNT] = std::array::from_fn(|k| {
                let p = k as f64 + dd.between(-1.0, 1.0);
                (!dd.chance(0.125)).then(|| 440.0 * ((p - 69.0) / 12.0).exp2())
            });
            let t = KeyTuning::from_mapped_frequencies(&hz).map_err(|err| fail(&s, err))?;
            params.tuning().set(&t);
            s.tunings += 1;
        }
        let limiter = params.snapshot().index_of(ParamId::Limiter) == 1;
        let n = dd.block(max_block);
        storm.fill(dd, n, rate, &mut events);
        let (bl, br) = (&mut l[..n], &mut r[..n]);
        let guarded = e.guarded_samples();
        let t = Instant::now();
        process(&mut e, &events, bl, br);
        let spent = t.elapsed();
        let guarded = e.guarded_samples() - guarded;
        let finite = bl.iter().chain(br.iter()).all(|x| x.is_finite());
        let peak = bl
            .iter()
            .chain(br.iter())
            .fold(0.0f32, |m, &x| m.max(x.abs()));
        s.block(n, rate, spent, &e);
        s.level(peak, limiter, guarded);
        if waiting {
            s.wait_blocks += 1;
            // Real-time pace while the worker builds (a host's audio thread does not race).
            if let Some(rest) = Duration::from_secs_f64(n as f64 / rate).checked_sub(spent) {
                std::thread::sleep(rest);
            }
        }
        let bound = if limiter {
            CEILING * CEILING_ROUNDING
        } else {
            1.0
        };
        if !finite || peak > bound || (limiter && guarded > 0) {
            let what = if !finite {
                "non-finite output".to_string()
            } else if peak > bound {
                format!("output {peak:e} above the bound {bound:e} (limiter on: {limiter})")
            } else {
                format!("{guarded} samples clipped by the guard with the limiter on")
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
