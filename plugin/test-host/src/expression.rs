//! `expression PLUGIN.clap STATE [--out DIR] [--break WHAT]`: per-note expressions measured
//! from the plugin's sound, through the CLAP host.
//!
//! `STATE` is a state blob of the ideal (B = 0) sitar string with its bridge out of reach
//! (`plugin/ci/expressions.sh` writes it from `assets/presets/sitar-b0.toml` with bridge
//! curvature 1 /m over 1 % of the length, polyphony 2, output gain -12 dB, threads 1: the
//! voice pool's late jobs would make an offline render on a loaded machine differ from run to
//! run, see the script): a harmonic string
//! whose fundamental has the closed form `f₁ = √(T/μ) / 2L` = 196.39 Hz at its root key 55
//! (T = 180.5 N, μ = 1.17e-3 kg/m, L = 1 m), the control of the engine's pitch tests
//! (tests/engine/pitch_from_sound.rs). The default gong's partials are inharmonic and closer
//! together than a band mask can separate for two notes, so it cannot tell two pitches apart.
//!
//! Cases (each a 2 s render at 48 kHz in 256-frame blocks, all events at frame 0):
//! - `clap tuning`: CLAP note-ons for keys 55 and 62, then CLAP tuning expressions +0.37 and
//!   -1.25 semitones: each note's fundamental must be `f₁ · 2^((key - 55 + tuning) / 12)`;
//! - `clap volume`: the same with a CLAP volume expression of 0.5 on key 62: its fundamental's
//!   level must be 0.5 of the `clap tuning` render's, key 55's unchanged (1);
//! - `mpe`: raw MIDI: the MPE Configuration Message (lower zone, 15 member channels), a bend
//!   on channel 2 before its note-on (key 55), a note-on on channel 3 (key 62) and a bend on
//!   channel 3 after it, and a bend on the master channel 1: each note's fundamental must carry
//!   its channel's bend × 48 semitones plus the master's bend × the plugin's global range
//!   (2 semitones).
//!
//! Estimator (as the engine's tests): the fundamental isolated by an FFT band mask of ±40 Hz
//! on the Hann-windowed left channel, its period from upward zero crossings on the middle
//! 80 % (`noether_core::analysis::frequency::measure`); level: RMS of the masked signal.
//! Tolerances: pitch 1e-5 relative (0.017 cent; measured 2e-9 to 7e-9, as the engine alone),
//! far below the smallest slip these
//! cases would show (the tuning left out: 2e-2; MPE's bend range taken as the global 2
//! semitones: 1.2e-2; 14-bit centre error 1/16383 of 48 semitones: 1.7e-4); level 1e-3
//! (the engine's volume test; a volume left out is off by 0.5).
//!
//! - `clap poly modulation`, `clap pressure`, `note ends` and `per-note flags`: `polymod.rs`.
//!
//! `--break WHAT` leaves something out of what the host sends, and the checks must then fail
//! (CI runs each): `tuning` (no CLAP tuning), `volume` (no CLAP volume), `mpe-config` (no MPE
//! Configuration Message: every bend is the global one), `member-bend` (no member-channel
//! bend), `poly-mod` (no polyphonic modulation), `note-off` (no note-offs: no note may end),
//! `pressure` (no CLAP pressure).
//!
//! Threads: the test host's main thread plays both the main and the audio thread.

use clack_host::events::event_types::{
    MidiEvent, NoteExpressionEvent, NoteExpressionType, NoteOnEvent,
};
use clack_host::prelude::*;
use noether_core::analysis::frequency::measure;
use rustfft::{num_complex::Complex, FftPlanner};
use std::f64::consts::PI;
use std::path::PathBuf;

use crate::args::path_arg;
use crate::conform_render::Session;
use crate::expression_setup::{started, Break, BLOCK, RATE};
use crate::host::process_stereo;

/// Length of each render (s).
const SECONDS: f64 = 2.0;
/// Half-width of the band mask (Hz): the string's partials are 196 Hz apart, the two notes'
/// fundamentals more than 60 Hz.
const HALF_BAND: f64 = 40.0;
/// Pitch tolerance (relative); see the module doc.
const PITCH_TOL: f64 = 1e-5;
/// Level tolerance (ratio); see the module doc.
const LEVEL_TOL: f64 = 1e-3;
/// Root key of the state's string (G3).
const ROOT_KEY: u8 = 55;
/// MPE's default member-channel bend range (semitones).
const MPE_RANGE: f64 = 48.0;
/// The plugin's default global pitch-bend range (semitones; `pitch_bend_range`).
const GLOBAL_RANGE: f64 = 2.0;

