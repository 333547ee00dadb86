//! Bad scene input gets a clear error naming the field (and value and range where there is a
//! value), never a panic. Each case is a (TOML edit, expected fragments of the message) pair
//! run through one harness.

use noether::models::plate::spec::TensorStorage;
use noether::scene::{Scene, SceneError};

const GOOD: &str = r#"
name = "t"
[output]
sample_rate = 48000
seconds = 1.0
[plate]
shape = "circular-free"
radius = 0.4
thickness = 0.001
n_phi = 20
n_psi = 10
sim_rate = 48000
scheme = "conservative-exact"
damping = { law = "power", a = 0.005, b = 0.6 }
excitation = { kind = "strike", at = { r = 0.92 }, duration = 0.001, peak_force = 40.0 }
"#;

fn parse(text: &str, overrides: &[&str]) -> Result<Scene, SceneError> {
    let o: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    Scene::from_toml(text, "test.toml", &o)
}

#[test]
fn the_reference_scene_parses() {
    let s = parse(GOOD, &[]).unwrap();
    assert_eq!(s.plate.as_ref().unwrap().n_phi, 20);
    assert_eq!(
        s.plate.as_ref().unwrap().tensor_storage,
        TensorStorage::Double,
        "the default storage"
    );
    assert_eq!(s.plate.unwrap().effective_pickups().len(), 2);
    let single = parse(GOOD, &["plate.tensor_storage=\"single\""]).unwrap();
    assert_eq!(single.plate.unwrap().tensor_storage, TensorStorage::Single);
}

#[test]
fn every_bad_input_names_its_field() {
    // (override, fragments that must all appear in the error message)
    let cases: &[(&str, &[&str])] = &[
        (
            "plate.thickness=-0.001",
            &["plate.thickness", "-0.001", "[0.00001, 0.1]"],
        ),
        ("plate.thickness=nan", &["plate.thickness", "NaN"]),
        ("plate.radius=inf", &["plate.radius", "inf"]),
        ("plate.n_phi=0", &["plate.n_phi", "0", "1 to 4000"]),
        ("plate.n_phi=100000", &["plate.n_phi", "100000"]),
        ("plate.n_phi=-3", &["n_phi"]),
        ("plate.n_phi=\"many\"", &["n_phi"]),
        ("plate.sim_rate=0", &["plate.sim_rate", "0"]),
        (
            "plate.material.poisson=0.7",
            &["plate.material.poisson", "0.7"],
        ),
        ("plate.scheme=fast", &["fast", "conservative"]),
        (
            "plate.tensor_storage=half",
            &["tensor_storage", "half", "double", "single"],
        ),
        ("plate.shape=triangle", &["triangle", "circular-free"]),
        ("plate.colour=1", &["colour"]),
        (
            "output.sample_rate=100",
            &["output.sample_rate", "100", "8000 to 384000"],
        ),
        ("output.seconds=0", &["output.seconds", "0"]),
        (
            "plate.excitation.at.r=1.5",
            &["plate.excitation.at.r", "1.5"],
        ),
        ("plate.excitation.at.x=0.5", &["plate.excitation.at.x"]),
        (
            "plate.excitation.peak_force=-1",
            &["plate.excitation.peak_force", "-1"],
        ),
        ("plate.damping.b=7", &["plate.damping.b", "7"]),
        ("plate.damping.law=magic", &["magic"]),
        ("plate.shape=rect-ss", &["plate.lx", "missing"]),
    ];
    for (o, fragments) in cases {
        let e = parse(GOOD, &[o]).expect_err(o).to_string();
        for f in *fragments {
            assert!(e.contains(f), "--set {o}: error `{e}` lacks `{f}`");
        }
    }
}

#[test]
fn malformed_files_are_errors_not_panics() {
    let truncated = &GOOD[..GOOD.len() / 2];
    for text in [truncated, "", "[output", "output = 3", "\u{0}\u{1}binary"] {
        assert!(parse(text, &[]).is_err(), "{text:?} parsed");
    }
    let missing = Scene::load(std::path::Path::new("/nonexistent/scene.toml"), &[]).unwrap_err();
    assert!(
        missing.to_string().contains("/nonexistent/scene.toml"),
        "{missing}"
    );
}
