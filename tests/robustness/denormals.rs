//! Decaying voices never run on subnormal numbers: the plate and the string flush modal state
//! values below `noether::models::FLUSH_TO_ZERO_BELOW` (1e-60) to zero each step (the choice
//! and its reasons are documented there). These tests let a strongly damped voice decay far
//! past the point where, without the flush, its state would be subnormal (amplitude times
//! `e^{-σt}` below 2.2e-308, computed from the damping law and asserted), and check at every
//! step that every state value, output and energy term is either zero or a normal number, that
//! the state ends exactly at zero, and that the power balance still closes (1e-12 relative to
//! the initial energy scale: the flush removes at most ~1e-100 J).

use noether::models::plate::voice::PlateVoice;
use noether::models::string::{
    ContactLaw, Losses, Obstacle, OutputChannel, Quantity, Readout, StiffString, StringConfig,
    StringParams, TrianglePluck,
};
use noether::render::source::RenderSource;
use noether::scene::Scene;

fn normal_or_zero(x: f64) -> bool {
    x == 0.0 || x.is_normal()
}

fn check_balance(first: f64, scale: f64, b: f64, step: usize) {
    assert!(
        (b - first).abs() <= 1e-12 * scale,
        "balance drift {} at step {step}",
        (b - first).abs() / scale
    );
}

#[test]
fn decaying_plate_goes_to_zero_without_subnormals() {
    noether_testkit::env::test_cache_dir();
    let t60 = 0.05;
    let fs = 8000.0;
    let seconds = 8.0;
    let text = format!(
        r#"
[output]
sample_rate = 8000
seconds = {seconds}
[plate]
shape = "circular-free"
radius = 0.3
thickness = 0.001
n_phi = 10
n_psi = 5
sim_rate = {fs}
scheme = "conservative-exact"
damping = {{ law = "t60", seconds = {t60} }}
excitation = {{ kind = "strike", at = {{ r = 0.8, angle = 0.2 }}, duration = 0.001, peak_force = 60.0 }}
"#
    );
    let scene = Scene::from_toml(&text, "denormal-plate", &[]).unwrap();
    let mut voice = PlateVoice::build(scene.plate.as_ref().unwrap()).unwrap();
    let steps = (seconds * fs) as usize;
    let mut out = vec![vec![0.0; 1]; voice.channels()];
    let mut peak_q = 0.0f64;
    let mut scale = 0.0f64;
    let mut first = None;
    let mut zero_from = None;
    for n in 0..steps {
        voice.process(&mut out, 1);
        let q = voice.model().q();
        peak_q = q.iter().fold(peak_q, |m, x| m.max(x.abs()));
        assert!(
            q.iter().all(|&x| normal_or_zero(x)),
            "subnormal q at step {n}"
        );
        assert!(
            out.iter().all(|c| normal_or_zero(c[0])),
            "subnormal output at step {n}"
        );
        let e = voice.energy();
        for v in [e.kinetic, e.linear, e.nonlinear] {
            assert!(normal_or_zero(v), "subnormal energy term {v:e} at step {n}");
        }
        scale = scale.max(e.total()).max(e.work);
        // The strike's work is done once the 1 ms pulse is over; from then on the balance
        // `total + dissipated - work` is constant.
        if n as f64 / fs > 2e-3 {
            let b = e.balance();
            check_balance(*first.get_or_insert(b), scale, b, n);
        }
        if zero_from.is_none() && q.iter().all(|&x| x == 0.0) && n as f64 / fs > 2e-3 {
            zero_from = Some(n);
        }
    }
    // Every mode's amplitude decays as e^{-c t/2} with c = 2 ln(1000)/T60 (SEED 3.1 losses).
    let sigma = 1000f64.ln() / t60;
    let unflushed_end = peak_q * (-sigma * (seconds - 2e-3)).exp();
    assert!(
        unflushed_end < f64::MIN_POSITIVE,
        "the run is too short to reach the subnormal range ({unflushed_end:e})"
    );
    let z = zero_from.expect("the state reached exactly zero");
    assert!(voice.model().q().iter().all(|&x| x == 0.0));
    eprintln!(
        "plate: peak |q| {peak_q:.3e}, state exactly zero from t = {:.3} s (no flush: {unflushed_end:.1e} at the end)",
        z as f64 / fs
    );
}

#[test]
fn decaying_string_goes_to_zero_without_subnormals() {
    let fs = 8000.0;
    let n_int = 100;
    let sigma = 100.0; // 1/s, every mode: amplitude e^{-σ t}
    let seconds = 8.0;
    let params = StringParams::lecture_guitar(n_int, fs);
    let mut s = StiffString::new(&StringConfig {
        params,
        losses: Losses::PerMode(vec![sigma; n_int - 1]),
        obstacle: Obstacle::Point {
            position: 6e-3,
            height: 0.0,
            width: 0.0,
        },
        contact: ContactLaw::lecture(),
        outputs: vec![OutputChannel::Pickup {
            position: 0.37,
            quantity: Quantity::Velocity,
            readout: Readout::Grid,
        }],
    })
    .unwrap();
    s.pluck(&TrianglePluck {
        position: 0.3,
        amplitude: -1e-3,
    })
    .unwrap();
    let peak_q = s
        .modal_displacement()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let e0 = s.energy_terms();
    let (first, scale) = (e0.balance(), e0.total());
    let steps = (seconds * fs) as usize;
    let mut out = vec![vec![0.0; 1]];
    let mut zero_from = None;
    for n in 0..steps {
        s.process(&mut out, 1);
        let grid_ok = s.grid_displacement().iter().all(|&x| normal_or_zero(x));
        let ok = grid_ok && s.modal_displacement().iter().all(|&x| normal_or_zero(x));
        assert!(ok, "subnormal state at step {n}");
        assert!(normal_or_zero(out[0][0]), "subnormal output at step {n}");
        let e = s.energy_terms();
        for v in [e.kinetic, e.linear, e.nonlinear] {
            assert!(normal_or_zero(v), "subnormal energy term {v:e} at step {n}");
        }
        check_balance(first, scale, e.balance(), n);
        if zero_from.is_none() && s.modal_displacement().iter().all(|&x| x == 0.0) {
            zero_from = Some(n);
        }
    }
    let unflushed_end = peak_q * (-sigma * seconds).exp();
    assert!(unflushed_end < f64::MIN_POSITIVE, "{unflushed_end:e}");
    let left = s
        .modal_displacement()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let u_left = s
        .grid_displacement()
        .iter()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    let z = zero_from.unwrap_or_else(|| panic!("state not zero: max |q| {left:e}, |u| {u_left:e}"));
    eprintln!(
        "string: peak |q| {peak_q:.3e}, state exactly zero from t = {:.3} s (no flush: {unflushed_end:.1e} at the end)",
        z as f64 / fs
    );
}
