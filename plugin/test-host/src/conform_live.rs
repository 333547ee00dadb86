//! `conform` cases of a live host (CLAP's real-time render mode), where clap-validator found
//! the plugin keeping the host waiting or breaking CLAP's event order:
//! - `activate`: random parameter sets activated one after another on one real-time instance
//!   (as clap-validator's `param-fuzz-*` tests do), each `activate()` timed on the wall clock;
//!   the 99th percentile must stay within [`ACTIVATE_P99`] (the target), so an
//!   activation that builds a model (seconds on a cold cache) fails it;
//! - `events`: note ends out of time order (clap-validator's `param-fuzz-modulation`: "output an
//!   event for sample 441 after it had previously output an event for sample 442"): a note on a
//!   sounding key and a note stealing another's voice at the sample where a parameter change
//!   splits the block; `process_stereo` fails on any output event out of order;
//! - `load`: blocks of [`LOAD_EVENTS`] input events each (notes, per-note modulation and
//!   note ends at a handful of sample times), denser than pluginval's automation tests, which
//!   overflowed nice-plug's input queues ("Input event buffer filled up! This will cause an
//!   allocation"); the plugin's own log, read by [`log_is_clean`], must not report it.
//!
//! Threads: the test host's main thread plays the main and the audio thread.

use clack_host::events::event_types::{NoteOffEvent, NoteOnEvent, ParamModEvent, ParamValueEvent};
use clack_host::prelude::*;
use std::time::Instant;

use crate::conform_params::clap_value;
use crate::conform_render::{set_values, Rng, Session};
use crate::host::{activate_started, new_realtime_instance, process_stereo, Started, TestHost};
use crate::runner::Runner;

/// Bound of the 99th percentile of `activate()`'s wall time (s).
const ACTIVATE_P99: f64 = 0.020;

/// Input events per block of the `load` case: more than nice-plug's default input queue (1024)
/// and than any host sends in one block (pluginval's densest test changes every parameter
/// once per block).
const LOAD_EVENTS: usize = 6000;

/// What nice-plug logs when an input queue overflows on the audio thread.
const ALLOCATION_WARNING: &str = "will cause an allocation";

/// Host rate and block of the live cases.
const RATE: f64 = 48_000.0;
const BLOCK: u32 = 512;

/// `count` random sets (seeded by `seed`) activated in turn on one real-time instance.
pub(crate) fn activate(s: &Session, seed: u64, count: usize, run: &mut Runner) {
    run.case(
        &format!("activate: {count} random sets on one real-time instance, wall time"),
        || {
            let mut inst = s.realtime_instance()?;
            let mut rng = Rng::new(seed ^ 0xac7);
            let mut times = Vec::with_capacity(count);
            for i in 0..count {
                let values: Vec<f64> = s.params.iter().map(|p| rng.value_of(p)).collect();
                set_values(&mut inst, &s.params, &values)?;
                let config = PluginAudioConfiguration {
                    sample_rate: RATE,
                    min_frames_count: 1,
                    max_frames_count: BLOCK,
                };
                let t0 = Instant::now();
                let stopped = inst
                    .activate(|_, _| (), config)
                    .map_err(|e| format!("set {}: activate failed: {e:?}", i + 1))?;
                times.push(t0.elapsed().as_secs_f64());
                inst.deactivate(stopped);
            }
            times.sort_by(f64::total_cmp);
            let at = |q: f64| {
                times[((q * times.len() as f64).ceil() as usize).clamp(1, times.len()) - 1]
            };
            let (p50, p99, max) = (at(0.5), at(0.99), times[times.len() - 1]);
            let figures = format!(
                "activate() median {:.2} ms, p99 {:.2} ms, max {:.2} ms",
                1e3 * p50,
                1e3 * p99,
                1e3 * max
            );
            if p99 > ACTIVATE_P99 {
                return Err(format!("{figures}: p99 above {:.0} ms", 1e3 * ACTIVATE_P99));
            }
            Ok(figures)
        },
    );
}

/// An offline instance of a small gong (24 modes, 4 in-plane: fast to build) with
/// `polyphony` voices, activated at [`RATE`] with blocks of [`BLOCK`] and processing.
fn small_gong(s: &Session, polyphony: &str) -> Result<Started, String> {
    let mut inst = s.instance()?;
    let mut values = s.defaults();
    for (name, text) in [
        ("Polyphony", polyphony),
        ("Modes", "24"),
        ("In-plane modes", "4"),
    ] {
        let (k, v) = clap_value(s, &mut inst, name, text)?;
        values[k] = v;
    }
    set_values(&mut inst, &s.params, &values)?;
    activate_started(inst, RATE, BLOCK)
}

