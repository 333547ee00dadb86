//! The instrument's plate and the scene's are one plate: a factory preset's root note, built
//! by the bank (`engine/plate_bank.rs`) and retuned as a note, against the scene's voice
//! ([`crate::models::plate::voice::PlateVoice`]) built from the same parameters' spec
//! (`engine/model_spec.rs`), driven by the same pulse or mallet, step by step.

use super::PlateVoice;
use crate::engine::cost_trial::Jobs;
use crate::engine::model_spec::plate_spec;
use crate::engine::params::{ParamId, ParamValues};
use crate::engine::plate_bank::{plate_sim_rate, plate_voices};
use crate::engine::preset::Preset;
use crate::engine::tuning::KeyTuning;
use crate::engine::voice::{Physics, VoiceModel};
use crate::models::plate::basis::ModalCache;
use crate::models::plate::voice::PlateVoice as ScenePlate;
use crate::models::plate::{RaisedCosine, StepBoard};
use crate::models::source::RenderSource;
use std::sync::Arc;

/// Steps compared (at the bank's rate: 0.05 to 0.1 s).
const STEPS: usize = 2000;

/// The preset `stem` with a small basis (40 modes, 6 in-plane; every mode heard), without the
/// band above (the scene's voice adds it to its outputs; the bank's runs it at the host rate,
/// apart from the model), and `changes` applied.
fn values(stem: &str, changes: &[(ParamId, f32)]) -> ParamValues {
    let mut v = Preset::factory_named(stem)
        .expect("a factory preset")
        .values()
        .expect("valid");
    for &(id, x) in [
        (ParamId::Modes, 40.0),
        (ParamId::InPlaneModes, 6.0),
        (ParamId::BandLimit, 20000.0),
        (ParamId::BandAbove, 0.0),
    ]
    .iter()
    .chain(changes)
    {
        v.set(id, x).expect("in range");
    }
    v
}

/// The bank's one voice for `v` at the root key (begun and retuned as a note), and the
/// scene's voice built from the spec of the tier it plays.
fn both(v: &ParamValues) -> (Box<PlateVoice>, ScenePlate) {
    let kind = v.model();
    let sim = plate_sim_rate(
        v.get(ParamId::BandLimit) as f64,
        v.get(ParamId::SimRate) as f64,
        v.index_of(ParamId::Scheme),
        v.index_of(ParamId::InPlaneModes),
    );
    let jobs = Jobs {
        host: 48_000.0,
        sim,
        above: 48_000.0,
        chunk: 64,
        gain: 1.0,
    };
    let board = Arc::new(StepBoard::new());
    let (mut voices, _) = plate_voices(kind, v, jobs, 1, &mut ModalCache::default(), &board, None)
        .expect("the bank builds");
    let VoiceModel::Plate(mut pv) = voices.remove(0).model else {
        panic!("a plate voice");
    };
    let p = Physics {
        values: *v,
        bend: 0.0,
        tuning: KeyTuning::default(),
        price_cap: f64::INFINITY,
        tempo: None,
    };
    let key = v.get(ParamId::RootKey) as u8;
    pv.begin(&p, key);
    assert!(pv.retune(&p, key, 0.0, false), "the root note retunes");
    let (n, m) = pv.data.tiers[pv.tier];
    let spec = plate_spec(kind, v, n, if pv.data.linear { 0 } else { m }, sim);
    spec.validate().expect("a preset's spec is a valid scene");
    (pv, ScenePlate::build(&spec).expect("the scene builds"))
}

/// The largest difference between the two voices' left pickups over [`STEPS`], relative to
/// the scene's peak, and that peak.
fn compare(pv: &mut PlateVoice, scene: &mut ScenePlate, mallet: bool) -> (f64, f64) {
    let mut out = vec![vec![0.0; STEPS]; scene.channels()];
    scene.process(&mut out, STEPS);
    let tier = pv.tier;
    let mut engine = Vec::with_capacity(STEPS);
    if mallet {
        for _ in 0..STEPS {
            pv.mallet.step(&mut pv.models[tier]).expect("finite");
            engine.push(pv.models[tier].outputs()[0]);
        }
    } else {
        let pulse = pv.strike.expect("a pulse");
        for i in 0..STEPS {
            let f = pulse.force(i as f64 / pv.fs);
            pv.models[tier].step(f).expect("finite");
            engine.push(pv.models[tier].outputs()[0]);
        }
    }
    assert_eq!(engine.len(), out[0].len(), "every step compared");
    let peak = out[0].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let worst = out[0]
        .iter()
        .zip(&engine)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    (worst / peak, peak)
}

