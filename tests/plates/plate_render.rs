//! Plate scenes rendered end to end through the library (scene -> voice -> render loop): the
//! report carries the energy drift and the power balance (lossless and with losses and a
//! strike); Störmer-Verlet's drift is reported, not hidden; the CLI writes the WAV and the
//! report; the scheme study reports the θ warping.

use noether::render::scene::render_scene;
use noether::scene::Scene;

fn scene(shape: &str, scheme: &str, excitation: &str, damping: &str, seconds: f64) -> Scene {
    let geometry = if shape == "rect-ss" {
        "lx = 0.4\nly = 0.6"
    } else {
        "radius = 0.3"
    };
    let text = format!(
        r#"
[output]
sample_rate = 48000
seconds = {seconds}
[plate]
shape = "{shape}"
{geometry}
thickness = 0.001
n_phi = 24
n_psi = 12
sim_rate = 48000
scheme = "{scheme}"
damping = {damping}
excitation = {excitation}
"#
    );
    noether_testkit::env::test_cache_dir();
    Scene::from_toml(&text, "test", &[]).unwrap()
}

fn impulse(shape: &str) -> String {
    let at = if shape == "rect-ss" {
        "{ x = 0.37, y = 0.41 }"
    } else {
        "{ r = 0.5, angle = 0.3 }"
    };
    format!("{{ kind = \"impulse\", at = {at}, impulse = 4.0 }}")
}

/// The render path reports the energy figures of a plate: a lossless impulse response at large
/// amplitude keeps `t + v + u` to 1e-10 relative over one second (48 000 steps; the round-off
/// accumulation observed is ~1e-13) while the in-plane energy reaches more than a third of the
/// total; with the lecture's damping law and a 60 N raised-cosine strike, energy + dissipated -
/// work is constant to 1e-9 of the peak energy (observed ~1e-12). One scheme: the balance of
/// every scheme on every plate shape is the catalogue's (`tests/schemes/catalogue.rs`); this
/// checks what the renderer and its report make of it.
#[test]
fn render_reports_energy_and_balance() {
    let s = scene(
        "circular-free",
        "conservative-exact",
        &impulse("circular-free"),
        "{ law = \"none\" }",
        1.0,
    );
    let (r, report) = render_scene(&s, |_| {}).unwrap();
    let share = r
        .energy
        .iter()
        .map(|e| e.nonlinear / e.total())
        .fold(0.0, f64::max);
    assert!(share > 0.33, "in-plane share only {share}");
    assert!(
        report.energy.max_rel_drift < 1e-10,
        "drift {}",
        report.energy.max_rel_drift
    );
    assert_eq!(report.nan_count, 0);
    assert!(report.conservative);
    let strike = "{ kind = \"strike\", at = { r = 0.92 }, duration = 0.001, peak_force = 60.0 }";
    let s = scene(
        "circular-free",
        "conservative",
        strike,
        "{ law = \"power\", a = 0.005, b = 0.6 }",
        0.5,
    );
    let (_, report) = render_scene(&s, |_| {}).unwrap();
    assert!(
        report.energy.max_balance_error < 1e-9,
        "{}",
        report.energy.max_balance_error
    );
    assert!(report.energy.dissipated > 0.0 && report.energy.work > 0.0);
}

/// Störmer-Verlet is not energy conserving: at the same large amplitude its drift is orders of
/// magnitude above round-off, and the report says the scheme is not conservative.
#[test]
fn stormer_verlet_drift_is_reported() {
    let s = scene(
        "circular-free",
        "stormer-verlet",
        &impulse("circular-free"),
        "{ law = \"none\" }",
        0.5,
    );
    let (_, report) = render_scene(&s, |_| {}).unwrap();
    assert!(!report.conservative);
    assert!(
        report.energy.max_rel_drift > 1e-8,
        "drift {}",
        report.energy.max_rel_drift
    );
    assert!(
        report.energy.max_rel_drift < 1.0,
        "drift {}",
        report.energy.max_rel_drift
    );
}

