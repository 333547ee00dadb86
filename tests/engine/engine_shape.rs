//! The curved plate in the engine (the `dome`, `boss` and `boss_radius` parameters: a rest
//! shape set per note on the voice's model): dome = boss = 0 is the flat engine bit for bit, a
//! dome raises the lowest axisymmetric mode as the shallow-shell theory says
//! (`noether::modal::shell`) at any size, thickness and key, a curved note with losses, the
//! strike and the hand keeps its power balance to round-off, and notes with a shape never
//! allocate on the audio thread. Figures print with `--nocapture`.

use assert_no_alloc::assert_no_alloc;
use noether::engine::{Engine, Event, EventKind, NoteExpression, ParamId, SharedParams};
use noether::modal::circular::{CircularEdge, PlateModes};
use noether::modal::shell::{shell_modes, CapCoupling, Imperfection};
use noether::modal::CircularPlateSpec;
use noether_testkit::presets::preset_params;
use noether_testkit::take;
use std::f64::consts::TAU;
use std::sync::Arc;

const RATE: f64 = 48_000.0;
const BLOCK: usize = 256;

/// An engine on gong-40N with `sets` applied, one voice, activated at [`RATE`], and its
/// parameters.
fn engine(sets: &[(ParamId, f32)]) -> (Engine, Arc<SharedParams>) {
    let params = preset_params("gong-40N", &[(ParamId::Polyphony, 1.0)]);
    for &(id, x) in sets {
        params.set(id, x).unwrap();
    }
    let (mut e, _h) = Engine::new(params.clone());
    assert!(e.activate(RATE, BLOCK).unwrap().is_none());
    (e, params)
}

/// Renders `seconds` after `events` (sent with the first block); left plus right.
fn render(e: &mut Engine, events: &[Event], seconds: f64) -> Vec<f64> {
    take::render(e, events, (seconds * RATE) as usize, BLOCK).sum_f64()
}

fn note_on(key: u8) -> Event {
    Event::new(0, EventKind::NoteOn { key, velocity: 1.0 })
}

/// Hann-windowed DFT magnitude of `x` at `f` Hz.
fn magnitude(x: &[f64], f: f64) -> f64 {
    let n = x.len() as f64;
    let (mut re, mut im) = (0.0, 0.0);
    for (i, &v) in x.iter().enumerate() {
        let w = 0.5 - 0.5 * (TAU * i as f64 / n).cos();
        let ph = TAU * f * i as f64 / RATE;
        re += w * v * ph.cos();
        im += w * v * ph.sin();
    }
    (re * re + im * im).sqrt()
}

/// The strongest partial of `x` in `[lo, hi]` Hz: a scan in 0.25 Hz steps, then a parabola
/// through the three samples around the maximum of the log magnitude (for a Hann window over
/// 1 s the parabola's bias is below 0.02 Hz).
fn peak_in(x: &[f64], lo: f64, hi: f64) -> f64 {
    let step = 0.25;
    let n = ((hi - lo) / step) as usize;
    let m: Vec<f64> = (0..=n)
        .map(|k| magnitude(x, lo + step * k as f64).ln())
        .collect();
    let k = (1..n).max_by(|&a, &b| m[a].total_cmp(&m[b])).unwrap();
    let (a, b, c) = (m[k - 1], m[k], m[k + 1]);
    lo + step * (k as f64 + 0.5 * (a - c) / (a - 2.0 * b + c))
}

/// The transverse and in-plane mode counts of the shell measurements (the engine's whole
/// mirror basis: the band limit keeps every mode, checked through `voice_model`).
const SHELL_MODES: (usize, usize) = (40, 20);

/// `λ²` of the shallow shell's axisymmetric modes (increasing) for the cap `kappa`, on the
/// free plate's mirror basis of [`SHELL_MODES`] (the engine's basis), ν = 0.3 (steel).
fn shell_axisymmetric(kappa: f64) -> Vec<f64> {
    let spec = CircularPlateSpec::new(CircularEdge::Free, 0.3, SHELL_MODES.0, SHELL_MODES.1, None)
        .unwrap()
        .mirror_symmetric();
    let modes = PlateModes::build(&spec).unwrap();
    let imp = Imperfection::spherical_cap(kappa).unwrap();
    let mut l: Vec<f64> = shell_modes(&modes, &imp, CapCoupling::ModalProjection)
        .unwrap()
        .iter()
        .filter(|m| m.n == 0)
        .map(|m| m.lambda2)
        .collect();
    l.sort_by(f64::total_cmp);
    l
}

