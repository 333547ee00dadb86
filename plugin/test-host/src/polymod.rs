//! The `expression` command's polyphonic-modulation and note-end case: CLAP
//! `CLAP_EVENT_PARAM_MOD` events addressed to one of two overlapping notes (by note id), and
//! the plugin's `CLAP_EVENT_NOTE_END` events, measured through the CLAP host.
//!
//! Case (the `expression` state: the ideal string with its bridge out of reach, see
//! `expression.rs`): note ids 55 and 62 on keys 55 and 62 at frame 0; the per-note
//! parameters must be flagged `CLAP_PARAM_IS_MODULATABLE_PER_NOTE_ID`; a modulation of
//! `Damping` (the `damping_scale` multiplier, a continuous parameter the host sees as
//! normalised [0, 1] over 0 to 20) by +[`OFFSET`] on note 62 only. The string's modes decay
//! at `σ_j = damping_scale · σ_j⁰` (the loss law scales linearly, `docs/models.md`), so
//! note 62's fundamental must decay [`RATE_RATIO`] times as fast as in the render without the
//! modulation and note 55's at the same rate. Decay rate: the fundamental's amplitude from a
//! Hann-windowed 0.2 s single-frequency DFT (its 5 Hz main lobe is far from the next partial,
//! 196 Hz away) at 0.4 s and 1.4 s, `σ = ln(a(0.4) / a(1.4)) / 1 s`. Both notes ring linearly
//! (no contact), so the amplitude is exactly exponential up to the other note's leakage;
//! tolerance 1 % on the ratio (a modulation left out gives a ratio of 1, off by 2).
//! Then both notes are released (note-offs at 2 s, the state's release T60 is 0.1 s) and
//! within 1 s after it the plugin must report a note end for each note id, and none before.
//!
//! `clap pressure`: the same two notes with a CLAP pressure expression of [`PRESSURE`] on
//! key 62 only: the player's hand rests on that string (an energy-accounted damper whose exact
//! decay the engine's tests check), so note 62 must decay at least [`PRESSURE_MIN_RATIO`]
//! times as fast as without it and note 55 at the same rate (1 %).
//!
//! Threads: the test host's main thread plays both the main and the audio thread.

use clack_extensions::params::{ParamInfoBuffer, ParamInfoFlags, PluginParams};
use clack_host::events::event_types::{
    NoteEndEvent, NoteExpressionEvent, NoteExpressionType, NoteOffEvent, NoteOnEvent, ParamModEvent,
};
use clack_host::events::Match;
use clack_host::prelude::*;
use std::f64::consts::PI;

use crate::conform_render::Session;
use crate::expression_setup::{started, Break, BLOCK, RATE};
use crate::host::process_stereo;

/// Note-offs at this time (s); the render ends 1 s later.
const RELEASE_AT: f64 = 2.0;
/// The normalised offset sent on note 62's damping (+2 on the 0-20 range).
const OFFSET: f64 = 0.1;
/// The state's damping multiplier (`sitar-b0`'s `damping_scale`).
const BASE_DAMPING: f64 = 1.0;
/// Expected ratio of note 62's decay rate with and without the modulation.
const RATE_RATIO: f64 = (BASE_DAMPING + 20.0 * OFFSET) / BASE_DAMPING;
/// Tolerance on the rate ratios (relative).
const RATIO_TOL: f64 = 1e-2;
/// The CLAP pressure sent on key 62 (a light touch: at full pressure the fundamental dies
/// 60 dB in 0.15 s, too fast to measure a rate between 0.4 s and 1.4 s).
const PRESSURE: f64 = 0.02;
/// Least ratio of note 62's decay rate with and without the pressure (a 0.02 touch adds
/// about 0.02 · ln(1000) / 0.15 s ≈ 0.9 /s to its fundamental's 0.4 /s).
const PRESSURE_MIN_RATIO: f64 = 2.0;
/// The parameters the plugin must let a host modulate per note (display names).
const PER_NOTE: [&str; 6] = [
    "Strike position",
    "Pluck position",
    "Mallet hardness",
    "Damping",
    "Left pickup position",
    "Right pickup position",
];

/// What a render gives back: the left channel and the note ends `(note id, frame)`.
struct Played {
    left: Vec<f64>,
    ends: Vec<(u32, usize)>,
}

/// Renders the two notes (with the modulation if `modulate`), their release, and collects
/// the plugin's note ends.
fn play(
    s: &Session,
    blob: &[u8],
    modulate: bool,
    release: bool,
    pressure: bool,
) -> Result<Played, String> {
    let damping = &s.params[s.index_of("Damping")?];
    let (mut inst, mut proc) = started(s, blob)?;
    let note = |key: u8| Pckn::new(0u16, 0u16, u16::from(key), u32::from(key));
    let mut start = EventBuffer::new();
    for key in [55, 62] {
        start.push(&NoteOnEvent::new(0, note(key), 1.0));
    }
    if modulate {
        start.push(&ParamModEvent::new(0, damping.id, note(62), OFFSET));
    }
    if pressure {
        start.push(&NoteExpressionEvent::new(
            0,
            note(62),
            NoteExpressionType::Pressure,
            PRESSURE,
        ));
    }
    let mut offs = EventBuffer::new();
    for key in [55, 62] {
        offs.push(&NoteOffEvent::new(0, note(key), 0.0));
    }
    let (off_at, total) = (
        (RELEASE_AT * RATE) as usize,
        ((RELEASE_AT + 1.0) * RATE) as usize,
    );
    let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
    let (mut ports, mut out_buf, empty) = (
        AudioPorts::with_capacity(2, 1),
        EventBuffer::new(),
        EventBuffer::new(),
    );
    let mut played = Played {
        left: Vec::with_capacity(total),
        ends: Vec::new(),
    };
    while played.left.len() < total {
        let pos = played.left.len();
        let n = BLOCK
            .min(total - pos)
            .min(if pos < off_at { off_at - pos } else { BLOCK });
        let ev = match pos {
            0 => &start,
            p if p == off_at && release => &offs,
            _ => &empty,
        };
        process_stereo(
            &mut proc,
            &mut ports,
            ev,
            &mut out_buf,
            [&mut l[..n], &mut r[..n]],
            pos as u64,
        )
        .map_err(|e| format!("process at frame {pos}: {e}"))?;
        for e in out_buf.iter() {
            if let Some(end) = e.as_event::<NoteEndEvent>() {
                if let Match::Specific(id) = end.note_id() {
                    played.ends.push((id, pos + end.header().time() as usize));
                }
            }
        }
        played.left.extend(l[..n].iter().map(|&x| f64::from(x)));
    }
    inst.deactivate(proc.stop_processing());
    Ok(played)
}