/// `noether render` writes a WAV at the output rate and a JSON report with every documented
/// field; `--set` overrides a field by its dotted path.
#[test]
fn cli_render_writes_wav_and_report() {
    let dir = std::env::temp_dir().join(format!("noether-render-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let wav = dir.join("g.wav");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_noether"))
        .env("NOETHER_CACHE", noether_testkit::env::test_cache_dir())
        .args([
            "render",
            concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/gong.toml"),
            "-q",
            "-o",
        ])
        .arg(&wav)
        .args([
            "--set",
            "output.seconds=0.2",
            "--set",
            "plate.n_phi=20",
            "--set",
            "output.sample_rate=44100",
            "--plot",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let reader = hound::WavReader::open(&wav).unwrap();
    assert_eq!(reader.spec().sample_rate, 44100);
    assert_eq!(reader.duration(), 8820);
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("g.json")).unwrap()).unwrap();
    for key in [
        "model",
        "scheme",
        "sample_rate",
        "sim_rate",
        "seconds",
        "n_phi",
        "n_psi",
        "nan_count",
        "peak",
        "wall_seconds",
        "realtime_factor",
    ] {
        assert!(!report[key].is_null(), "report lacks {key}");
    }
    for key in ["initial", "max_rel_drift", "max_balance_error"] {
        assert!(
            report["energy"][key].is_number(),
            "report lacks energy.{key}"
        );
    }
    assert_eq!(report["n_phi"], 20);
    for f in [
        "gong-energy.png",
        "gong-waveform.png",
        "gong-spectrogram.png",
    ] {
        assert!(std::fs::metadata(dir.join(f)).unwrap().len() > 1000, "{f}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `noether accuracy --vary scheme`'s study on a lossless plate: the linear-partial metric of
/// the θ = 1 scheme (closed form from the scheme's recursion, `acos` of `C / 2√C̃`) equals the
/// θ-family's numerical frequency `(2/h) asin(hω/2)` of SEED.md 1.1 evaluated independently at
/// every partial below the output Nyquist frequency (1e-9 relative: two round-off-level
/// evaluations of one angle), the exact linear part shows no warping beyond the `acos` form's
/// round-off (`ε/(ω_min h)²` relative, under 1e-6 cents here), and, with a weak impulse (nearly
/// linear motion), the exact scheme is the closer to the reference in waveform (θ = 1 detunes
/// every partial upwards; these 24 modes stay below about 200 Hz, where it is 0.05 cents).
#[test]
fn scheme_study_reports_the_theta_warping() {
    use noether::analysis::frequency::cents;
    use noether::models::plate::voice::PlateVoice;
    use noether::render::accuracy::{study, Variant};
    use noether::schemes::linear::numerical_frequency;
    let mk = |scheme: &str, fs: f64| {
        let mut s = scene(
            "circular-free",
            scheme,
            &impulse("circular-free").replace("4.0", "0.05"),
            "{ law = \"none\" }",
            0.06,
        );
        s.set_sim_rate(fs).unwrap();
        s
    };
    let variants: Vec<Variant> = ["conservative", "conservative-exact"]
        .iter()
        .map(|&name| Variant {
            setting: name.into(),
            value: None,
            scene: mk(name, 48_000.0),
        })
        .collect();
    let st = study(
        "scheme",
        &variants,
        &mk("conservative-exact", 96_000.0),
        "conservative-exact at 96 kHz".into(),
        |_| {},
    )
    .unwrap();
    let voice = PlateVoice::build(variants[0].scene.plate.as_ref().unwrap()).unwrap();
    let h = 1.0 / 48_000.0;
    let expected = voice
        .model()
        .linear_partials()
        .iter()
        .filter(|p| p.exact_hz < 24_000.0)
        .map(|p| {
            let w = std::f64::consts::TAU * p.exact_hz;
            cents(numerical_frequency(1.0, h, w).unwrap(), w).abs()
        })
        .fold(0.0, f64::max);
    let (theta1, exact) = (&st.rows[0], &st.rows[1]);
    let got = theta1.partial_cents.unwrap();
    eprintln!(
        "θ = 1: {got:.6} cents (closed form {expected:.6}), exact: {:.2e} cents; L2 {:.3e} vs {:.3e}",
        exact.partial_cents.unwrap(),
        theta1.l2_50ms,
        exact.l2_50ms
    );
    assert!(
        expected > 0.01,
        "the case should warp measurably: {expected}"
    );
    assert!((got / expected - 1.0).abs() < 1e-9, "{got} vs {expected}");
    assert!(exact.partial_cents.unwrap() < 1e-6);
    assert!(exact.l2_50ms < theta1.l2_50ms);
}
