//! `quality = "auto"` on string scenes (issue 6): the ladder's mode counts cover the heard band
//! and never exceed the full count, its rates divide the scene's and keep every mode below the
//! Nyquist limit; candidates that are not valid scenes (a bridge shorter than one grid
//! spacing) are skipped with a reason; the chosen model, re-rendered, is within the tolerance
//! of the full model; a 1e-9 dB tolerance keeps the full model. Small strings (200 modes at
//! 192 kHz) and 0.05 s excerpts keep this under a second in the test profile.

use noether::models::string::StringParams;
use noether::render::accuracy::log_spectral_distance;
use noether::render::auto::plan::plan;
use noether::render::auto::plan_string::{mode_hz, modes_to_cover, NYQUIST_MARGIN};
use noether::render::auto::select;
use noether::render::scene::render_scene;
use noether::scene::Scene;

/// `assets/scenes/sitar.toml` at 200 modes, 192 kHz, 0.05 s, `[quality] mode = "auto"` with
/// `tolerance_db`, plus `extra` overrides.
fn sitar(tolerance_db: f64, extra: &[&str]) -> Scene {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scenes/sitar.toml"
    ))
    .unwrap();
    let mut set: Vec<String> = [
        "string.modes=200",
        "string.sim_rate=192000",
        "output.seconds=0.05",
        "quality.mode=auto",
        "quality.excerpt_seconds=0.05",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    set.push(format!("quality.tolerance_db={tolerance_db:e}"));
    set.extend(extra.iter().map(|s| s.to_string()));
    Scene::from_toml(&text, "sitar-auto-test", &set).unwrap()
}

/// Worst-pickup LSD (dB) of `a` against `b`, from fresh renders.
fn lsd(a: &Scene, b: &Scene) -> f64 {
    let (ra, _) = render_scene(a, |_| {}).unwrap();
    let (rb, _) = render_scene(b, |_| {}).unwrap();
    ra.out
        .iter()
        .zip(&rb.out)
        .map(|(x, y)| log_spectral_distance(x, y))
        .fold(0.0, f64::max)
}

fn full(s: &Scene) -> Scene {
    let mut f = s.clone();
    f.quality = None;
    f
}

/// Every candidate: mode count in [n_hear, full], top mode at or above f_hear (20 kHz here),
/// rate a divisor of 192 kHz at least max(1.1 x 2 f_max, 48 kHz) (or the scene's), f_max the
/// closed form; the full model itself is not a candidate; cheapest first.
#[test]
fn string_ladder_follows_the_rules() {
    let s = sitar(1.0, &[]);
    let p = plan(&s).unwrap();
    let params: StringParams = s.string.as_ref().unwrap().params();
    let n_hear = modes_to_cover(&params, 20_000.0, 200).unwrap();
    assert!(mode_hz(&params, n_hear) >= 20_000.0 && mode_hz(&params, n_hear - 1) < 20_000.0);
    assert!(!p.candidates.is_empty());
    for c in &p.candidates {
        let z = c.size;
        assert!(z.string && z.n_phi >= n_hear && z.n_phi <= 200, "{z:?}");
        assert!((z.f_max_hz - mode_hz(&params, z.n_phi)).abs() < 1e-9 * z.f_max_hz);
        assert!(192_000.0 % z.sim_rate == 0.0, "{z:?}");
        assert!(
            z.sim_rate == 192_000.0
                || (z.sim_rate >= NYQUIST_MARGIN * 2.0 * z.f_max_hz && z.sim_rate >= 48_000.0),
            "{z:?}"
        );
        assert!(!(z.n_phi == 200 && z.sim_rate == 192_000.0));
    }
    assert!(p.candidates.iter().any(|c| c.size.sim_rate < 192_000.0));
    assert!(p
        .candidates
        .windows(2)
        .all(|w| w[0].estimated_cost <= w[1].estimated_cost));
}

/// At an 8 kHz output the heard band (4 kHz) needs about 20 modes, a 47 mm grid spacing, longer
/// than the 20 mm bridge: such candidates are skipped with the validation's reason, and every
/// remaining one is a valid scene.
#[test]
fn invalid_bridge_candidates_are_skipped_with_a_reason() {
    let s = sitar(1.0, &["output.sample_rate=8000"]);
    let p = plan(&s).unwrap();
    let why = p
        .reasons
        .iter()
        .find(|r| r.starts_with("skipped"))
        .expect("a skipped candidate");
    assert!(why.contains("string.obstacle"), "{why}");
    for c in &p.candidates {
        c.size.apply(&s).unwrap();
    }
}

/// With 3 dB on the buzzing sitar a reduced model is chosen, and re-rendering it and the full
/// model gives an LSD within 3 dB equal to the reported one (renders are deterministic: 1e-9).
#[test]
fn chosen_string_model_meets_the_tolerance() {
    let s = sitar(3.0, &[]);
    let (report, reduced) = select(&s, |l| eprintln!("{l}")).unwrap();
    assert!(!report.chosen_is_full, "{:?}", report.reasons);
    let d = lsd(&reduced, &full(&s));
    eprintln!("chosen {}: LSD {d:.4} dB", report.chosen.label());
    assert!(d <= 3.0, "{d}");
    assert!((d - report.lsd_db).abs() < 1e-9, "{d} {}", report.lsd_db);
    let st = reduced.string.as_ref().unwrap();
    assert!(st.modes < 200 || st.sim_rate < 192_000.0);
    assert_eq!(st.contact_scheme, s.string.as_ref().unwrap().contact_scheme);
    assert!(reduced.quality.is_none());
}

/// 1e-9 dB: no truncation of the modes or the rate meets it, so the full model is kept, every
/// candidate measured above the tolerance.
#[test]
fn a_tight_tolerance_keeps_the_full_string_model() {
    let s = sitar(1e-9, &[]);
    let (report, reduced) = select(&s, |_| {}).unwrap();
    assert!(report.chosen_is_full, "{:?}", report.reasons);
    assert_eq!(report.untried, 0);
    assert!(report.candidates.iter().all(|c| c.lsd_db > 1e-9));
    assert_eq!(reduced.string, full(&s).string);
}
