//! The mallet in scenes: `excitation = { kind = "mallet", ... }` renders through the library
//! with the joint energy of plate, mallet and felt in the report, and bad mallet fields are
//! refused by name, value and range.

use noether::error::SceneError;
use noether::models::plate::voice::PlateVoice;
use noether::models::source::RenderSource;
use noether::render::scene::render_scene;
use noether::scene::Scene;

fn scene(excitation: &str, damping: &str, seconds: f64) -> Result<Scene, SceneError> {
    let text = format!(
        r#"
[output]
sample_rate = 48000
seconds = {seconds}
[plate]
shape = "circular-free"
radius = 0.3
thickness = 0.001
n_phi = 24
n_psi = 12
sim_rate = 48000
scheme = "sav"
damping = {damping}
excitation = {excitation}
"#
    );
    noether_testkit::env::test_cache_dir();
    Scene::from_toml(&text, "test", &[])
}

const MALLET: &str = "{ kind = \"mallet\", at = { r = 0.9, angle = 0.2 }, mass = 0.2, stiffness = 1e8, exponent = 2.5, speed = 3.0, loss = 0.1 }";

/// A mallet scene renders (0.2 kg, 1e8 N/m^2.5, 3 m/s on a 0.3 m, 1 mm steel disc): no NaN,
/// the joint power balance (plate + mallet + felt, the launch as work in) within 1e-11 of the
/// peak energy (measured 3.1e-12), the mallet strikes (3 impacts in 0.1 s, at most 3 Newton
/// evaluations a step) and the felt and the modes dissipate. The same scene with a lossless
/// felt and no damping conserves the joint energy (measured 3.3e-12, bound 1e-11).
#[test]
fn mallet_scene_renders_with_a_closed_balance() {
    let s = scene(MALLET, "{ law = \"power\", a = 0.005, b = 0.6 }", 0.5).unwrap();
    let (_, report) = render_scene(&s, |_| {}).unwrap();
    println!(
        "damped: balance {:.2e}, drift {:.2e}, peak {:.3}",
        report.energy.max_balance_error, report.energy.max_rel_drift, report.peak
    );
    assert_eq!(report.nan_count, 0);
    assert!(report.peak > 0.0);
    assert!(report.energy.max_balance_error < 1e-11);
    assert!(report.energy.dissipated > 0.0 && report.energy.work > 0.0);

    let lossless = MALLET.replace("loss = 0.1", "loss = 0.0");
    let s = scene(&lossless, "{ law = \"none\" }", 0.5).unwrap();
    let (_, report) = render_scene(&s, |_| {}).unwrap();
    println!("lossless: balance {:.2e}", report.energy.max_balance_error);
    assert!(report.energy.max_balance_error < 1e-11);

    let mut voice = PlateVoice::build(s.plate.as_ref().unwrap()).unwrap();
    let mut out = vec![vec![0.0; 4800]; voice.channels()];
    voice.process(&mut out, 4800);
    let m = voice.mallet().unwrap();
    println!("mallet: {:?}", m.stats());
    assert!(m.stats().impacts >= 1 && m.stats().solver_failures == 0);
    assert!(m.stats().contact_steps > 10);
}

/// Out-of-range or misspelt mallet fields are errors naming the dotted field, the value and the
/// allowed range (a deliberately broken input for each check).
#[test]
fn bad_mallet_fields_are_named() {
    for (from, to, field) in [
        ("mass = 0.2", "mass = 0.0", "plate.excitation.mass"),
        (
            "stiffness = 1e8",
            "stiffness = 1e14",
            "plate.excitation.stiffness",
        ),
        (
            "exponent = 2.5",
            "exponent = 4.5",
            "plate.excitation.exponent",
        ),
        ("speed = 3.0", "speed = -1.0", "plate.excitation.speed"),
        ("loss = 0.1", "loss = 20.0", "plate.excitation.loss"),
        ("r = 0.9", "r = 1.5", "plate.excitation.at.r"),
    ] {
        let bad = MALLET.replace(from, to);
        match scene(&bad, "{ law = \"none\" }", 0.1) {
            Err(SceneError::Invalid(e)) => {
                assert_eq!(e.field, field, "{e}");
                assert!(!e.allowed.is_empty(), "{e}");
            }
            other => panic!("{to}: {other:?}"),
        }
    }
    for (from, to, name) in [
        ("mass = 0.2", "masss = 0.2", "masss"),
        ("speed = 3.0, ", "", "speed"),
    ] {
        let bad = MALLET.replace(from, to);
        match scene(&bad, "{ law = \"none\" }", 0.1) {
            Err(SceneError::Parse(msg)) => assert!(msg.contains(name), "{msg}"),
            other => panic!("{to}: {other:?}"),
        }
    }
}
