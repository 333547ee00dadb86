//! Golden renders of the factory presets through the real-time engine, for before/after
//! comparisons of a refactor (`scripts/compare-renders.sh`).
//!
//! For each preset (the TOML files given on the command line, or every factory preset embedded
//! in the library when none is given) this plays the preset the way the plugin does when a user
//! picks it in the editor, using only the public `noether::engine` API:
//!
//! 1. a fresh engine on default parameters is activated at 48 kHz with 256-sample blocks (this
//!    builds the default bank on the calling thread and starts the worker thread);
//! 2. the preset's full parameter set is written into the shared parameters
//!    ([`Preset::apply`]); the worker notices the change, debounces it and builds the preset's
//!    bank. We wait (bounded, `--build-timeout`) on the handle's status
//!    ([`EngineHandle::banks_built`], [`EngineHandle::is_rebuilding`],
//!    [`EngineHandle::last_error`]) instead of sleeping a fixed time;
//! 3. the audio thread takes the new bank at the first chunk of its next block, so one silent
//!    block is processed (and not written) before the note: a note-on sent earlier would start
//!    on the old bank and be faded out with it. The bank in use is then checked against the
//!    preset (model and polyphony);
//! 4. the preset's root key is played at full velocity (1.0), released after `--hold` seconds
//!    (sample-accurate note-off event), and `--seconds` of output are rendered in 256-sample
//!    blocks and written as a stereo 32-bit float WAV `<stem>.wav` (the engine's f32 samples as
//!    they are), with a small `<stem>.json` of counters (peak, refused notes, diverged voices,
//!    Newton cap hits, bank rate and size).
//!
//! `--load-before-activate` instead writes the preset before `activate` (the path of a host
//! restoring a saved state: the bank is built on the calling thread, no worker build), then
//! processes the same one silent block. Both paths must give the same samples.
//!
//! ```text
//! cargo run --release --example render_presets -- [--out DIR] [--seconds S] [--hold S]
//!     [--build-timeout S] [--load-before-activate] [PRESET.toml ...]
//! ```
//!
//! Exit status: 0 when every preset rendered, 1 when one failed (the others are still
//! rendered), 2 on a bad command line.

use noether::engine::{Engine, EngineHandle, Event, EventKind, ParamId, Preset, SharedParams};
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Host rate of the renders (Hz).
const HOST_RATE: f64 = 48_000.0;
/// Host block size (samples).
const BLOCK: usize = 256;
/// Note-on velocity ("full velocity").
const VELOCITY: f32 = 1.0;
/// Polling period while waiting for the worker.
const POLL: Duration = Duration::from_millis(2);

/// Command-line options.
#[derive(Debug)]
struct Options {
    out: PathBuf,
    seconds: f64,
    hold: f64,
    build_timeout: f64,
    load_before_activate: bool,
    files: Vec<PathBuf>,
}

const USAGE: &str = "usage: render_presets [--out DIR] [--seconds S] [--hold S] \
[--build-timeout S] [--load-before-activate] [PRESET.toml ...]
  --out DIR               output folder (default: out/presets)
  --seconds S             rendered length after the note-on (default 1.5, allowed 0.01..=60)
  --hold S                note-off time after the note-on (default 1.0, allowed 0..=seconds)
  --build-timeout S       longest wait for the worker's bank build (default 120)
  --load-before-activate  write the preset before activate (host state restore) instead of
                          after it (editor preset menu, the default)
  PRESET.toml             preset files (default: every factory preset embedded in the library)";

fn parse_number(flag: &str, value: Option<String>) -> Result<f64, String> {
    let v = value.ok_or_else(|| format!("`{flag}` needs a value"))?;
    v.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("invalid value for `{flag}`: `{v}` (allowed: a finite number)"))
}

fn parse_args() -> Result<Options, String> {
    let mut o = Options {
        out: PathBuf::from("out/presets"),
        seconds: 1.5,
        hold: 1.0,
        build_timeout: 120.0,
        load_before_activate: false,
        files: Vec::new(),
    };
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "-h" | "--help" => return Err(String::new()),
            "--out" => o.out = PathBuf::from(args.next().ok_or("`--out` needs a folder")?),
            "--seconds" => o.seconds = parse_number("--seconds", args.next())?,
            "--hold" => o.hold = parse_number("--hold", args.next())?,
            "--build-timeout" => o.build_timeout = parse_number("--build-timeout", args.next())?,
            "--load-before-activate" => o.load_before_activate = true,
            s if s.starts_with('-') => return Err(format!("unknown option `{s}`")),
            s => o.files.push(PathBuf::from(s)),
        }
    }
    if !(0.01..=60.0).contains(&o.seconds) {
        return Err(format!(
            "invalid value for `--seconds`: {} (allowed: 0.01 to 60)",
            o.seconds
        ));
    }
    if !(0.0..=o.seconds).contains(&o.hold) {
        return Err(format!(
            "invalid value for `--hold`: {} (allowed: 0 to --seconds = {})",
            o.hold, o.seconds
        ));
    }
    if !(o.build_timeout > 0.0 && o.build_timeout <= 3600.0) {
        return Err(format!(
            "invalid value for `--build-timeout`: {} (allowed: > 0 to 3600)",
            o.build_timeout
        ));
    }
    Ok(o)
}

