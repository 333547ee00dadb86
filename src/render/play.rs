//! `noether play`: a factory or user preset played through the real-time [`Engine`] headless,
//! exactly as the plugin plays it: the preset's full parameter set in the engine's shared
//! parameters ([`super::preset_engine`]), the engine activated at the host rate, blocks of the
//! host's size, and note events at their sample offsets inside the blocks
//! ([`Engine::process_events`]). The notes come from `--note` specifications ([`parse_note`],
//! [`notes_timeline`]) or a standard MIDI file ([`super::midi`]).
//!
//! What the render cost is measured in CPU time of the whole process (`CLOCK_PROCESS_CPUTIME_ID`:
//! the calling thread, which plays the audio thread, and every engine thread), over the
//! render loop only (the bank is built before it), and per block around `process_events`.
//!
//! Runs on the calling (CLI) thread.

use super::preset_engine::{start_engine, FoundPreset, PresetEngine, BANK_TIMEOUT};
use crate::engine::{
    Event, EventKind, FitReason, KeyTuning, ParamId, Preset, MAX_HOST_RATE, MAX_TEMPO, MAX_VOICES,
    MIN_HOST_RATE, MIN_TEMPO,
};
use crate::error::{check_closed, Error, ParamError};
use serde::Serialize;

/// Velocity of a `--note` without one (MIDI, 1 to 127).
pub const DEFAULT_VELOCITY: u8 = 127;
/// How long a `--note` without a duration is held (s).
pub const DEFAULT_HOLD: f64 = 4.0;
/// Longest held note, gap, tail or `--at` time (s).
pub const MAX_SECONDS: f64 = 600.0;
/// Longest render (s): the output is kept in memory (2 × 4 bytes per sample).
pub const MAX_RENDER_SECONDS: f64 = 1800.0;
/// Largest host block (samples).
pub const MAX_BLOCK: usize = 8192;

/// One engine event at a time in seconds from the start of the render.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimedEvent {
    /// Time (s).
    pub time: f64,
    /// The event.
    pub kind: EventKind,
}

/// A performance: engine events in time order, and the time of the last one (s).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Timeline {
    /// Events sorted by time; at equal times note offs come first (a repeated key is released,
    /// then struck again), the others in the given order (a note's per-note expressions after
    /// its note on, as MPE and the MIDI mapping send them).
    pub events: Vec<TimedEvent>,
    /// Time of the last event (s): the render goes on for the tail after it.
    pub end: f64,
}

impl Timeline {
    /// Sorts `events` (stable, see [`Timeline::events`]) and finds the end.
    pub fn new(mut events: Vec<TimedEvent>) -> Timeline {
        let is_off = |k: &EventKind| matches!(k, EventKind::NoteOff { .. });
        events.sort_by(|a, b| {
            a.time
                .total_cmp(&b.time)
                .then(is_off(&b.kind).cmp(&is_off(&a.kind)))
        });
        let end = events.last().map_or(0.0, |e| e.time);
        Timeline { events, end }
    }
}

/// A `--note KEY[:VEL[:SECONDS]]`: MIDI key, velocity 1-127 and how long it is held (s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NoteSpec {
    /// MIDI key (0 to 127; 60 = C4).
    pub key: u8,
    /// MIDI velocity (1 to 127).
    pub velocity: u8,
    /// Seconds from note on to note off.
    pub seconds: f64,
}

impl NoteSpec {
    /// `key` at the default velocity and duration.
    pub fn new(key: u8) -> NoteSpec {
        NoteSpec {
            key,
            velocity: DEFAULT_VELOCITY,
            seconds: DEFAULT_HOLD,
        }
    }
}

