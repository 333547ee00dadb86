//! `noether accuracy --preset`: factory presets played through the engine and compared with a
//! richer reference (src/render/preset_accuracy.rs).

use noether::engine::Preset;
use noether::render::preset_accuracy::{
    preset_study, render_preset, with_overrides, PresetVariant,
};

/// The engine is deterministic: a variant equal to the reference has L2 and LSD exactly 0; a
/// variant with fewer modes has a positive error; the voice closes its power balance to 1e-9 of
/// its largest energy (the engine's exact-linear-part scheme, f64 state: round-off is about
/// 1e-12 per the render tests, 1e-9 leaves room for the damped, struck, retuned voice).
#[test]
fn preset_study_measures_differences_and_nothing_else() {
    let gong = Preset::factory_named("gong-40N").expect("factory preset gong-40N");
    let base = with_overrides(&gong, &["modes=20".into(), "in_plane_modes=6".into()]).unwrap();
    let variants = vec![
        PresetVariant {
            setting: "10".into(),
            value: Some(10.0),
            preset: with_overrides(&base, &["modes=10".into()]).unwrap(),
        },
        PresetVariant {
            setting: "20".into(),
            value: Some(20.0),
            preset: base.clone(),
        },
    ];
    let study = preset_study(
        "gong-40N",
        "modes",
        &variants,
        &base,
        "same".into(),
        0.1,
        |_| {},
    )
    .expect("study");
    assert_eq!(study.rows.len(), 2);
    let (coarse, same) = (&study.rows[0], &study.rows[1]);
    assert_eq!(
        same.l2_50ms, 0.0,
        "identical settings must render identically"
    );
    assert_eq!(same.lsd_db, 0.0);
    assert!(
        coarse.l2_50ms > 1e-3,
        "10 modes vs 20: L2 {}",
        coarse.l2_50ms
    );
    assert!(
        coarse.lsd_db > 0.01,
        "10 modes vs 20: LSD {}",
        coarse.lsd_db
    );
    for r in &study.rows {
        assert!(r.energy_balance_error < 1e-9, "{r:?}");
        assert_eq!((r.n_phi, r.n_psi), (r.value.unwrap() as usize, 6));
    }
}

/// Bad overrides and durations are errors naming the key or field and the allowed range.
#[test]
fn preset_overrides_are_checked() {
    let gong = Preset::factory_named("gong-40N").unwrap();
    let e = with_overrides(&gong, &["modes=100000".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("modes") && e.contains("100000"), "{e}");
    let e = with_overrides(&gong, &["no_such_key=1".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("no_such_key"), "{e}");
    let e = with_overrides(&gong, &["modes".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("KEY=VALUE"), "{e}");
    let e = render_preset(&gong, f64::NAN).unwrap_err().to_string();
    assert!(e.contains("seconds") && e.contains("0.01 to 60"), "{e}");
}