/// The lowest axisymmetric partial of a steel gong of radius `size` (m), thickness `h` (m) and
/// dome `dome` (thicknesses), key `key` (the root key 60 plays `h`, 72 twice `h`), struck
/// softly at the centre (only the axisymmetric modes sound; 0.5 N keeps the motion within
/// 1e-3 h, so the nonlinear shift is negligible) and rendered losslessly for 1 s at a 48 kHz
/// simulation rate: returns `λ²` measured (`ω a² √(ρh/D)` of the note's own `h`) and the
/// partial's `ω` times the time step.
fn measured_lambda2(size: f32, h: f32, dome: f32, key: u8, window: (f64, f64)) -> (f64, f64) {
    let (mut e, _) = engine(&[
        (ParamId::Size, size),
        (ParamId::Thickness, h),
        (ParamId::Dome, dome),
        (ParamId::Modes, SHELL_MODES.0 as f32),
        (ParamId::InPlaneModes, SHELL_MODES.1 as f32),
        (ParamId::BandLimit, 20_000.0),
        (ParamId::SimRate, 48_000.0),
        (ParamId::Scheme, 1.0), // conservative-exact
        (ParamId::StrikeRadius, 0.0),
        (ParamId::StrikeForce, 0.5),
        (ParamId::DampingScale, 0.0),
        (ParamId::Limiter, 0.0),
    ]);
    let x = render(&mut e, &[note_on(key)], 1.0);
    let info = e.voice_model(0).unwrap();
    assert_eq!(
        (info.n_phi as usize, info.n_psi as usize),
        SHELL_MODES,
        "the note simulates the whole basis"
    );
    // ω a² √(ρh/D) with the note's thickness (steel: E = 2e11 Pa, ρ = 7860 kg/m³, ν = 0.3).
    let hn = h as f64 * 2f64.powf((key as f64 - 60.0) / 12.0);
    let d = 2.0e11 * hn.powi(3) / (12.0 * (1.0 - 0.09));
    let scale = (d / (7860.0 * hn)).sqrt() / (size as f64).powi(2);
    let f = |l2: f64| l2 * scale / TAU;
    let fm = peak_in(&x, f(window.0), f(window.1));
    (TAU * fm / scale, TAU * fm / 48_000.0)
}

/// A cap of rise 5 h (κ = 10) raises the lowest axisymmetric mode from the flat λ² = 9.00 (ν = 0.3) to
/// the shallow shell's (about 34, `shell_modes` on the engine's basis), on a 0.15 m, 2 mm plate
/// at the root key, on a 0.2 m, 1.5 mm plate, and an octave up (h doubled): the rise follows
/// Size and Thickness. The conservative-exact scheme integrates the curvature's stiffness
/// implicitly, lowering the frequency by `O((ω h)²)` with `h` the time step (measured: 7.0e-4
/// at `ω h = 0.097`, 2.8e-3 at 0.19, i.e. about `0.075 (ω h)²`); tolerance `0.1 (ω h)² + 1e-4`
/// relative (the measurement's 0.02 Hz is below 1e-4 of these partials). The flat case's
/// exact linear part leaves only the measurement: 2e-4. A shape that did not follow Size,
/// Thickness or the key would change `κ` and miss `λ²` by far more (at κ = 10, `λ²` moves
/// by about 3 per unit of κ).
#[test]
fn dome_raises_the_axisymmetric_mode_as_the_shell_theory_says() {
    let flat = shell_axisymmetric(0.0);
    let curved = shell_axisymmetric(10.0);
    let window = |l: &[f64]| (0.5 * l[0], 0.5 * (l[0] + l[1]));
    println!("shell: flat λ² {:.3}, κ = 10 λ² {:.3}", flat[0], curved[0]);
    assert!((flat[0] - 9.0).abs() < 0.01 && curved[0] > 3.0 * flat[0]);
    let (lf, _) = measured_lambda2(0.15, 0.002, 0.0, 60, window(&flat));
    println!("flat: λ² measured {lf:.4} (shell {:.4})", flat[0]);
    assert!((lf / flat[0] - 1.0).abs() < 2e-4, "flat {lf}");
    for (size, h, key) in [(0.15, 0.002, 60), (0.2, 0.0015, 60), (0.15, 0.002, 72)] {
        let (l, wh) = measured_lambda2(size, h, 5.0, key, window(&curved));
        let err = l / curved[0] - 1.0;
        println!(
            "a = {size} m, h = {h} m, key {key}: λ² measured {l:.4}, shell {:.4}, error {err:.1e} at ω h = {wh:.3}",
            curved[0]
        );
        let tol = 0.1 * wh * wh + 1e-4;
        assert!(
            err.abs() < tol,
            "a = {size}, h = {h}, key {key}: {l}, tolerance {tol:.1e}"
        );
    }
}