/// A key as a MIDI number (`0` to `127`) or a note name: a letter A-G (either case), an optional
/// `#` or `b`, and an octave -1 to 9 with C4 = 60 (scientific pitch notation), e.g. `F#3` = 54,
/// `Bb-1` = 10. Errors name `--note` and the text.
pub fn parse_key(text: &str) -> Result<u8, ParamError> {
    let bad = || {
        ParamError::new(
            "--note",
            format!("key `{text}`"),
            "a MIDI key 0 to 127 or a note name C-1 to G9 (C4 = 60, e.g. F#3, Bb2)",
        )
    };
    let t = text.trim();
    if let Ok(k) = t.parse::<i64>() {
        return u8::try_from(k).ok().filter(|&k| k <= 127).ok_or_else(bad);
    }
    let mut chars = t.chars();
    let letter = chars.next().ok_or_else(bad)?;
    let base: i64 = match letter.to_ascii_uppercase() {
        'C' => 0,
        'D' => 2,
        'E' => 4,
        'F' => 5,
        'G' => 7,
        'A' => 9,
        'B' => 11,
        _ => return Err(bad()),
    };
    let rest = chars.as_str();
    let (shift, octave) = if let Some(r) = rest.strip_prefix('#') {
        (1, r)
    } else if let Some(r) = rest.strip_prefix('b') {
        (-1, r)
    } else {
        (0, rest)
    };
    let octave: i64 = octave.parse().map_err(|_| bad())?;
    if !(-1..=9).contains(&octave) {
        return Err(bad());
    }
    let k = (octave + 1) * 12 + base + shift;
    u8::try_from(k).ok().filter(|&k| k <= 127).ok_or_else(bad)
}

/// Parses `KEY[:VEL[:SECONDS]]` (defaults: velocity [`DEFAULT_VELOCITY`], held
/// [`DEFAULT_HOLD`] s). Errors name `--note`, the part and its range.
pub fn parse_note(text: &str) -> Result<NoteSpec, ParamError> {
    let mut parts = text.split(':');
    let key = parse_key(parts.next().unwrap_or(""))?;
    let mut note = NoteSpec::new(key);
    if let Some(v) = parts.next() {
        let bad = || ParamError::new("--note", format!("velocity `{v}` in `{text}`"), "1 to 127");
        let vel: u8 = v.trim().parse().map_err(|_| bad())?;
        if !(1..=127).contains(&vel) {
            return Err(bad());
        }
        note.velocity = vel;
    }
    if let Some(s) = parts.next() {
        let bad = || {
            ParamError::new(
                "--note",
                format!("seconds `{s}` in `{text}`"),
                format!("0.001 to {MAX_SECONDS}"),
            )
        };
        let secs: f64 = s.trim().parse().map_err(|_| bad())?;
        if !(secs.is_finite() && (0.001..=MAX_SECONDS).contains(&secs)) {
            return Err(bad());
        }
        note.seconds = secs;
    }
    if parts.next().is_some() {
        return Err(ParamError::new(
            "--note",
            format!("`{text}`"),
            "KEY[:VEL[:SECONDS]], e.g. C4, 60:100, F#3:90:2.5",
        ));
    }
    Ok(note)
}

/// The timeline of `notes`: each starts at its `at` time if `at` is given (then `at` has one
/// time per note, or `notes` is a single note played at every time), else `gap` seconds after
/// the previous note's release (the first at 0 s). Errors name `--at` or `--gap`.
pub fn notes_timeline(notes: &[NoteSpec], at: &[f64], gap: f64) -> Result<Timeline, ParamError> {
    check_closed("--gap", gap, 0.0, MAX_SECONDS)?;
    for &t in at {
        check_closed("--at", t, 0.0, MAX_SECONDS)?;
    }
    let starts: Vec<(NoteSpec, f64)> = if at.is_empty() {
        let mut t = 0.0;
        notes
            .iter()
            .map(|n| {
                let s = t;
                t += n.seconds + gap;
                (*n, s)
            })
            .collect()
    } else if notes.len() == 1 {
        at.iter().map(|&t| (notes[0], t)).collect()
    } else if notes.len() == at.len() {
        notes.iter().copied().zip(at.iter().copied()).collect()
    } else {
        return Err(ParamError::new(
            "--at",
            format!("{} times for {} notes", at.len(), notes.len()),
            "one time per --note (or a single --note played at every time)",
        ));
    };
    let mut events = Vec::with_capacity(2 * starts.len());
    for (n, t) in starts {
        events.push(TimedEvent {
            time: t,
            kind: EventKind::NoteOn {
                key: n.key,
                velocity: f32::from(n.velocity) / 127.0,
            },
        });
        events.push(TimedEvent {
            time: t + n.seconds,
            kind: EventKind::NoteOff { key: n.key },
        });
    }
    Ok(Timeline::new(events))
}

