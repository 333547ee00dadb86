//! The parameter table's `reads` column (`core/src/engine/param_meta.rs`) is what the models
//! do: for each instrument (every model, both exciters, the custom and a factory mallet head,
//! the custom material), every parameter the column says it does not read is moved to another
//! value of its range, and a note rendered through the engine must come out the same bit for
//! bit. The editor hides exactly those rows, so a row hidden while it changes the sound (a
//! parameter mislabelled) fails here. The base note must sound (peak above -60 dBFS), so the
//! comparison is never between two silences.

use noether::engine::{Engine, Event, EventKind, ParamId, ParamKind, ParamValues, SharedParams};
use noether_testkit::presets::preset_params;
use noether_testkit::take;
use std::sync::Arc;

/// Samples rendered per note (85 ms at 48 kHz: the attack, where every exciter acts).
const SAMPLES: usize = 4096;
const BLOCK: usize = 256;

/// A small version of the factory preset `stem` with `sets` (40 modes, 4 in-plane modes, one
/// voice, the audio thread alone so the sum's order is fixed).
fn instrument(stem: &str, sets: &[(ParamId, f32)]) -> ParamValues {
    let mut all = vec![
        (ParamId::Modes, 40.0),
        (ParamId::InPlaneModes, 4.0),
        (ParamId::Polyphony, 1.0),
        (ParamId::Threads, 1.0),
    ];
    all.extend_from_slice(sets);
    preset_params(stem, &all).snapshot()
}

/// The stereo output of one note (key 60, velocity 0.8) on a new engine playing `v`; panics if
/// the set is refused.
fn render(v: &ParamValues, what: &str) -> Vec<f32> {
    let params = Arc::new(SharedParams::from_values(v));
    let (mut e, _h) = Engine::new(params);
    let refused = e.activate(48_000.0, BLOCK).unwrap();
    assert!(refused.is_none(), "{what}: refused: {refused:?}");
    let on = [Event::new(
        0,
        EventKind::NoteOn {
            key: 60,
            velocity: 0.8,
        },
    )];
    let t = take::render(&mut e, &on, SAMPLES, BLOCK);
    [t.left, t.right].concat()
}

/// Another value of `id` inside its range: 73 % of the way from the minimum (of the
/// logarithm for log parameters), or 31 % where that is the current value; the next index for
/// integers and enumerations.
fn moved(id: ParamId, current: f32) -> f32 {
    let info = id.info();
    let at = |t: f32| match info.kind {
        ParamKind::Float { log: true } if info.min > 0.0 => {
            (info.min.ln() + t * (info.max.ln() - info.min.ln())).exp()
        }
        _ => info.min + t * (info.max - info.min),
    };
    match info.kind {
        ParamKind::Float { .. } => {
            let x = at(0.73);
            if x == current {
                at(0.31)
            } else {
                x
            }
        }
        _ => {
            let next = current + 1.0;
            if next > info.max {
                info.min
            } else {
                next
            }
        }
    }
}

#[test]
fn a_parameter_an_instrument_does_not_read_does_not_change_its_sound() {
    let custom_material = (ParamId::Material, 4.0);
    let mallet = (ParamId::Exciter, 1.0);
    let instruments = [
        ("gong, pulse", instrument("gong-40N", &[])),
        ("gong, custom mallet", instrument("gong-40N", &[mallet])),
        (
            "cymbal, wooden mallet, custom material",
            instrument(
                "gong-40N",
                &[
                    (ParamId::Model, 1.0),
                    mallet,
                    (ParamId::MalletHead, 4.0),
                    custom_material,
                ],
            ),
        ),
        ("rectangle", instrument("rect-plate", &[])),
        ("sitar", instrument("sitar", &[])),
        ("tanpura", instrument("tanpura", &[(ParamId::Modes, 60.0)])),
        // The drone on a grid of 200 modes (step 5 mm), its jivari on the node at 10 mm.
        (
            "tanpura drone",
            instrument(
                "tanpura-drone",
                &[(ParamId::Modes, 200.0), (ParamId::Jivari, 10.0)],
            ),
        ),
        // The sitar with three taraf strings and its chikari, tuned by tension (tuning by ear
        // is read, and not moved), at 48 kHz.
        (
            "sitar with taraf",
            instrument(
                "sitar-taraf",
                &[
                    (ParamId::TarafStrings, 3.0),
                    (ParamId::DroneEar, 0.0),
                    (ParamId::SimRate, 48_000.0),
                    (ParamId::ChikariStroke, 0.5),
                ],
            ),
        ),
    ];
    let mut checked = 0;
    for (name, v) in &instruments {
        let base = render(v, name);
        let peak = base.iter().fold(0.0f32, |m, x| m.max(x.abs()));
        assert!(peak > 1e-3, "{name}: the note sounds (peak {peak})");
        for info in noether::engine::PARAMS {
            if v.reads(info.id) {
                continue;
            }
            let mut w = *v;
            let x = moved(info.id, v.get(info.id));
            w.set(info.id, x).unwrap();
            let what = format!("{name} with {} = {x} (unread)", info.key);
            let out = render(&w, &what);
            let first = base.iter().zip(&out).position(|(a, b)| a != b);
            assert!(
                first.is_none(),
                "{what} changes the sound from sample {:?} (of the left, then the right)",
                first
            );
            checked += 1;
        }
    }
    // Each instrument ignores many rows: plates the string's nine, strings the plate's
    // sixteen and more (121 in all on 2026-11-28).
    println!("{checked} parameters checked");
    assert!(checked > 100, "{checked} parameters checked");
}
