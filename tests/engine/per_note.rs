//! Per-note values: polyphonic modulation ([`EventKind::NoteModulation`]) and the brightness
//! expression, and the engine's sounding keys (what a host layer reports as note ends).
//!
//! **A modulated note plays as the global value would.** For each per-note parameter, a
//! render of two overlapping notes, the first with its own value, must equal the sum of two
//! single-note renders: the first note with the value set globally, the second with the
//! global default. The output stage is linear here (limiter off, output gain -20 dB, far from
//! full scale), so the only difference is the f32 rounding of the mix (measured below 1e-6 of
//! the peak; tolerance 1e-5 of the peak). A modulation left out (or applied to both notes)
//! differs by the whole difference the value makes (printed: 1e-2 to 1 of the peak).
//!
//! **Brightness is the strike's own control.** A note at brightness 1 equals, bit for bit, the
//! note with the harder mallet (`mallet_hardness + 0.5`), the half-length force pulse, or the
//! pluck at half the distance to the end (module doc of
//! `noether_core::engine::voice::modulation`).

use noether::engine::voice::modulation::bright_pluck;
use noether::engine::{Engine, Event, EventKind, NoteExpression, ParamId};
use noether_testkit::presets::preset_params;
use noether_testkit::take::{self, peak};

const RATE: f64 = 48_000.0;
const BLOCK: usize = 256;

/// An engine on factory preset `preset` with a light plate (100 modes, 8 in-plane) where it is
/// one, polyphony 2, limiter off, gain -20 dB, the audio thread alone, and `sets`.
fn engine(preset: &str, sets: &[(ParamId, f32)]) -> Engine {
    let params = preset_params(preset, &[]);
    if preset.starts_with("gong") {
        params.set(ParamId::Modes, 100.0).unwrap();
        params.set(ParamId::InPlaneModes, 8.0).unwrap();
    }
    params.set(ParamId::Polyphony, 2.0).unwrap();
    params.set(ParamId::Threads, 1.0).unwrap();
    params.set(ParamId::Limiter, 0.0).unwrap();
    params.set(ParamId::Gain, -20.0).unwrap();
    for &(id, v) in sets {
        params.set(id, v).unwrap();
    }
    let (mut e, _h) = Engine::new(params);
    assert!(e.activate(RATE, BLOCK).unwrap().is_none());
    e
}

/// `seconds` (whole blocks, at least one) of both channels, the left then the right, with
/// `events` in the first block.
fn render(e: &mut Engine, events: &[Event], seconds: f64) -> Vec<f32> {
    let n = ((seconds * RATE) as usize / BLOCK).max(1) * BLOCK;
    let t = take::render(e, events, n, BLOCK);
    [t.left, t.right].concat()
}

fn note(key: u8) -> Event {
    Event::new(0, EventKind::NoteOn { key, velocity: 1.0 })
}

/// Largest difference of `a` and `b` over the peak of `a`.
fn rel_diff(a: &[f32], b: &[f32]) -> f64 {
    let d = a
        .iter()
        .zip(b)
        .fold(0.0f32, |m, (x, y)| m.max((x - y).abs()));
    f64::from(d) / f64::from(peak(a))
}

/// Keys of the two notes: the root and a fifth above.
const KEYS: (u8, u8) = (60, 67);

/// The two-note render with the first note's own `value` of `param`, against the sum of the
/// single-note renders (module doc). Returns the relative difference.
fn modulated_pair(preset: &str, base: &[(ParamId, f32)], param: ParamId, value: f32) -> f64 {
    let seconds = 0.6;
    let modulation = Event::new(
        0,
        EventKind::NoteModulation {
            key: KEYS.0,
            param,
            value,
        },
    );
    let pair = render(
        &mut engine(preset, base),
        &[note(KEYS.0), note(KEYS.1), modulation],
        seconds,
    );
    let mut global = base.to_vec();
    global.push((param, value));
    let first = render(&mut engine(preset, &global), &[note(KEYS.0)], seconds);
    let second = render(&mut engine(preset, base), &[note(KEYS.1)], seconds);
    let sum: Vec<f32> = first.iter().zip(&second).map(|(a, b)| a + b).collect();
    // The same pair without the modulation: how far a modulation left out would be.
    let plain = render(
        &mut engine(preset, base),
        &[note(KEYS.0), note(KEYS.1)],
        seconds,
    );
    let d = rel_diff(&sum, &pair);
    let left_out = rel_diff(&sum, &plain);
    println!(
        "{preset} {:?} = {value}: modulated pair vs sum {d:.2e}, modulation left out {left_out:.2e}",
        param
    );
    assert!(left_out > 1e-3, "{param:?} = {value} changes nothing here");
    d
}

/// A case: preset, its settings, the per-note parameter and the note's value.
type Case = (&'static str, &'static [(ParamId, f32)], ParamId, f32);

#[test]
fn each_per_note_parameter_plays_as_its_global_value() {
    const MALLET: [(ParamId, f32); 1] = [(ParamId::Exciter, 1.0)];
    let cases: [Case; 7] = [
        ("gong-40N", &[], ParamId::StrikeRadius, 0.5),
        ("gong-40N", &MALLET, ParamId::MalletHardness, 0.9),
        ("gong-40N", &[], ParamId::DampingScale, 4.0),
        ("gong-40N", &[], ParamId::PickupLeftPos, 0.5),
        ("gong-40N", &[], ParamId::PickupRightPos, 0.3),
        ("sitar", &[], ParamId::PluckPosition, 0.5),
        ("sitar", &[], ParamId::DampingScale, 3.0),
    ];
    for (preset, base, param, value) in cases {
        let d = modulated_pair(preset, base, param, value);
        assert!(d < 1e-5, "{preset} {param:?}: {d:.2e} of the peak");
    }
}