/// The host of a play: its rate, block size, and the tail rendered after the last event.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaySettings {
    /// Host sample rate (Hz).
    pub host_rate: f64,
    /// Host block size (samples).
    pub block: usize,
    /// Seconds rendered after the timeline's last event.
    pub tail: f64,
    /// The pitch of every key (12-TET: [`KeyTuning::equal`]; a Scala file:
    /// [`crate::engine::load_scala`]).
    pub tuning: KeyTuning,
    /// The host's tempo (beats per minute; `None`: none), as a host's transport gives it
    /// (the drone's cycle follows it with `drone_sync` on).
    pub tempo: Option<f64>,
}

impl PlaySettings {
    /// Checks each setting (errors name `--rate`, `--block`, `--tail`, `--tempo`).
    pub fn validate(&self) -> Result<(), ParamError> {
        check_closed("--rate", self.host_rate, MIN_HOST_RATE, MAX_HOST_RATE)?;
        if !(1..=MAX_BLOCK).contains(&self.block) {
            return Err(ParamError::new(
                "--block",
                self.block,
                format!("1 to {MAX_BLOCK} samples"),
            ));
        }
        check_closed("--tail", self.tail, 0.0, MAX_SECONDS)?;
        if let Some(bpm) = self.tempo {
            check_closed("--tempo", bpm, MIN_TEMPO, MAX_TEMPO)?;
        }
        Ok(())
    }
}

/// What one note played (read from the engine just after the block in which it started).
#[derive(Debug, Clone, Serialize)]
pub struct NoteReport {
    /// MIDI key.
    pub key: u8,
    /// MIDI velocity (1 to 127).
    pub velocity: u8,
    /// Note-on time (s).
    pub start_s: f64,
    /// Transverse plate modes stepped (strings: modes `N - 1`); `null` if no voice sounds the
    /// key (the note was refused).
    pub n_phi: Option<u32>,
    /// In-plane modes stepped (0: a linear plate or a string).
    pub n_psi: Option<u32>,
    /// Simulation rate of the voice (Hz).
    pub sim_rate: Option<f32>,
    /// Frequency of the highest mode driven and heard (Hz).
    pub top_mode_hz: Option<f32>,
    /// Modes of a plate's band above the simulation (0: none or off).
    pub above_modes: Option<u32>,
    /// Frequency of the band above's highest mode (Hz; 0 without one).
    pub above_top_hz: Option<f32>,
}

