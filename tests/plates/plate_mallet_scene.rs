//! The mallet in scenes: `excitation = { kind = "mallet", ... }` renders through the library
//! with the joint energy of plate, mallet and felt in the report, and bad mallet fields are
//! refused by name, value and range; the factory heads (`head = "wood"`, ...) fill the fields
//! not given, and sound brighter from soft felt to metal.

use noether::error::SceneError;
use noether::models::plate::mallet_heads::hertz_duration;
use noether::models::plate::voice::PlateVoice;
use noether::models::source::RenderSource;
use noether::render::report::spectral_centroid;
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
        ("mass = 0.2", "head = \"glass\"", "glass"),
        ("mass = 0.2", "head = \"glass\"", "hard-felt"),
    ] {
        let bad = MALLET.replace(from, to);
        match scene(&bad, "{ law = \"none\" }", 0.1) {
            Err(SceneError::Parse(msg)) => assert!(msg.contains(name), "{msg}"),
            other => panic!("{to}: {other:?}"),
        }
    }
}

/// A factory head fills the fields not given (the scene then plays exactly as with its values
/// written out); without a head a missing field is named. On the plate (0.3 m, 1 mm, 24 modes,
/// 2 m/s) the heads' contacts keep the order of their Hertz contacts on a rigid target (the
/// plate's compliance lengthens them: soft felt 41 ms against 10 ms, rubber 7.5 against 6.2,
/// hard felt 4.0 against 2.0, wood 0.17, metal 0.12 ms), and the hard heads' first 0.1 s has a
/// spectral centroid above 1.3 times the soft heads' (measured about 93-98 Hz against 36-63:
/// the 24-mode plate's band is low).
#[test]
fn factory_heads_fill_the_mallet_and_order_its_brightness() {
    use noether::models::plate::MalletHead;
    let head = |name: &str| {
        format!("{{ kind = \"mallet\", at = {{ r = 0.9, angle = 0.2 }}, head = \"{name}\", speed = 2.0 }}")
    };
    let play = |excitation: &str| {
        let s = scene(excitation, "{ law = \"none\" }", 0.1).unwrap();
        let mut voice = PlateVoice::build(s.plate.as_ref().unwrap()).unwrap();
        let mut out = vec![vec![0.0; 4800]; voice.channels()];
        voice.process(&mut out, 4800);
        let stats = voice.mallet().unwrap().stats();
        (out.swap_remove(0), stats)
    };
    let render = |excitation: &str| play(excitation).0;
    // Written out, the wood head's law gives the same samples.
    let law = MalletHead::Wood.law();
    let written = format!(
        "{{ kind = \"mallet\", at = {{ r = 0.9, angle = 0.2 }}, mass = {:e}, stiffness = {:e}, exponent = {:e}, loss = {:e}, speed = 2.0 }}",
        law.mass, law.stiffness, law.exponent, law.loss
    );
    assert_eq!(render(&head("wood")), render(&written));
    // A head's field can be overridden.
    let heavier = head("wood").replace("speed", "mass = 0.5, speed");
    assert_ne!(render(&heavier), render(&head("wood")));
    // No head: the missing field is named.
    let bare = "{ kind = \"mallet\", at = { r = 0.9, angle = 0.2 }, mass = 0.2, exponent = 2.5, speed = 2.0 }";
    match scene(bare, "{ law = \"none\" }", 0.1) {
        Err(SceneError::Invalid(e)) => assert_eq!(e.field, "plate.excitation.stiffness", "{e}"),
        other => panic!("{other:?}"),
    }
    let centroid = |x: &[f64]| spectral_centroid(x, 48_000.0).expect("sound");
    // (head, mean contact per impact in s, centroid in Hz, Hertz's contact on a rigid target)
    let mut rows = Vec::new();
    for h in MalletHead::ALL {
        let (x, stats) = play(&head(h.name()));
        let l = h.law();
        let contact = stats.contact_steps as f64 / 48_000.0 / stats.impacts.max(1) as f64;
        let rigid = hertz_duration(l.mass, l.stiffness, l.exponent, 2.0);
        let c = centroid(&x);
        println!(
            "{}: M {} kg, K {:.3e} N/m^{}, λ {} s/m: {} impacts, {:.3} ms per contact (rigid target {:.3} ms), centroid {c:.0} Hz",
            h.name(),
            l.mass,
            l.stiffness,
            l.exponent,
            l.loss,
            stats.impacts,
            1e3 * contact,
            1e3 * rigid
        );
        rows.push((h, contact, c, rigid));
    }
    // The contacts on the plate keep the order of the heads' contacts on a rigid target.
    rows.sort_by(|a, b| b.3.total_cmp(&a.3));
    for w in rows.windows(2) {
        assert!(w[0].1 > w[1].1, "{:?} vs {:?}", w[0], w[1]);
    }
    // The hard heads (wood, metal) sound brighter than the soft ones.
    let hard = rows[3].2.min(rows[4].2);
    let soft = rows[0].2.max(rows[1].2).max(rows[2].2);
    assert!(hard > 1.3 * soft, "hard heads {hard} Hz, soft {soft} Hz");
}