/// What one render measured (written as `<stem>.json` and printed).
struct Summary {
    samples: usize,
    peak: f32,
    nonfinite: usize,
    key: u8,
    model: String,
    sim_rate: f64,
    polyphony: usize,
    latency: u32,
    worker_builds: u64,
    refused: u64,
    diverged: u64,
    newton_cap_hits: u64,
    active_at_end: usize,
    build_seconds: f64,
    render_seconds: f64,
}

/// Waits until the worker has handed over a bank for the preset now in `params`: polls the
/// handle's status, processes one silent block per finished build (the audio thread swaps
/// banks at a chunk boundary) and stops when the bank in use has the preset's model and
/// polyphony. Returns the number of silent blocks processed.
fn wait_for_bank(
    engine: &mut Engine,
    handle: &EngineHandle,
    params: &SharedParams,
    timeout: Duration,
) -> Result<usize, String> {
    let start = Instant::now();
    let v = params.snapshot();
    let (want_model, want_poly) = (v.model(), v.index_of(ParamId::Polyphony));
    let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
    let first_id = engine.bank_id();
    let mut seen = 0u64;
    let mut silent_blocks = 0;
    loop {
        while handle.banks_built() <= seen || handle.is_rebuilding() {
            if let Some(e) = handle.last_error() {
                return Err(format!("the worker refused the preset: {e}"));
            }
            if start.elapsed() > timeout {
                return Err(format!(
                    "no bank from the worker within {:.0} s (builds so far: {}, rebuilding: {})",
                    timeout.as_secs_f64(),
                    handle.banks_built(),
                    handle.is_rebuilding()
                ));
            }
            std::thread::sleep(POLL);
        }
        seen = handle.banks_built();
        engine.process(&mut l, &mut r);
        silent_blocks += 1;
        if l.iter().chain(r.iter()).any(|&x| x != 0.0) {
            return Err("a block before the note was not silent".into());
        }
        if engine.bank_id() != first_id
            && engine.model() == Some(want_model)
            && engine.polyphony() == want_poly
        {
            return Ok(silent_blocks);
        }
        // A bank for a half-written parameter set (the worker polled during `apply`): the
        // worker builds again for the final values.
        eprintln!(
            "  note: bank {} does not match the preset yet (model {:?}, polyphony {}); waiting",
            engine.bank_id(),
            engine.model(),
            engine.polyphony()
        );
    }
}

/// Renders one preset into `out/<stem>.wav` and `out/<stem>.json`.
fn render(stem: &str, preset: &Preset, o: &Options) -> Result<Summary, String> {
    let values = preset.values().map_err(|e| e.to_string())?;
    let params = Arc::new(SharedParams::new());
    let (mut engine, handle) = Engine::new(params.clone());
    let t0 = Instant::now();
    let mut silent_blocks = 0;
    if o.load_before_activate {
        preset.apply(&params).map_err(|e| e.to_string())?;
        engine
            .activate(HOST_RATE, BLOCK)
            .map_err(|e| format!("activate: {e}"))?;
    } else {
        engine
            .activate(HOST_RATE, BLOCK)
            .map_err(|e| format!("activate: {e}"))?;
        let before = params.snapshot().rebuild_key();
        preset.apply(&params).map_err(|e| e.to_string())?;
        if params.snapshot().rebuild_key() != before {
            let timeout = Duration::from_secs_f64(o.build_timeout);
            silent_blocks = wait_for_bank(&mut engine, &handle, &params, timeout)?;
        }
    }
    let worker_builds = handle.banks_built();
    // Offline: wait for the voice pool's workers as long as it takes (a late job would leave
    // a voice's chunk out and make renders differ between runs; one note uses one voice, so
    // the pool is idle here anyway).
    engine.set_job_wait(Some(Duration::from_secs(10)));
    // Exactly one silent block before the note on both paths (the editor path needs it for
    // the bank swap), so that they start from the same resampler phase and frame count.
    if silent_blocks == 0 {
        let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
        engine.process(&mut l, &mut r);
    }
    let build_seconds = t0.elapsed().as_secs_f64();

    let key = values.index_of(ParamId::RootKey).min(127) as u8;
    let total = (o.seconds * HOST_RATE).round() as usize;
    let off_at = (o.hold * HOST_RATE).round() as usize;
    let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
    let (mut left, mut right) = (Vec::with_capacity(total), Vec::with_capacity(total));
    let t1 = Instant::now();
    engine.note_on(key, VELOCITY);
    let mut pos = 0;
    while pos < total {
        let n = BLOCK.min(total - pos);
        let mut events = Vec::new();
        if (pos..pos + n).contains(&off_at) {
            events.push(Event::new(
                (off_at - pos) as u32,
                EventKind::NoteOff { key },
            ));
        }
        engine.process_events(&events, &mut l[..n], &mut r[..n]);
        left.extend_from_slice(&l[..n]);
        right.extend_from_slice(&r[..n]);
        pos += n;
    }
    let render_seconds = t1.elapsed().as_secs_f64();

    let all = left.iter().chain(right.iter());
    let summary = Summary {
        samples: total,
        peak: all.clone().fold(0.0f32, |m, x| m.max(x.abs())),
        nonfinite: all.filter(|x| !x.is_finite()).count(),
        key,
        model: engine.model().map_or("none", |m| m.key()).to_string(),
        sim_rate: engine.sim_rate().unwrap_or(0.0),
        polyphony: engine.polyphony(),
        latency: engine.latency_samples(),
        worker_builds,
        refused: engine.refused_notes(),
        diverged: engine.diverged_voices(),
        newton_cap_hits: engine.newton_cap_hits(),
        active_at_end: engine.active_voices(),
        build_seconds,
        render_seconds,
    };
    drop(engine); // stops and joins the worker
    write_wav(&o.out.join(format!("{stem}.wav")), &left, &right)?;
    write_json(&o.out.join(format!("{stem}.json")), stem, &summary)?;
    Ok(summary)
}