/// The JSON report of a play.
#[derive(Debug, Clone, Serialize)]
pub struct PlayReport {
    /// Preset file stem.
    pub preset: String,
    /// Preset display name.
    pub preset_name: String,
    /// Host rate (Hz).
    pub host_rate: f64,
    /// Host block (samples).
    pub block: usize,
    /// Rendered seconds (the timeline plus the tail).
    pub seconds: f64,
    /// Each note on, in time order.
    pub notes: Vec<NoteReport>,
    /// Process CPU seconds spent in the render loop per second of audio rendered (every
    /// thread of the process; 1.0 = one core fully busy in real time).
    pub cpu_seconds_per_audio_second: f64,
    /// Largest process CPU time of one `process_events` call over the block's duration.
    pub max_block_cpu_fraction: f64,
    /// Wall seconds spent in `process_events` per second of audio rendered: below 1 the
    /// engine keeps up with real time on this machine (with every core it uses; a helper
    /// thread that spins while it waits for work counts in the CPU figure, not in this one).
    pub wall_seconds_per_audio_second: f64,
    /// Largest wall time of one `process_events` call over the block's duration (note-ons
    /// included, whose tier set-up runs in that block).
    pub max_block_wall_fraction: f64,
    /// Threads sharing the voices' work: the `threads` parameter, or the machine's available
    /// parallelism when it is 0.
    pub threads: usize,
    /// Voices of the bank.
    pub polyphony: usize,
    /// Simulation rate of the bank (Hz).
    pub bank_sim_rate: Option<f64>,
    /// Wall seconds from activation until the bank was in use (before the loop).
    pub bank_seconds: f64,
    /// The engine's latency (host samples) as a plugin reports it to the host: the
    /// resampler's half-width. A note's sound starts this late after its event.
    pub latency_samples: u32,
    /// Largest absolute sample of either channel.
    pub peak: f64,
    /// `peak` in dB relative to full scale (1.0); -inf for silence (written as `null`).
    pub peak_dbfs: Option<f64>,
    /// Non-finite samples (0 for a healthy render).
    pub nan_count: u64,
    /// Notes the engine refused (unstable coefficients).
    pub refused_notes: u64,
    /// Voices silenced as diverged.
    pub diverged_voices: u64,
    /// Voice chunks a worker had not finished within the audio thread's bounded wait (left
    /// out of the mix).
    pub late_jobs: u64,
    /// Halves of split plate steps run by a worker (voices with a coupling tensor of at
    /// least `SPLIT_MIN_ENTRIES` entries share each step between two cores).
    pub shared_step_halves: u64,
    /// Halves of split steps a worker took but did not finish within the bounded wait (the
    /// voice computed them itself: same sound).
    pub late_step_halves: u64,
    /// Megabytes of coupling tensors the engine held (`Engine::memory_bytes`: the bank's tiers
    /// and the modal cache's basis).
    pub tensor_megabytes: f64,
    /// The bank was built with fewer modes than asked: "1000 of 2000 modes (memory cap)"
    /// (offline, only the memory cap reduces a model; `null` otherwise).
    pub reduced: Option<String>,
    /// How a string network's strings were tuned (the drone's, the sitar's: "tuned by ear at
    /// the root and at keys up to 12 semitones around it"; `null` for the other models).
    pub drone_tuning: Option<String>,
}

/// A finished play: the stereo output at the host rate and its report.
#[derive(Debug, Clone)]
pub struct Played {
    /// Left and right channels.
    pub out: [Vec<f32>; 2],
    /// The report.
    pub report: PlayReport,
}

/// CPU seconds of the whole process (every thread) since it started; where the platform has
/// no process clock (not Unix), wall seconds since the first call.
pub fn process_cpu_seconds() -> f64 {
    use std::sync::OnceLock;
    static T0: OnceLock<std::time::Instant> = OnceLock::new();
    match noether_core::clock::process_cpu_time() {
        Some(t) => t.as_secs_f64(),
        None => T0
            .get_or_init(std::time::Instant::now)
            .elapsed()
            .as_secs_f64(),
    }
}

/// The preset's root key (the default note of `noether play`).
pub fn root_key(preset: &Preset) -> Result<u8, ParamError> {
    Ok(preset.values()?.get(ParamId::RootKey) as u8)
}