/// Note ends in time order when a parameter change splits a block at the sample of two notes.
pub(crate) fn events(s: &Session, run: &mut Runner) {
    run.case(
        "events: note ends in time order across a block split by a parameter change",
        || {
            let gain = &s.params[s.index_of("Output gain")?];
            let (mut inst, mut proc) = small_gong(s, "2")?;
            let note = |key: u16, id: u32| Pckn::new(0u16, 0u16, key, id);
            let mut first = EventBuffer::new();
            first.push(&NoteOnEvent::new(0, note(60, 1), 1.0));
            first.push(&NoteOnEvent::new(0, note(62, 2), 1.0));
            // At sample 300: key 60 again (its note 1 ends there) and key 64 (stealing note 2's
            // voice: it ends at the sub-block's end), then the gain, which splits the block.
            let mut second = EventBuffer::new();
            second.push(&NoteOnEvent::new(300, note(60, 3), 1.0));
            second.push(&NoteOnEvent::new(300, note(64, 4), 1.0));
            second.push(&ParamValueEvent::new(
                300,
                gain.id,
                Pckn::match_all(),
                gain.default,
            ));
            let (mut l, mut r) = (vec![0.0f32; BLOCK as usize], vec![0.0f32; BLOCK as usize]);
            let (mut ports, mut out_buf) = (AudioPorts::with_capacity(2, 1), EventBuffer::new());
            let mut result = Ok(());
            let mut ends = 0;
            for (b, ev) in [&first, &second, &EventBuffer::new()]
                .into_iter()
                .enumerate()
            {
                result = process_stereo(
                    &mut proc,
                    &mut ports,
                    ev,
                    &mut out_buf,
                    [&mut l, &mut r],
                    b as u64 * u64::from(BLOCK),
                );
                ends += out_buf.iter().count();
                if result.is_err() {
                    break;
                }
            }
            inst.deactivate(proc.stop_processing());
            result.map(|()| format!("{ends} note ends, in order"))
        },
    );
}

/// Four blocks of [`LOAD_EVENTS`] input events each (an offline instance, so the model plays
/// from the first block): output finite,
/// within full scale and note ends in order (`process_stereo`); the log check at the end of
/// `conform` fails if a queue overflowed.
pub(crate) fn load(s: &Session, run: &mut Runner) {
    run.case(
        &format!("load: 4 blocks of {LOAD_EVENTS} input events each"),
        || {
            let damping = &s.params[s.index_of("Damping")?];
            let (mut inst, mut proc) = small_gong(s, "4")?;
            // A third of the events note-ons, a third per-note modulations, a third note-offs,
            // in time order at eight sample times of the block.
            let per_kind = LOAD_EVENTS / 3;
            let (mut l, mut r) = (vec![0.0f32; BLOCK as usize], vec![0.0f32; BLOCK as usize]);
            let (mut ports, mut out_buf) = (AudioPorts::with_capacity(2, 1), EventBuffer::new());
            let (mut ends, mut peak) = (0, 0.0f32);
            let mut result = Ok(());
            for b in 0..4u32 {
                let mut ev = EventBuffer::new();
                for slot in 0..8u32 {
                    let time = slot * (BLOCK / 8);
                    let share = per_kind / 8;
                    for i in 0..share {
                        let id = b * 100_000 + slot * 10_000 + i as u32;
                        let key = (36 + (i % 48)) as u16;
                        let note = Pckn::new(0u16, 0u16, key, id);
                        ev.push(&NoteOnEvent::new(time, note, 0.8));
                        ev.push(&ParamModEvent::new(time, damping.id, note, 0.1));
                        ev.push(&NoteOffEvent::new(time, note, 0.0));
                    }
                }
                result = process_stereo(
                    &mut proc,
                    &mut ports,
                    &ev,
                    &mut out_buf,
                    [&mut l, &mut r],
                    u64::from(b * BLOCK),
                );
                ends += out_buf.iter().count();
                peak = l.iter().chain(&r).fold(peak, |m, x| m.max(x.abs()));
                if result.is_err() {
                    break;
                }
                if !l.iter().chain(&r).all(|x| x.is_finite() && x.abs() <= 1.0) {
                    result = Err(format!("block {b}: output not finite or above full scale"));
                    break;
                }
            }
            inst.deactivate(proc.stop_processing());
            result.map(|()| format!("{ends} note ends in order, peak {peak:.3}"))
        },
    );
}

/// The plugin's log (nice-plug's `NICE_LOG` file, set by `conform`) holds no warning that the
/// audio thread allocated (an overflowing input event queue).
pub(crate) fn log_is_clean(log: &std::path::Path, run: &mut Runner) {
    run.case("log: no allocation reported on the audio thread", || {
        let text = std::fs::read_to_string(log).unwrap_or_default();
        let hits: Vec<&str> = text
            .lines()
            .filter(|l| l.contains(ALLOCATION_WARNING))
            .collect();
        match hits.first() {
            None => Ok(format!("{} log lines, none warns", text.lines().count())),
            Some(first) => Err(format!("{} warnings, the first: {first}", hits.len())),
        }
    });
}

impl Session {
    /// A new instance in CLAP's real-time render mode (a live host's).
    pub(crate) fn realtime_instance(&self) -> Result<PluginInstance<TestHost>, String> {
        new_realtime_instance(&self.entry, &self.id)
    }
}