/// The closed-form fundamental of the state's string at its root key (Hz).
fn f1() -> f64 {
    (180.5f64 / 1.17e-3).sqrt() / 2.0
}

/// Options of `expression`.
#[derive(Debug, Clone)]
pub struct ExpressionOptions {
    /// The `.clap` file under test.
    pub plugin: PathBuf,
    /// The state blob loaded before each render.
    pub state: PathBuf,
    /// Directory for the renders' WAV files (none written without it).
    pub out: Option<PathBuf>,
    /// What to leave out (a deliberately broken input).
    pub broken: Option<Break>,
}

impl ExpressionOptions {
    /// Parses `PLUGIN STATE [--out DIR] [--break tuning|volume|mpe-config|member-bend]`.
    pub fn parse(args: &[String]) -> Result<Self, String> {
        let mut it = args.iter();
        let plugin = path_arg("PLUGIN.clap", it.next())?;
        let state = path_arg("STATE", it.next())?;
        let mut o = Self {
            plugin,
            state,
            out: None,
            broken: None,
        };
        while let Some(flag) = it.next() {
            match flag.as_str() {
                "--out" => o.out = Some(path_arg("--out DIR", it.next())?),
                "--break" => {
                    let what = it.next().ok_or("--break needs WHAT")?;
                    o.broken = Some(match what.as_str() {
                        "tuning" => Break::Tuning,
                        "volume" => Break::Volume,
                        "mpe-config" => Break::MpeConfig,
                        "member-bend" => Break::MemberBend,
                        "poly-mod" => Break::PolyMod,
                        "note-off" => Break::NoteOff,
                        "pressure" => Break::Pressure,
                        other => {
                            return Err(format!(
                            "--break: `{other}` is none of tuning, volume, mpe-config, member-bend, poly-mod, note-off, pressure"
                        ))
                        }
                    });
                }
                other => return Err(format!("unknown option `{other}`")),
            }
        }
        Ok(o)
    }
}

/// A CLAP note target on port 0, channel `ch`, key `key` (note id: the key).
fn pckn(ch: u16, key: u8) -> Pckn {
    Pckn::new(0u16, ch, u16::from(key), u32::from(key))
}

/// A MIDI 1.0 pitch bend on `channel` (0-based) with 14-bit value `raw`.
fn bend(channel: u8, raw: u16) -> MidiEvent {
    MidiEvent::new(0, 0, [0xE0 | channel, (raw & 0x7f) as u8, (raw >> 7) as u8])
}

/// A bend's value in `[-1, 1]` by MIDI 1.0 (8192 is the centre; 8192 below, 8191 above).
fn bend_value(raw: u16) -> f64 {
    let v = f64::from(raw) - 8192.0;
    v / if v < 0.0 { 8192.0 } else { 8191.0 }
}

/// Renders `SECONDS` of a fresh instance with `blob` loaded and `events` at frame 0; returns
/// the left channel.
fn render(s: &Session, blob: &[u8], events: &EventBuffer) -> Result<Vec<f64>, String> {
    let (mut inst, mut proc) = started(s, blob)?;
    let total = (SECONDS * RATE) as usize;
    let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
    let (mut ports, mut out_buf, empty) = (
        AudioPorts::with_capacity(2, 1),
        EventBuffer::new(),
        EventBuffer::new(),
    );
    let mut out = Vec::with_capacity(total);
    while out.len() < total {
        let n = BLOCK.min(total - out.len());
        let ev = if out.is_empty() { events } else { &empty };
        let pos = out.len() as u64;
        process_stereo(
            &mut proc,
            &mut ports,
            ev,
            &mut out_buf,
            [&mut l[..n], &mut r[..n]],
            pos,
        )
        .map_err(|e| format!("process at frame {pos}: {e}"))?;
        out.extend(l[..n].iter().map(|&x| f64::from(x)));
    }
    inst.deactivate(proc.stop_processing());
    if let Some(bad) = out.iter().position(|x| !x.is_finite() || x.abs() > 1.0) {
        return Err(format!(
            "sample {bad} is {} (not finite or above 0 dBFS)",
            out[bad]
        ));
    }
    Ok(out)
}