/// Pulse strikes on a cymbal (clamped, domed, with a boss), the lecture's gong (free, flat,
/// SAV) and the rectangle (full basis, aspect 4/3): the bank's note and the scene's plate
/// agree to 1e-9 of the peak over 2000 steps.
///
/// Tolerance: the two paths compute the same coefficients in different orders (the damping
/// law `s(a ω^b + c0)` against `(s a) ω^b + s c0`, the rest shape per unit rise scaled per
/// note against the rise projected directly, the pickups' `cos(n θ)` applied to the radial
/// values against evaluated with them), a few ulps each; the strikes are weak enough (1 N)
/// that the cascade does not amplify them: measured 2e-14 to 7e-13 (2026-11-28). A wrong position,
/// angle, size, material, rest shape or damping in either path moves it by 1e-3 or more.
#[test]
fn a_preset_note_is_the_scene_of_its_spec() {
    for stem in ["crash", "gong-40N", "rect-plate"] {
        let v = values(
            stem,
            &[(ParamId::Exciter, 0.0), (ParamId::StrikeForce, 1.0)],
        );
        let (mut pv, mut scene) = both(&v);
        pv.strike = Some(
            RaisedCosine::new(
                v.get(ParamId::StrikeDuration) as f64,
                v.get(ParamId::StrikeForce) as f64,
            )
            .expect("valid pulse"),
        );
        let (worst, peak) = compare(&mut pv, &mut scene, false);
        eprintln!("{stem}, pulse: worst difference {worst:.2e} of the peak {peak:.3e}");
        assert!(peak > 0.0 && peak.is_finite(), "{stem}: the strike sounds");
        assert!(worst <= 1e-9, "{stem}: {worst:.2e} of the peak apart");
    }
}

/// The crash's own exciter, the factory wooden stick at its speed, launched by the bank's
/// voice and by the scene: the same to 1e-9 of the peak (tolerance as above; the stick's
/// contact is solved per step by both with the same law).
#[test]
fn a_preset_mallet_note_is_the_scene_of_its_spec() {
    let v = values("crash", &[(ParamId::MalletSpeed, 0.2)]);
    assert_eq!(
        v.index_of(ParamId::Exciter),
        1,
        "the crash strikes with its stick"
    );
    let (mut pv, mut scene) = both(&v);
    pv.launch_mallet(&v, v.get(ParamId::MalletSpeed) as f64)
        .expect("launched");
    let (worst, peak) = compare(&mut pv, &mut scene, true);
    eprintln!("crash, stick: worst difference {worst:.2e} of the peak {peak:.3e}");
    assert!(peak > 0.0 && peak.is_finite(), "the stick sounds");
    assert!(worst <= 1e-9, "{worst:.2e} of the peak apart");
}

/// Every factory plate preset, as the instrument plays it, is a valid scene plate.
#[test]
fn every_plate_preset_is_a_valid_scene() {
    for (stem, preset) in Preset::factory() {
        let v = preset.values().expect("valid");
        if !v.model().is_plate() {
            continue;
        }
        let spec = plate_spec(
            v.model(),
            &v,
            v.index_of(ParamId::Modes),
            v.index_of(ParamId::InPlaneModes),
            plate_sim_rate(
                v.get(ParamId::BandLimit) as f64,
                v.get(ParamId::SimRate) as f64,
                v.index_of(ParamId::Scheme),
                v.index_of(ParamId::InPlaneModes),
            ),
        );
        if let Err(e) = spec.validate() {
            panic!("{stem}: {e}");
        }
    }
}
