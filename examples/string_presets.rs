//! The factory string presets as the instrument plays them: contact, brightness over time,
//! velocity-dependent timbre, and the CPU of one voice.
//!
//! `cargo run --release --example string_presets -- STEM [key=value ...] [--cpu-seconds S]`,
//! for example `cargo run --release --example string_presets -- sitar modes=200
//! sim_rate=192000`. `key=value` pairs override engine parameters of the preset (as
//! `noether accuracy --preset --set`). One voice, 48 kHz host rate, through the public
//! `noether::engine` API (bank, voice, resampler: what the plugin runs; `threads = 1`, so the
//! voice runs on the calling thread). For the keys
//! root - 12, root and root + 12 at velocities 40 and 127 (0.315 and 1.0) it prints:
//!
//! - the contact energy share: the largest `nonlinear / total` of the voice's energy terms,
//!   sampled every 16 host samples over the first 0.3 s, and the fraction of those samples with
//!   a non-zero contact energy (0 for a string that never touches its bridge);
//! - the spectral centroid of the left output (Hz) over six 50 ms windows of the first 0.3 s
//!   ([`spectral_centroid`], Hann window over each 50 ms): after the pluck's attack (first window)
//!   a buzzing sitar's rises, a plain plucked string's falls (its high partials decay first);
//! - for each key, the velocity timbre distance: the log-spectral distance (dB) between the
//!   velocity-127 render and the velocity-40 render scaled by 127/40 (0 dB for a linear string,
//!   whose spectrum only scales with the pluck);
//!
//! and, with `--cpu-seconds S` (default 2, 0 to skip), the thread CPU time
//! (`CLOCK_THREAD_CPUTIME_ID`, immune to other load on the shared machine) of rendering the
//! first S seconds after a velocity-127 note at each key, in 256-sample blocks, as a
//! percentage of one core (100 % = S seconds of CPU).

use noether::engine::{Engine, ParamId, Preset, SharedParams};
use noether::render::metrics::log_spectral_distance;
use noether::render::preset_accuracy::with_overrides;
use noether::render::report::spectral_centroid;
use std::sync::Arc;
use std::time::Duration;

/// Host rate (Hz).
const RATE: f64 = 48_000.0;

/// CPU time consumed by the calling thread so far (`noether::clock`).
fn thread_cpu_time() -> Duration {
    noether::clock::thread_cpu_time().expect("the thread CPU clock (Unix)")
}

/// A fresh one-voice engine playing `preset` at [`RATE`] with blocks up to `block`.
fn engine(preset: &Preset, block: usize) -> Engine {
    let params = Arc::new(SharedParams::new());
    preset.apply(&params).expect("preset");
    params.set(ParamId::Polyphony, 1.0).expect("polyphony");
    // The voice runs on the calling thread, whose CPU time is measured.
    params.set(ParamId::Threads, 1.0).expect("threads");
    let (mut e, _h) = Engine::new(params);
    e.activate(RATE, block).expect("activate");
    e
}

/// One note: the left output over `seconds`, the largest contact energy share and the
/// fraction of energy samples in contact (sampled every `block` host samples).
struct Note {
    left: Vec<f64>,
    share_max: f64,
    in_contact: f64,
}

fn play(preset: &Preset, key: u8, velocity: f32, seconds: f64) -> Note {
    const BLOCK: usize = 16;
    let mut e = engine(preset, BLOCK);
    e.note_on(key, velocity);
    let n = (seconds * RATE) as usize;
    let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
    let mut left = Vec::with_capacity(n);
    let (mut share_max, mut touching, mut samples) = (0.0f64, 0usize, 0usize);
    while left.len() < n {
        e.process(&mut l, &mut r);
        left.extend(l.iter().map(|&x| f64::from(x)));
        if let Some(t) = e.voice_energy(0) {
            samples += 1;
            if t.nonlinear > 0.0 {
                touching += 1;
                share_max = share_max.max(t.nonlinear / t.total());
            }
        }
    }
    left.truncate(n);
    Note {
        left,
        share_max,
        in_contact: touching as f64 / samples.max(1) as f64,
    }
}

fn main() {
    let mut args = std::env::args().skip(1);
    let stem = args
        .next()
        .expect("usage: string_presets STEM [key=value ...]");
    let (mut sets, mut cpu_seconds) = (Vec::new(), 2.0);
    while let Some(a) = args.next() {
        if a == "--cpu-seconds" {
            cpu_seconds = args.next().and_then(|s| s.parse().ok()).expect("seconds");
        } else {
            sets.push(a);
        }
    }
    let preset = with_overrides(&Preset::factory_named(&stem).expect("preset stem"), &sets)
        .expect("overrides");
    let v = preset.values().expect("values");
    let root = v.get(ParamId::RootKey) as u8;
    println!(
        "{stem} {}: modes {}, sim rate {} Hz",
        sets.join(" "),
        v.index_of(ParamId::Modes),
        v.get(ParamId::SimRate)
    );
    let win = (0.05 * RATE) as usize;
    for key in [root - 12, root, root + 12] {
        let mut notes = Vec::new();
        for vel in [40u8, 127] {
            let note = play(&preset, key, f32::from(vel) / 127.0, 0.3);
            let cents: Vec<String> = note
                .left
                .chunks(win)
                .map(|w| format!("{:.0}", spectral_centroid(w, RATE).unwrap_or(0.0)))
                .collect();
            println!(
                "key {key} vel {vel:3}: contact share max {:.3e}, in contact {:5.1} % of samples, centroid per 50 ms (Hz) {}",
                note.share_max,
                100.0 * note.in_contact,
                cents.join(" ")
            );
            notes.push(note);
        }
        let scaled: Vec<f64> = notes[0].left.iter().map(|x| x * 127.0 / 40.0).collect();
        println!(
            "key {key}: velocity timbre distance (LSD, 127 vs 40 scaled) {:.2} dB",
            log_spectral_distance(&notes[1].left, &scaled)
        );
    }
    if cpu_seconds > 0.0 {
        for key in [root - 12, root, root + 12] {
            let mut e = engine(&preset, 256);
            let (mut l, mut r) = (vec![0.0f32; 256], vec![0.0f32; 256]);
            e.note_on(key, 1.0);
            let blocks = (cpu_seconds * RATE / 256.0).ceil() as usize;
            let t0 = thread_cpu_time();
            for _ in 0..blocks {
                e.process(&mut l, &mut r);
            }
            let cpu = (thread_cpu_time() - t0).as_secs_f64();
            let audio = blocks as f64 * 256.0 / RATE;
            println!(
                "key {key} vel 127: CPU {:.1} % of one core ({cpu:.3} s thread CPU for {audio:.2} s of audio)",
                100.0 * cpu / audio
            );
        }
    }
}