/// `x`, Hann-windowed, with only its spectrum within [`HALF_BAND`] of `f` kept.
fn band(x: &[f64], f: f64) -> Vec<f64> {
    let n = x.len();
    let hann = |k: usize| 0.5 - 0.5 * (2.0 * PI * k as f64 / n as f64).cos();
    let mut buf: Vec<Complex<f64>> = x
        .iter()
        .enumerate()
        .map(|(k, &v)| Complex::new(v * hann(k), 0.0))
        .collect();
    let mut planner = FftPlanner::new();
    planner.plan_fft_forward(n).process(&mut buf);
    for (k, b) in buf.iter_mut().enumerate() {
        if ((k.min(n - k) as f64 * RATE / n as f64) - f).abs() > HALF_BAND {
            *b = Complex::new(0.0, 0.0);
        }
    }
    planner.plan_fft_inverse(n).process(&mut buf);
    buf.iter().map(|c| c.re / n as f64).collect()
}

/// The fundamental (Hz) of `x` near `f`: zero crossings of the masked middle 80 %.
fn fundamental(x: &[f64], f: f64) -> Result<f64, String> {
    let y = band(x, f);
    let n = y.len();
    measure(&y[n / 10..n - n / 10], 1.0 / RATE)
        .map(|m| m.omega / (2.0 * PI))
        .ok_or_else(|| format!("no oscillation within {HALF_BAND} Hz of {f:.3} Hz"))
}

/// RMS of the fundamental near `f`.
fn level(x: &[f64], f: f64) -> f64 {
    let y = band(x, f);
    (y.iter().map(|v| v * v).sum::<f64>() / y.len() as f64).sqrt()
}

/// Checks each note's fundamental: `(what, key, tuning in semitones)`; returns the figures
/// (every note's, also when one fails).
fn pitches(x: &[f64], notes: &[(&str, u8, f64)]) -> Result<String, String> {
    let mut figures = Vec::new();
    let mut ok = true;
    for &(what, key, tuning) in notes {
        let want = f1() * ((f64::from(key) - f64::from(ROOT_KEY) + tuning) / 12.0).exp2();
        let got = fundamental(x, want)?;
        let rel = got / want - 1.0;
        ok &= rel.abs() < PITCH_TOL;
        figures.push(format!(
            "{what}: {got:.5} Hz, expected {want:.5} Hz, relative {rel:+.1e}"
        ));
    }
    let figures = figures.join("; ");
    if ok {
        Ok(figures)
    } else {
        Err(format!("{figures} (tolerance {PITCH_TOL:.0e})"))
    }
}