/// Renders key 60 alone with `events` after its note-on, on `preset` with `sets`.
fn single(preset: &str, sets: &[(ParamId, f32)], events: &[EventKind]) -> Vec<f32> {
    let mut all = vec![note(KEYS.0)];
    all.extend(events.iter().map(|&k| Event::new(0, k)));
    render(&mut engine(preset, sets), &all, 0.4)
}

#[test]
fn brightness_is_the_strikes_own_control() {
    let bright = EventKind::NoteExpression {
        key: KEYS.0,
        expression: NoteExpression::Brightness(1.0),
    };
    let own = |param, value| EventKind::NoteModulation {
        key: KEYS.0,
        param,
        value,
    };
    // The mallet: hardness 0.3 → 0.8.
    let mallet = [(ParamId::Exciter, 1.0), (ParamId::MalletHardness, 0.3)];
    let a = single("gong-40N", &mallet, &[bright]);
    let b = single("gong-40N", &mallet, &[own(ParamId::MalletHardness, 0.8)]);
    let neutral = single("gong-40N", &mallet, &[]);
    assert_eq!(a, b, "brightness 1 on a mallet: hardness + 0.5");
    assert!(rel_diff(&a, &neutral) > 1e-2);
    // The pulse: 10 ms → 5 ms.
    let a = single("gong-40N", &[], &[bright]);
    let b = single("gong-40N", &[(ParamId::StrikeDuration, 0.005)], &[]);
    assert_eq!(a, b, "brightness 1 on a pulse: half its duration");
    // The pluck: 0.25 → 0.125 of the length.
    let at = bright_pluck(0.25, 1.0) as f32;
    assert_eq!(at, 0.125);
    let sitar = [(ParamId::PluckPosition, 0.25)];
    let a = single("sitar", &sitar, &[bright]);
    let b = single("sitar", &sitar, &[own(ParamId::PluckPosition, at)]);
    assert_eq!(
        a, b,
        "brightness 1 on a pluck: half the distance to the end"
    );
    assert!(rel_diff(&a, &single("sitar", &sitar, &[])) > 1e-2);
}

#[test]
fn sounding_keys_follow_note_ends_steals_and_panic() {
    let mut e = engine(
        "sitar",
        &[(ParamId::ReleaseT60, 0.05), (ParamId::DampingScale, 20.0)],
    );
    let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
    assert_eq!(e.sounding_keys(), 0);
    e.process_events(&[note(60), note(64)], &mut l, &mut r);
    assert_eq!(e.sounding_keys(), 1 << 60 | 1 << 64);
    // A third note steals the oldest voice of the two (polyphony 2).
    e.process_events(&[note(67)], &mut l, &mut r);
    let keys = e.sounding_keys();
    assert_eq!(keys.count_ones(), 2, "{keys:b}");
    assert!(keys & 1 << 67 != 0);
    // Released with a 50 ms T60 and heavy damping: the voices end within a second.
    e.process_events(
        &[
            Event::new(0, EventKind::NoteOff { key: 60 }),
            Event::new(0, EventKind::NoteOff { key: 64 }),
        ],
        &mut l,
        &mut r,
    );
    take::render(&mut e, &[], RATE as usize / BLOCK * BLOCK, BLOCK);
    assert_eq!(e.sounding_keys(), 1 << 67, "the held note still sounds");
    e.process_events(&[Event::new(0, EventKind::AllSoundOff)], &mut l, &mut r);
    assert_eq!(e.sounding_keys(), 0);
}

/// Pan: 0.5 plays as no expression (bit for bit), 0 leaves the note in the left channel alone,
/// 1 in the right alone, 0.25 keeps the left and halves the right.
#[test]
fn pan_places_the_note() {
    let pan = |p: f32| EventKind::NoteExpression {
        key: KEYS.0,
        expression: NoteExpression::Pan(p),
    };
    // `render` returns the left channel, then the right.
    let split = |x: &[f32]| {
        let (l, r) = x.split_at(x.len() / 2);
        (l.to_vec(), r.to_vec())
    };
    let neutral = single("sitar", &[], &[]);
    assert_eq!(single("sitar", &[], &[pan(0.5)]), neutral);
    let (l0, r0) = split(&neutral);
    let (l, r) = split(&single("sitar", &[], &[pan(0.0)]));
    assert_eq!(l, l0);
    assert!(r.iter().all(|&x| x == 0.0) && peak(&r0) > 0.0);
    let (l, r) = split(&single("sitar", &[], &[pan(1.0)]));
    assert!(l.iter().all(|&x| x == 0.0));
    assert_eq!(r, r0);
    let (l, r) = split(&single("sitar", &[], &[pan(0.25)]));
    assert_eq!(l, l0);
    let half: Vec<f32> = r0.iter().map(|x| 0.5 * x).collect();
    assert!(rel_diff(&half, &r) < 1e-6, "{}", rel_diff(&half, &r));
}
