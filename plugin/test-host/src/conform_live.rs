//! `conform` cases of a live host (CLAP's real-time render mode), where clap-validator found
//! the plugin keeping the host waiting or breaking CLAP's event order:
//! - `activate`: random parameter sets activated one after another on one real-time instance
//!   (as clap-validator's `param-fuzz-*` tests do), each `activate()` timed on the wall clock;
//!   the 99th percentile must stay within [`ACTIVATE_P99`] (the target), so an
//!   activation that builds a model (seconds on a cold cache) fails it;
//! - `events`: note ends out of time order (clap-validator's `param-fuzz-modulation`: "output an
//!   event for sample 441 after it had previously output an event for sample 442"): a note on a
//!   sounding key and a note stealing another's voice at the sample where a parameter change
//!   splits the block; `process_stereo` fails on any output event out of order.
//!
//! Threads: the test host's main thread plays the main and the audio thread.

use clack_host::events::event_types::{NoteOnEvent, ParamValueEvent};
use clack_host::prelude::*;
use std::time::Instant;

use crate::conform::Runner;
use crate::conform_params::clap_value;
use crate::conform_render::{set_values, Rng, Session};
use crate::host::{new_realtime_instance, process_stereo, TestHost};

/// Bound of the 99th percentile of `activate()`'s wall time (s).
const ACTIVATE_P99: f64 = 0.020;

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

/// Note ends in time order when a parameter change splits a block at the sample of two notes.
pub(crate) fn events(s: &Session, run: &mut Runner) {
    run.case(
        "events: note ends in time order across a block split by a parameter change",
        || {
            let mut inst = s.instance()?;
            // Two voices, a small gong (fast to build).
            let mut values = s.defaults();
            for (name, text) in [("Polyphony", "2"), ("Modes", "24"), ("In-plane modes", "4")] {
                let (k, v) = clap_value(s, &mut inst, name, text)?;
                values[k] = v;
            }
            set_values(&mut inst, &s.params, &values)?;
            let gain = &s.params[s.index_of("Output gain")?];
            let config = PluginAudioConfiguration {
                sample_rate: RATE,
                min_frames_count: 1,
                max_frames_count: BLOCK,
            };
            let stopped = inst
                .activate(|_, _| (), config)
                .map_err(|e| format!("activate failed: {e:?}"))?;
            let mut proc = stopped
                .start_processing()
                .map_err(|_| "start_processing failed".to_string())?;
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

impl Session {
    /// A new instance in CLAP's real-time render mode (a live host's).
    pub(crate) fn realtime_instance(&self) -> Result<PluginInstance<TestHost>, String> {
        new_realtime_instance(&self.entry, &self.id)
    }
}