/// Writes `x` (mono) to `DIR/name.wav` if `--out` was given.
fn save(o: &ExpressionOptions, name: &str, x: &[f64]) -> Result<(), String> {
    let Some(dir) = &o.out else { return Ok(()) };
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let path = dir.join(format!("{name}.wav"));
    let spec = hound::WavSpec {
        channels: 1,
        sample_rate: RATE as u32,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let mut w = hound::WavWriter::create(&path, spec).map_err(|e| format!("{e}"))?;
    for &v in x {
        w.write_sample(v as f32).map_err(|e| format!("{e}"))?;
    }
    w.finalize().map_err(|e| format!("{e}"))
}

/// The CLAP case's events: two note-ons, their tunings, and key 62's volume if given.
fn clap_events(o: &ExpressionOptions, volume: Option<f64>) -> EventBuffer {
    let mut ev = EventBuffer::new();
    for key in [55, 62] {
        ev.push(&NoteOnEvent::new(0, pckn(0, key), 1.0));
    }
    if o.broken != Some(Break::Tuning) {
        for (key, t) in [(55, 0.37), (62, -1.25)] {
            ev.push(&NoteExpressionEvent::new(
                0,
                pckn(0, key),
                NoteExpressionType::Tuning,
                t,
            ));
        }
    }
    if let Some(v) = volume.filter(|_| o.broken != Some(Break::Volume)) {
        ev.push(&NoteExpressionEvent::new(
            0,
            pckn(0, 62),
            NoteExpressionType::Volume,
            v,
        ));
    }
    ev
}

/// Bends of the MPE case (14-bit): channel 2 (before its note), channel 3 (after its note),
/// master channel 1.
const MPE_BENDS: [u16; 3] = [8192 + 63, 7936, 12288];

/// The MPE case's events (see the module doc).
fn mpe_events(o: &ExpressionOptions) -> EventBuffer {
    let mut ev = EventBuffer::new();
    let midi = |b: [u8; 3]| MidiEvent::new(0, 0, b);
    if o.broken != Some(Break::MpeConfig) {
        // RPN 6 (MPE Configuration Message) on channel 1: 15 member channels.
        for b in [[0xB0, 101, 0], [0xB0, 100, 6], [0xB0, 6, 15]] {
            ev.push(&midi(b));
        }
    }
    let member_bends = o.broken != Some(Break::MemberBend);
    if member_bends {
        ev.push(&bend(1, MPE_BENDS[0]));
    }
    ev.push(&midi([0x91, 55, 127]));
    ev.push(&midi([0x92, 62, 127]));
    if member_bends {
        ev.push(&bend(2, MPE_BENDS[1]));
    }
    ev.push(&bend(0, MPE_BENDS[2]));
    ev
}

/// `expression`: runs the three cases; fails if any fails.
pub fn expression(o: &ExpressionOptions) -> Result<(), String> {
    let s = Session::load(&o.plugin)?;
    let blob = std::fs::read(&o.state).map_err(|e| format!("{}: {e}", o.state.display()))?;
    if let Some(b) = o.broken {
        println!("deliberately broken input: {b:?} left out");
    }
    let mut failed = Vec::new();
    let mut report = |name: &str, r: Result<String, String>| match r {
        Ok(f) => println!("PASS {name}: {f}"),
        Err(e) => {
            println!("FAIL {name}: {e}");
            failed.push(name.to_string());
        }
    };
    let plain = render(&s, &blob, &clap_events(o, None))?;
    save(o, "clap-tuning", &plain)?;
    let notes = [("key 55 +0.37", 55, 0.37), ("key 62 -1.25", 62, -1.25)];
    report("clap tuning", pitches(&plain, &notes));

    let soft = render(&s, &blob, &clap_events(o, Some(0.5)))?;
    save(o, "clap-volume", &soft)?;
    report("clap volume", {
        let ratio = |key: u8, t: f64| {
            let f = f1() * ((f64::from(key) - f64::from(ROOT_KEY) + t) / 12.0).exp2();
            level(&soft, f) / level(&plain, f)
        };
        let (r62, r55) = (ratio(62, -1.25), ratio(55, 0.37));
        let line = format!("key 62 (volume 0.5) x{r62:.6}, key 55 x{r55:.6}");
        if (r62 - 0.5).abs() < LEVEL_TOL && (r55 - 1.0).abs() < LEVEL_TOL {
            Ok(line)
        } else {
            Err(format!(
                "{line} (expected 0.5 and 1 within {LEVEL_TOL:.0e})"
            ))
        }
    });

    let x = render(&s, &blob, &mpe_events(o))?;
    save(o, "mpe", &x)?;
    let global = bend_value(MPE_BENDS[2]) * GLOBAL_RANGE;
    let t2 = bend_value(MPE_BENDS[0]) * MPE_RANGE + global;
    let t3 = bend_value(MPE_BENDS[1]) * MPE_RANGE + global;
    let (w2, w3) = (
        format!("channel 2 key 55 {t2:+.5}"),
        format!("channel 3 key 62 {t3:+.5}"),
    );
    report("mpe", pitches(&x, &[(&w2, 55, t2), (&w3, 62, t3)]));
    crate::polymod::poly_cases(&s, &blob, o.broken, f1(), &mut report)?;
    if failed.is_empty() {
        Ok(())
    } else {
        Err(format!("expression cases failed: {}", failed.join(", ")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The estimator on two synthetic notes 196.4 Hz and 268.9 Hz apart, each with a louder
    /// second partial: both fundamentals to 1e-7 relative, far inside [`PITCH_TOL`].
    #[test]
    fn two_notes_are_told_apart() {
        let (a, b) = (196.4, 268.9);
        let x: Vec<f64> = (0..(SECONDS * RATE) as usize)
            .map(|k| {
                let t = k as f64 / RATE;
                let s = |f: f64| (2.0 * PI * f * t).sin() + 2.0 * (4.0 * PI * f * t + 0.3).sin();
                s(a) + 0.5 * s(b)
            })
            .collect();
        for f in [a, b] {
            let got = fundamental(&x, f + 3.0).unwrap();
            assert!((got / f - 1.0).abs() < 1e-7, "{got} vs {f}");
        }
        let ratio = level(&x, b) / level(&x, a);
        assert!((ratio - 0.5).abs() < 1e-4, "{ratio}");
    }

    #[test]
    fn bend_values_follow_midi() {
        assert_eq!(bend_value(8192), 0.0);
        assert_eq!(bend_value(0), -1.0);
        assert_eq!(bend_value(16383), 1.0);
        assert_eq!(bend_value(7936) * MPE_RANGE, -1.5);
    }
}
