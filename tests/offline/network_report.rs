//! A string network's report says where its modes lie against the Nyquist frequency of the
//! simulation, and `noether render` warns when some alias (docs/models.md, "The drone's grid and
//! rate").

use noether::render::scene::render_scene;
use noether::scene::Scene;

/// Each string's `(modes, modes above Nyquist, top mode Hz)` and the warnings of a short render
/// of the drone scene with `set`.
fn drone_report(set: &[&str]) -> (Vec<(u64, u64, f64)>, Vec<String>) {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/tanpura-drone.toml"
    );
    let mut set: Vec<String> = set.iter().map(|s| s.to_string()).collect();
    set.extend([
        "output.seconds=0.01".into(),
        "tanpura.tune_by_ear=false".into(),
    ]);
    let scene = Scene::load(std::path::Path::new(path), &set).unwrap();
    let (_, report) = render_scene(&scene, |_| {}).unwrap();
    let strings = report.details["strings"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            (
                s["modes"].as_u64().unwrap(),
                s["modes_above_nyquist"].as_u64().unwrap(),
                s["top_mode_hz"].as_f64().unwrap(),
            )
        })
        .collect();
    (strings, report.warnings)
}

/// The default drone (480 modes at 48 kHz) aliases: its strings' stiffness lifts the top modes
/// past 130 kHz (measured 137-163 kHz), most modes lie above 24 kHz, and the render warns,
/// naming every string. The same strings at 384 kHz lie under its Nyquist frequency (no
/// warning); at 192 kHz some do not, and fewer than at 48 kHz. The bound on the top mode is
/// the stiffness's: `480 f_1` alone would be 33 to 67 kHz.
#[test]
fn the_report_counts_the_modes_above_nyquist_and_warns() {
    let (at48, warn48) = drone_report(&[]);
    assert_eq!(at48.len(), 4);
    for (i, &(modes, above, top)) in at48.iter().enumerate() {
        assert_eq!(modes, 480);
        assert!(top > 1.3e5, "string {i}: {top} Hz");
        assert!(
            above > 240 && above < 480,
            "string {i}: {above} above 24 kHz"
        );
    }
    assert_eq!(warn48.len(), 1, "{warn48:?}");
    assert!(
        (0..4).all(|i| warn48[0].contains(&format!("string {i} ("))),
        "{}",
        warn48[0]
    );
    let (at192, _) = drone_report(&["tanpura.sim_rate=192000"]);
    for (a, b) in at48.iter().zip(&at192) {
        assert!(b.1 > 0 && b.1 < a.1, "{a:?} at 48 kHz, {b:?} at 192 kHz");
    }
    let (at384, warn384) = drone_report(&["tanpura.sim_rate=384000"]);
    assert!(at384.iter().all(|s| s.1 == 0), "{at384:?}");
    assert!(warn384.is_empty(), "{warn384:?}");
}

/// The alias-free drone (`tanpura.alias_free`) steps only the modes under 0.9 of the Nyquist
/// frequency: at 48 kHz every string keeps its 480-mode grid but steps fewer than a third of
/// its modes, the highest under 21.6 kHz, none above 24 kHz, and the render does not warn.
#[test]
fn an_alias_free_drone_steps_no_mode_above_nyquist() {
    let (strings, warnings) = drone_report(&["tanpura.alias_free=true"]);
    assert_eq!(strings.len(), 4);
    for (i, &(modes, above, top)) in strings.iter().enumerate() {
        assert_eq!(modes, 480, "string {i}");
        assert_eq!(above, 0, "string {i}");
        assert!(
            top > 15e3 && top < 21.6e3,
            "string {i}: top stepped mode {top} Hz"
        );
    }
    assert!(warnings.is_empty(), "{warnings:?}");
}