/// dome = boss = 0 is the flat engine bit for bit: a note after a curved note on the same
/// voice, the shape set back to zero, renders exactly the samples of an engine that never had
/// a shape (the model's zero shape runs the flat arithmetic). A dome of 0.01 h changes them
/// (the comparison sees a shape).
#[test]
fn flat_shape_is_the_flat_engine_bit_for_bit() {
    let sets = [(ParamId::Modes, 60.0), (ParamId::Scheme, 1.0)];
    let (mut plain, _) = engine(&sets);
    let want = render(&mut plain, &[note_on(60)], 0.3);
    let (mut e, p) = engine(&sets);
    p.set(ParamId::Dome, 8.0).unwrap();
    p.set(ParamId::Boss, 4.0).unwrap();
    let curved = render(&mut e, &[note_on(60)], 0.3);
    assert_ne!(curved, want);
    e.reset();
    p.set(ParamId::Dome, 0.0).unwrap();
    p.set(ParamId::Boss, 0.0).unwrap();
    let again = render(&mut e, &[note_on(60)], 0.3);
    assert!(again == want, "the flat note after a curved one differs");
    let (mut slight, _) = engine(&[sets[0], sets[1], (ParamId::Dome, 0.01)]);
    assert_ne!(render(&mut slight, &[note_on(60)], 0.3), want);
}

/// A curved gong note (dome 8 h, boss 4 h, the conservative-exact scheme, the preset's losses,
/// an 80 N strike and the hand at half pressure) keeps its power balance `E + dissipated -
/// work` to round-off over 1 s through the engine path: deviation below 1e-9 of the peak
/// energy, the bound of the engine's lossless energy test (the schemes' own round-off per run
/// is about 1e-12 in the testkit catalogue; the bound leaves room for accumulation over the
/// 13 400 steps of f32-stored tensor contractions).
#[test]
fn curved_note_keeps_the_power_balance() {
    let (mut e, _) = engine(&[
        (ParamId::Modes, 120.0),
        (ParamId::InPlaneModes, 15.0),
        (ParamId::Scheme, 1.0),
        (ParamId::Dome, 8.0),
        (ParamId::Boss, 4.0),
        (ParamId::StrikeForce, 80.0),
    ]);
    let events = [
        note_on(60),
        Event::new(
            0,
            EventKind::NoteExpression {
                key: 60,
                expression: NoteExpression::Pressure(0.5),
            },
        ),
    ];
    render(&mut e, &events, 0.001);
    let b0 = e.voice_energy(0).unwrap().balance();
    let (mut worst, mut peak, mut dissipated, mut work) = (0.0f64, 0.0f64, 0.0, 0.0);
    for _ in 0..50 {
        render(&mut e, &[], 0.02);
        let t = e.voice_energy(0).expect("the note sounds");
        peak = peak.max(t.total());
        worst = worst.max((t.balance() - b0).abs());
        (dissipated, work) = (t.dissipated, t.work);
    }
    let rel = worst / peak;
    println!("curved note: peak {peak:.3e} J, work {work:.3e} J, dissipated {dissipated:.3e} J, balance error {rel:.2e}");
    assert!(work > 0.0 && dissipated > 0.1 * work, "losses exercised");
    assert!(rel < 1e-9, "balance error {rel}");
}

/// Notes with a shape never allocate on the audio thread: fresh notes, re-strikes, an octave
/// up (the shape follows the note's thickness) and the dome and boss changed between blocks
/// (each change sets the shape again on the sounding voices), under `assert_no_alloc`.
#[test]
fn shaped_notes_never_allocate() {
    let (mut e, p) = engine(&[
        (ParamId::Modes, 80.0),
        (ParamId::Scheme, 1.0),
        (ParamId::Polyphony, 3.0),
        (ParamId::Dome, 6.0),
        (ParamId::Boss, 3.0),
    ]);
    let (mut l, mut r) = (vec![0.0f32; BLOCK], vec![0.0f32; BLOCK]);
    for k in 0..60u8 {
        p.set(ParamId::Dome, (k % 7) as f32 * 4.0).unwrap();
        p.set(ParamId::Boss, (k % 5) as f32 * 3.0).unwrap();
        let ev = [note_on(48 + 12 * (k % 3))];
        let events: &[Event] = if k % 4 == 0 { &ev } else { &[] };
        assert_no_alloc(|| e.process_events(events, &mut l, &mut r));
        assert!(l.iter().chain(&r).all(|x| x.is_finite()));
    }
}