fn write_wav(path: &Path, left: &[f32], right: &[f32]) -> Result<(), String> {
    let spec = hound::WavSpec {
        channels: 2,
        sample_rate: HOST_RATE as u32,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let ctx = |e: hound::Error| format!("writing {}: {e}", path.display());
    let mut w = hound::WavWriter::create(path, spec).map_err(ctx)?;
    for (&a, &b) in left.iter().zip(right) {
        w.write_sample(a).map_err(ctx)?;
        w.write_sample(b).map_err(ctx)?;
    }
    w.finalize().map_err(ctx)
}

fn write_json(path: &Path, stem: &str, s: &Summary) -> Result<(), String> {
    let j = serde_json::json!({
        "preset": stem,
        "host_rate": HOST_RATE,
        "block": BLOCK,
        "samples": s.samples,
        "key": s.key,
        "velocity": VELOCITY,
        "peak": s.peak,
        "nan_count": s.nonfinite,
        "model": s.model,
        "sim_rate": s.sim_rate,
        "polyphony": s.polyphony,
        "latency_samples": s.latency,
        "worker_builds": s.worker_builds,
        "refused_notes": s.refused,
        "diverged_voices": s.diverged,
        "newton_cap_hits": s.newton_cap_hits,
        "active_voices_at_end": s.active_at_end,
        "build_seconds": s.build_seconds,
        "wall_seconds": s.render_seconds,
    });
    let text = serde_json::to_string_pretty(&j).map_err(|e| e.to_string())?;
    std::fs::write(path, text + "\n").map_err(|e| format!("writing {}: {e}", path.display()))
}

/// The presets to render: `(stem, preset)` from the files given, else the embedded factory set.
fn presets(files: &[PathBuf]) -> Vec<(String, Result<Preset, String>)> {
    if files.is_empty() {
        return Preset::factory()
            .into_iter()
            .map(|(stem, p)| (stem.to_string(), Ok(p)))
            .collect();
    }
    files
        .iter()
        .map(|f| {
            let stem = f
                .file_stem()
                .map_or_else(|| f.display().to_string(), |s| s.to_string_lossy().into());
            let p = Preset::load(f).map_err(|e| e.to_string());
            if let Ok(p) = &p {
                match Preset::factory_named(&stem) {
                    Some(embedded) if embedded != *p => eprintln!(
                        "warning: {} differs from the embedded factory preset `{stem}` \
                         (rendering the file)",
                        f.display()
                    ),
                    None => eprintln!("note: {} is not an embedded factory preset", f.display()),
                    _ => {}
                }
            }
            (stem, p)
        })
        .collect()
}

fn main() -> ExitCode {
    let o = match parse_args() {
        Ok(o) => o,
        Err(e) if e.is_empty() => {
            println!("{USAGE}");
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            eprintln!("error: {e}\n{USAGE}");
            return ExitCode::from(2);
        }
    };
    if let Err(e) = std::fs::create_dir_all(&o.out) {
        eprintln!("error: creating {}: {e}", o.out.display());
        return ExitCode::FAILURE;
    }
    let list = presets(&o.files);
    if list.is_empty() {
        eprintln!("error: no preset to render");
        return ExitCode::FAILURE;
    }
    let mut failed = 0;
    for (stem, p) in list {
        match p.and_then(|p| render(&stem, &p, &o)) {
            Ok(s) => println!(
                "{stem}: {} samples, key {}, {} at {} Hz x{} voices, peak {:.6e}, \
                 build {:.2} s, render {:.2} s{}",
                s.samples,
                s.key,
                s.model,
                s.sim_rate,
                s.polyphony,
                s.peak,
                s.build_seconds,
                s.render_seconds,
                if s.nonfinite > 0 {
                    format!(", {} NON-FINITE samples", s.nonfinite)
                } else {
                    String::new()
                }
            ),
            Err(e) => {
                eprintln!("{stem}: error: {e}");
                failed += 1;
            }
        }
    }
    if failed > 0 {
        eprintln!("{failed} preset(s) failed");
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}