/// Plays `timeline` through a fresh engine holding `preset` (see the module documentation);
/// `progress` receives the fraction done about every 0.1 s of audio.
pub fn play(
    preset: &FoundPreset,
    timeline: &Timeline,
    settings: &PlaySettings,
    mut progress: impl FnMut(f64),
) -> Result<Played, Error> {
    settings.validate()?;
    let seconds = timeline.end + settings.tail;
    check_closed("rendered seconds", seconds, 0.0, MAX_RENDER_SECONDS)?;
    let PresetEngine {
        mut engine,
        params,
        handle: _handle,
        bank_seconds,
    } = start_engine(
        &preset.preset,
        &[],
        settings.host_rate,
        settings.block,
        BANK_TIMEOUT,
    )?;
    // Taken by the engine at its first block, before any note.
    params.tuning().set(&settings.tuning);
    engine.set_host_tempo(settings.tempo);
    let rate = settings.host_rate;
    let total = (seconds * rate).round() as usize;
    let at = |t: f64| ((t * rate).round() as usize).min(total.saturating_sub(1));
    let mut out = [Vec::with_capacity(total), Vec::with_capacity(total)];
    let (mut l, mut r) = (vec![0.0f32; settings.block], vec![0.0f32; settings.block]);
    let mut block_events: Vec<Event> = Vec::with_capacity(timeline.events.len().min(4096));
    let mut notes = Vec::new();
    let (mut next, mut pos, mut max_fraction) = (0usize, 0usize, 0.0f64);
    let (mut wall, mut max_wall_fraction) = (0.0f64, 0.0f64);
    let progress_every = (0.1 * rate) as usize;
    let mut next_progress = 0;
    let cpu0 = process_cpu_seconds();
    while pos < total {
        let n = settings.block.min(total - pos);
        block_events.clear();
        let first = next;
        while next < timeline.events.len() && at(timeline.events[next].time) < pos + n {
            let e = timeline.events[next];
            block_events.push(Event::new((at(e.time) - pos) as u32, e.kind));
            next += 1;
        }
        let (c0, w0) = (process_cpu_seconds(), std::time::Instant::now());
        engine.process_events(&block_events, &mut l[..n], &mut r[..n]);
        let (spent, took) = (process_cpu_seconds() - c0, w0.elapsed().as_secs_f64());
        max_fraction = max_fraction.max(spent / (n as f64 / rate));
        max_wall_fraction = max_wall_fraction.max(took / (n as f64 / rate));
        wall += took;
        for e in &timeline.events[first..next] {
            if let EventKind::NoteOn { key, velocity } = e.kind {
                notes.push(note_report(&engine, key, velocity, e.time));
            }
        }
        out[0].extend_from_slice(&l[..n]);
        out[1].extend_from_slice(&r[..n]);
        pos += n;
        if pos >= next_progress {
            progress(pos as f64 / total.max(1) as f64);
            next_progress = pos + progress_every;
        }
    }
    let cpu = process_cpu_seconds() - cpu0;
    let peak = out
        .iter()
        .flatten()
        .filter(|x| x.is_finite())
        .fold(0.0f64, |m, &x| m.max(f64::from(x).abs()));
    let nan_count = out.iter().flatten().filter(|x| !x.is_finite()).count() as u64;
    let threads_param = params.get(ParamId::Threads) as usize;
    let threads = if threads_param == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        threads_param
    };
    let report = PlayReport {
        preset: preset.stem.clone(),
        preset_name: preset.preset.name.clone(),
        host_rate: rate,
        block: settings.block,
        seconds: total as f64 / rate,
        notes,
        cpu_seconds_per_audio_second: cpu / (total.max(1) as f64 / rate),
        max_block_cpu_fraction: max_fraction,
        wall_seconds_per_audio_second: wall / (total.max(1) as f64 / rate),
        max_block_wall_fraction: max_wall_fraction,
        threads,
        polyphony: engine.polyphony(),
        bank_sim_rate: engine.sim_rate(),
        bank_seconds,
        latency_samples: engine.latency_samples(),
        peak,
        peak_dbfs: (peak > 0.0).then(|| 20.0 * peak.log10()),
        nan_count,
        refused_notes: engine.refused_notes(),
        diverged_voices: engine.diverged_voices(),
        late_jobs: engine.late_jobs(),
        shared_step_halves: engine.shared_step_halves(),
        late_step_halves: engine.late_step_halves(),
        tensor_megabytes: engine.memory_bytes() as f64 / 1048576.0,
        reduced: engine.modes_fitted().map(|f| {
            let why = match f.reason {
                FitReason::Cpu => "CPU budget",
                FitReason::Memory => "memory cap",
            };
            format!("{} of {} modes ({why})", f.built, f.wanted)
        }),
        drone_tuning: engine.drone_tuning().map(|t| t.to_string()),
    };
    Ok(Played { out, report })
}