/// Amplitude of the component at `f` (Hz) of `x` around time `t` (s): a Hann-windowed DFT
/// over 0.2 s.
fn amplitude(x: &[f64], f: f64, t: f64) -> f64 {
    let n = (0.2 * RATE) as usize;
    let start = (t * RATE) as usize - n / 2;
    let (mut re, mut im) = (0.0, 0.0);
    for k in 0..n {
        let w = 0.5 - 0.5 * (2.0 * PI * k as f64 / n as f64).cos();
        let ph = 2.0 * PI * f * (start + k) as f64 / RATE;
        re += w * x[start + k] * ph.cos();
        im += w * x[start + k] * ph.sin();
    }
    (re * re + im * im).sqrt()
}

/// Decay rate (1/s) of the component at `f` between 0.4 s and 1.4 s.
fn decay_rate(x: &[f64], f: f64) -> f64 {
    (amplitude(x, f, 0.4) / amplitude(x, f, 1.4)).ln()
}

/// Whether every per-note parameter carries CLAP's per-note-id modulation flag.
fn per_note_flags(s: &Session) -> Result<String, String> {
    let mut inst = s.instance()?;
    let handle = inst.plugin_handle();
    let params: PluginParams = handle.get_extension().ok_or("no params extension")?;
    let mut buffer = ParamInfoBuffer::new();
    let mut missing = Vec::new();
    for name in PER_NOTE {
        let i = s.index_of(name)?;
        let info = params
            .get_info(&handle, i as u32, &mut buffer)
            .ok_or_else(|| format!("params.get_info({i}) failed"))?;
        if !info
            .flags
            .contains(ParamInfoFlags::IS_MODULATABLE_PER_NOTE_ID)
        {
            missing.push(name);
        }
    }
    if missing.is_empty() {
        Ok(format!(
            "{} parameters modulatable per note id",
            PER_NOTE.len()
        ))
    } else {
        Err(format!(
            "not modulatable per note id: {}",
            missing.join(", ")
        ))
    }
}

/// Runs the case; each check goes to `report` as `(name, result)`.
pub fn poly_cases(
    s: &Session,
    blob: &[u8],
    broken: Option<Break>,
    f1: f64,
    mut report: impl FnMut(&str, Result<String, String>),
) -> Result<(), String> {
    report("per-note flags", per_note_flags(s));
    let plain = play(s, blob, false, true, false)?;
    let modulated = play(
        s,
        blob,
        broken != Some(Break::PolyMod),
        broken != Some(Break::NoteOff),
        false,
    )?;
    let pressed = play(s, blob, false, true, broken != Some(Break::Pressure))?;
    let f = |key: u8| f1 * ((f64::from(key) - 55.0) / 12.0).exp2();
    let ratio = |key: u8| decay_rate(&modulated.left, f(key)) / decay_rate(&plain.left, f(key));
    let (r62, r55) = (ratio(62), ratio(55));
    let line = format!(
        "note 62 decays x{r62:.4} as fast (expected {RATE_RATIO}), note 55 x{r55:.4} (expected 1); \
         plain rates {:.3}/s and {:.3}/s",
        decay_rate(&plain.left, f(62)),
        decay_rate(&plain.left, f(55))
    );
    report(
        "clap poly modulation",
        if (r62 / RATE_RATIO - 1.0).abs() < RATIO_TOL && (r55 - 1.0).abs() < RATIO_TOL {
            Ok(line)
        } else {
            Err(format!("{line} (tolerance {RATIO_TOL:.0e})"))
        },
    );
    let pratio = |key: u8| decay_rate(&pressed.left, f(key)) / decay_rate(&plain.left, f(key));
    let (p62, p55) = (pratio(62), pratio(55));
    let line = format!("note 62 (pressure {PRESSURE}) decays x{p62:.3} as fast, note 55 x{p55:.4}");
    report(
        "clap pressure",
        if p62 > PRESSURE_MIN_RATIO && (p55 - 1.0).abs() < RATIO_TOL {
            Ok(line)
        } else {
            Err(format!(
                "{line} (expected above {PRESSURE_MIN_RATIO} and 1 within {RATIO_TOL:.0e})"
            ))
        },
    );
    let off_at = (RELEASE_AT * RATE) as usize;
    let mut ids: Vec<u32> = modulated.ends.iter().map(|e| e.0).collect();
    ids.sort_unstable();
    let early: Vec<_> = modulated.ends.iter().filter(|e| e.1 < off_at).collect();
    let line = format!("note ends {:?}", modulated.ends);
    report(
        "note ends",
        if ids == [55, 62] && early.is_empty() {
            Ok(line)
        } else {
            Err(format!(
                "{line}: expected one for each of notes 55 and 62, after the release at frame {off_at}"
            ))
        },
    );
    Ok(())
}