/// The model of the voice sounding `key`, read just after its note started.
fn note_report(engine: &crate::engine::Engine, key: u8, velocity: f32, start_s: f64) -> NoteReport {
    let model = (0..engine.polyphony().min(MAX_VOICES))
        .find(|&s| engine.voice_key(s) == Some(key))
        .and_then(|s| engine.voice_model(s));
    NoteReport {
        key,
        velocity: (velocity * 127.0).round().clamp(1.0, 127.0) as u8,
        start_s,
        n_phi: model.map(|m| m.n_phi),
        n_psi: model.map(|m| m.n_psi),
        sim_rate: model.map(|m| m.sim_rate),
        top_mode_hz: model.map(|m| m.top_mode_hz),
        above_modes: model.map(|m| m.above_modes),
        above_top_hz: model.map(|m| m.above_top_hz),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Names and numbers: C4 = 60, A4 = 69, F#3 = 54, Bb-1 = 10, G9 = 127; out of range and
    /// malformed keys are refused naming `--note`.
    #[test]
    fn keys() {
        for (t, k) in [
            ("C4", 60),
            ("a4", 69),
            ("F#3", 54),
            ("Bb-1", 10),
            ("G9", 127),
            ("C-1", 0),
            ("0", 0),
            ("127", 127),
        ] {
            assert_eq!(parse_key(t).unwrap(), k, "{t}");
        }
        for t in ["128", "-1", "H4", "G#9", "C10", "", "C", "C#x"] {
            let e = parse_key(t).unwrap_err();
            assert_eq!(e.field, "--note", "{t}");
            assert!(e.allowed.contains("0 to 127"), "{e}");
        }
    }

    #[test]
    fn note_specs() {
        assert_eq!(parse_note("C4").unwrap(), NoteSpec::new(60));
        let n = parse_note("61:90:2.5").unwrap();
        assert_eq!((n.key, n.velocity, n.seconds), (61, 90, 2.5));
        for bad in [
            "C4:0",
            "C4:128",
            "C4:x",
            "C4:100:0",
            "C4:100:nan",
            "C4:1:1:1",
        ] {
            assert_eq!(parse_note(bad).unwrap_err().field, "--note", "{bad}");
        }
    }

    /// Sequential notes follow one another `gap` s after each release; `--at` places them;
    /// a mismatched `--at` count is refused.
    #[test]
    fn timelines() {
        let a = NoteSpec {
            seconds: 1.0,
            ..NoteSpec::new(60)
        };
        let t = notes_timeline(&[a, a], &[], 0.5).unwrap();
        let times: Vec<f64> = t.events.iter().map(|e| e.time).collect();
        assert_eq!(times, vec![0.0, 1.0, 1.5, 2.5]);
        assert_eq!(t.end, 2.5);
        let t = notes_timeline(&[a], &[0.0, 0.25], 0.0).unwrap();
        assert_eq!(t.events.len(), 4);
        assert_eq!(t.end, 1.25);
        assert_eq!(
            notes_timeline(&[a, a], &[0.0, 1.0, 2.0], 0.0)
                .unwrap_err()
                .field,
            "--at"
        );
        assert_eq!(notes_timeline(&[a], &[], -1.0).unwrap_err().field, "--gap");
        // Back to back on one key: the release comes before the new strike.
        let t = notes_timeline(&[a, a], &[], 0.0).unwrap();
        assert!(matches!(t.events[1].kind, EventKind::NoteOff { .. }));
        assert!(matches!(t.events[2].kind, EventKind::NoteOn { .. }));
    }
}
