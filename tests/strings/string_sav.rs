//! The energy-quadratised (SAV) contact scheme of the string (`models::string::contact_sav`):
//! identity with the exact (Newton) scheme without contact, convergence towards the Newton
//! scheme as fs grows, hostile contact laws, and the scene field. Every test prints the figures
//! it checks (`--nocapture`). The conservation of its modified energy `H_q` with contact and the
//! power balance with losses and forcing are the catalogue's (`tests/schemes/catalogue.rs`);
//! no allocation: `string_alloc.rs` runs both schemes.

use noether::models::string::{
    ContactLaw, ContactScheme, Losses, Obstacle, StiffString, StrikeForce, TrianglePluck,
};
use noether::render::source::RenderSource;
use noether::scene::Scene;

/// Lecture string with the given grid, rate, losses, obstacle, law and scheme; outputs: grid
/// displacement at 0.37 m, modal velocity at 0.37 m, obstacle force.
fn string(
    n: usize,
    fs: f64,
    losses: Losses,
    obstacle: Obstacle,
    law: ContactLaw,
    scheme: ContactScheme,
) -> StiffString {
    noether_testkit::harness::lecture_string_with_law(n, fs, losses, obstacle, law, scheme)
}

/// The lecture's pluck: triangle of 1 mm at 0.3 m, at rest.
fn pluck(s: &mut StiffString) {
    s.pluck(&TrianglePluck {
        position: 0.3,
        amplitude: 1e-3,
    })
    .unwrap();
}

/// Balance figure of a run relative to the largest energy seen, and the first output.
#[derive(Debug)]
struct Run {
    /// max |(H + dissipated - work)_n - (..)_0| / max H.
    balance: f64,
    /// Largest total energy (J).
    max: f64,
    /// Output channel 0, every step.
    signal: Vec<f64>,
}

/// Steps one step per `process` call, sampling energy and outputs every step; every output
/// must be finite.
fn run(s: &mut StiffString, steps: usize) -> Run {
    let mut out = vec![vec![0.0; 1]; s.channels()];
    let first = s.energy();
    let mut max = first.total();
    let (mut hist, mut signal) = (Vec::with_capacity(steps), Vec::with_capacity(steps));
    for _ in 0..steps {
        s.process(&mut out, 1);
        assert!(out.iter().all(|c| c[0].is_finite()), "non-finite output");
        let e = s.energy();
        max = max.max(e.total());
        hist.push(e);
        signal.push(out[0][0]);
    }
    let balance = hist
        .iter()
        .map(|e| (e.balance() - first.balance()).abs() / max)
        .fold(0.0f64, f64::max);
    Run {
        balance,
        max,
        signal,
    }
}

/// What the quadratisation costs, measured on the lossless sitar (N = 500, the 1 mm pluck) and
/// printed for docs/ACCURACY.md (its conservation is the catalogue's,
/// `tests/schemes/catalogue.rs`):
/// - `z` is an independent variable, so the gap `Δx Σ (z²/2 - ψ)` is not zero: at 2 MHz (20 ms)
///   its largest magnitude is 8.1e-4 of H (measured; required below 2e-3), and an attractive
///   bridge force appears when a node whose `z` froze below 0 touches again (measured down to
///   -0.88 N; required < 0, so the documented behaviour is still the one measured);
/// - at 48 kHz (1 s) the contact is soft: the penetration is more than 10 times Newton's
///   (measured 48 µm against 0.88 µm).
#[test]
fn quadratisation_gap_and_soft_contact_are_measured() {
    let law = ContactLaw::lecture();
    let worst = |fs: f64, steps: usize, scheme| {
        let mut s = string(500, fs, Losses::None, Obstacle::seed_sitar(), law, scheme);
        pluck(&mut s);
        let mut out = vec![vec![0.0; 1]; s.channels()];
        let (mut gap, mut min_force, mut max) = (0.0f64, 0.0f64, 0.0f64);
        for _ in 0..steps {
            s.process(&mut out, 1);
            gap = gap.max(s.quadratisation_gap().abs());
            min_force = min_force.min(out[2][0]);
            max = max.max(s.energy().total());
        }
        (gap / max, min_force, s.contact_stats().max_penetration)
    };
    let (gap, min_force, _) = worst(2e6, 40_000, ContactScheme::Quadratised);
    eprintln!("sitar 2 MHz, quadratised: |gap| max {gap:.2e} of H, min force {min_force:.3} N");
    assert!(gap < 2e-3 && min_force < 0.0, "{gap} {min_force}");
    let (_, _, soft) = worst(48e3, 48_000, ContactScheme::Quadratised);
    let (_, _, newton) = worst(48e3, 48_000, ContactScheme::NewtonDiscreteGradient);
    eprintln!(
        "sitar 48 kHz: max penetration {soft:.3e} m (quadratised) against {newton:.3e} m (Newton)"
    );
    assert!(soft > 10.0 * newton && newton > 0.0, "{soft} {newton}");
}

/// Without contact (a fretboard 5 mm below a 1 mm pluck, never reached) the quadratised scheme
/// is bit-for-bit the exact scheme: `g = 0` at every node, so the node update is `r = b`,
/// `f = 0`, exactly as Newton's no-contact branch. Compared over 20 000 steps at 48 kHz, every
/// output sample equal (tolerance 0: the same floating-point operations).
#[test]
fn without_contact_the_schemes_are_identical() {
    let far = || Obstacle::Fretboard { distance: 5e-3 };
    let law = ContactLaw::lecture();
    let mut a = string(
        300,
        48e3,
        Losses::None,
        far(),
        law,
        ContactScheme::Quadratised,
    );
    let mut b = string(
        300,
        48e3,
        Losses::None,
        far(),
        law,
        ContactScheme::NewtonDiscreteGradient,
    );
    pluck(&mut a);
    pluck(&mut b);
    let (ra, rb) = (run(&mut a, 20_000), run(&mut b, 20_000));
    assert_eq!(a.contact_stats().contact_steps, 0);
    assert_eq!(ra.signal, rb.signal);
    assert_eq!(a.modal_displacement(), b.modal_displacement());
    assert_eq!(ra.max, rb.max);
}

/// Relative L2 distance between the two schemes' displacement at 0.37 m over the first 6 ms
/// (more than one period, wrapping onto the bridge) of the lossless sitar (N = 200, the 1 mm
/// pluck) with contact stiffness `k` (α = 1.5), both at `fs`.
fn scheme_distance(fs: f64, k: f64) -> f64 {
    let steps = (6e-3 * fs).round() as usize;
    let law = ContactLaw {
        stiffness: k,
        exponent: 1.5,
    };
    let mut sig = Vec::new();
    for scheme in ContactScheme::ALL {
        let mut s = string(200, fs, Losses::None, Obstacle::seed_sitar(), law, scheme);
        pluck(&mut s);
        sig.push(run(&mut s, steps).signal);
        assert!(s.contact_stats().contact_steps > 0);
    }
    let (mut num, mut den) = (0.0, 0.0);
    for (a, b) in sig[1].iter().zip(&sig[0]) {
        num += (a - b) * (a - b);
        den += b * b;
    }
    (num / den).sqrt()
}

/// Convergence towards the Newton scheme as fs grows (both schemes are consistent with the same
/// equation, so their distance measures the quadratised scheme's extra error where Newton's is
/// smaller or similar). Over fs = 96 kHz · 2^m, m = 0..6 (to 6.1 MHz):
/// - a contact soft enough to be resolved in time (K = 1e9): the least-squares order of the
///   distance must be at least 1.2. The force is a midpoint rule, second-order for smooth
///   motion, but `g ∝ η^{1/4}` and `ψ'' ∝ η^{1/2}` are not smooth at the onset and release of
///   contact; measured: about 1.5 (docs/ACCURACY.md);
/// - the lecture's K = 1e13, whose contacts last a few steps even at MHz rates (local contact
///   frequency `√(ψ''/μ)/2π` ≈ 0.5 MHz at 0.4 µm penetration), so the distance is
///   pre-asymptotic: it must fall by at least 10× from 192 kHz to 6.1 MHz (measured ≈ 80×).
#[test]
fn quadratised_converges_to_newton_as_fs_grows() {
    let rates: Vec<f64> = (0..7).map(|m| 96e3 * f64::from(1u32 << m)).collect();
    let soft: Vec<f64> = rates.iter().map(|&fs| scheme_distance(fs, 1e9)).collect();
    let n = rates.len() as f64;
    let (x, y): (Vec<f64>, Vec<f64>) = rates
        .iter()
        .zip(&soft)
        .map(|(f, d)| (f.log2(), d.log2()))
        .unzip();
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(&y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let order = -sxy / sxx;
    for (fs, d) in rates.iter().zip(&soft) {
        eprintln!("K = 1e9, fs = {fs:>8.0} Hz: relative L2 distance {d:.3e}");
    }
    eprintln!("K = 1e9: least-squares order {order:.2}");
    assert!(order >= 1.2, "{soft:?}");
    let (lo, hi) = (scheme_distance(192e3, 1e13), scheme_distance(6.144e6, 1e13));
    eprintln!("K = 1e13: distance {lo:.3e} at 192 kHz, {hi:.3e} at 6.1 MHz");
    assert!(hi < lo / 10.0, "{lo} {hi}");
}

/// Hostile contact laws (K from 1 to 1e18, the scene's range, α from 1 to 10) hit hard (a
/// 1e4 N strike towards a penetrating point bridge) at 8 kHz and 4 MHz, lossless: every output
/// finite and `H_q` conserved to 1e-13 of its maximum. The node update is solved for the mean
/// `w = μ_{t·}z` (no cancellation of `b` against `k g z⁻` at stiffness ratios `k g²` up to
/// ~1e16), so the identity holds to round-off: measured worst case 2.1e-14 (K = 1e18, α = 4,
/// 8 kHz; printed over 2000 steps). Tolerance 1e-13, five times that; the direct form `r = (b - k g z⁻)/(1 + k g²/4)` gave 1.5e-7 at K = 1e13, α = 10, 8 kHz.
#[test]
fn hostile_contact_laws_stay_finite_and_conservative() {
    let mut worst = 0.0f64;
    for &k in &[1.0, 1e6, 1e13, 1e18] {
        for &alpha in &[1.0, 1.5, 4.0, 10.0] {
            for &fs in &[8e3, 4e6] {
                let law = ContactLaw {
                    stiffness: k,
                    exponent: alpha,
                };
                let point = Obstacle::Point {
                    position: 0.05,
                    height: 1e-4,
                    width: 0.0,
                };
                let mut s = string(
                    100,
                    fs,
                    Losses::None,
                    point,
                    law,
                    ContactScheme::Quadratised,
                );
                s.strike(&StrikeForce {
                    position: 0.1,
                    duration: 1e-3,
                    peak: -1e4,
                })
                .unwrap();
                let r = run(&mut s, 2000);
                eprintln!("K={k:e} alpha={alpha} fs={fs}: balance {:.2e}", r.balance);
                assert!(r.max.is_finite() && r.balance.is_finite());
                worst = worst.max(r.balance);
                assert!(
                    r.balance < 1e-13,
                    "K={k} alpha={alpha} fs={fs}: {}",
                    r.balance
                );
            }
        }
    }
    eprintln!("worst balance error {worst:.2e}");
}

/// The scene field: `contact_scheme = "quadratised"` reaches the model, the default is Newton,
/// and a bad name is a `ParamError` naming `string.contact_scheme`, the value and the choices.
#[test]
fn scene_field_selects_the_scheme() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/seed-sitar.toml");
    let text = std::fs::read_to_string(path).unwrap();
    let load = |o: &[&str]| {
        let o: Vec<String> = o.iter().map(|s| s.to_string()).collect();
        Scene::from_toml(&text, "seed-sitar.toml", &o)
    };
    let newton = load(&[]).unwrap().string.unwrap();
    assert_eq!(
        newton.scheme().unwrap(),
        ContactScheme::NewtonDiscreteGradient
    );
    let sav = load(&["string.contact_scheme=quadratised"]).unwrap();
    let sav = sav.string.unwrap();
    assert_eq!(sav.scheme().unwrap(), ContactScheme::Quadratised);
    let model = noether::render::scene::build_string(&sav).unwrap();
    assert_eq!(model.contact_scheme(), ContactScheme::Quadratised);
    let err = load(&["string.contact_scheme=sav"])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("string.contact_scheme") && err.contains("sav") && err.contains("quadratised"),
        "{err}"
    );
}

/// `noether accuracy --vary scheme` on a string scene (the shared `study`, with the
/// `string.contact_scheme` field): a small sitar (209 modes, 20 ms, four nodes on the bridge)
/// under each scheme at 96 kHz against Newton at 192 kHz; one row per scheme, its report names
/// the scheme; the Newton row is the pure rate error, the quadratised row adds the scheme's;
/// both finite, non-zero and different (the string touched the bridge). Both conserve their
/// energy to round-off: measured balance errors 7.5e-15 (Newton) and 8.9e-15 (quadratised),
/// printed; tolerance 5e-14, about five times that.
#[test]
fn accuracy_study_varies_the_scheme() {
    use noether::render::accuracy::{study, Variant};
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/seed-sitar.toml");
    let load = |extra: &[&str]| {
        let mut o: Vec<String> = ["string.modes=209", "output.seconds=0.02"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        o.extend(extra.iter().map(|s| s.to_string()));
        Scene::load(std::path::Path::new(path), &o).unwrap()
    };
    let variants: Vec<Variant> = ["newton", "quadratised"]
        .iter()
        .map(|name| Variant {
            setting: name.to_string(),
            value: None,
            scene: load(&[
                "string.sim_rate=96000",
                &format!("string.contact_scheme={name}"),
            ]),
        })
        .collect();
    let reference = load(&["string.sim_rate=192000"]);
    let st = study(
        "scheme",
        &variants,
        &reference,
        "newton at 192 kHz".into(),
        |_| {},
    )
    .unwrap();
    let schemes: Vec<_> = st.rows.iter().map(|r| r.scheme.as_str()).collect();
    assert_eq!(
        schemes,
        [
            "exact-modal+discrete-gradient-contact",
            "exact-modal+quadratised-contact"
        ]
    );
    for r in &st.rows {
        eprintln!(
            "{}: L2 {:.3e}, LSD {:.3} dB, balance {:.2e}",
            r.setting, r.l2_50ms, r.lsd_db, r.energy_balance_error
        );
        assert!(r.l2_50ms.is_finite() && r.l2_50ms > 0.0 && r.lsd_db.is_finite());
        assert!(r.energy_balance_error < 5e-14, "{}", r.energy_balance_error);
    }
    assert_ne!(st.rows[0].l2_50ms, st.rows[1].l2_50ms);
}

/// The relaxation of `z` (`models::sav_relaxation`, off by default for the contact; here
/// τ = 2 ms) pulls the auxiliary of
/// each node off the obstacle back to `√(2ψ(η)) = 0`: on the lossless sitar at 48 kHz, whose
/// nodes leave the bridge with `z` frozen at whatever the last contact left, the energy held
/// by released nodes (`StiffString::released_contact_energy`) over the last half of a 1 s
/// pluck is far smaller relaxed than plain (the bound asks 5×; measured 8×: 1.4e-3 of the
/// energy against 1.1e-2), while the energy plus what the relaxation removed stays constant to 1e-9
/// of the peak and the energy never exceeds its start (lossless: it gives back at most what it
/// took). Figures printed with `--nocapture`.
#[test]
fn relaxation_pulls_z_back_to_its_definition() {
    use noether::models::sav_relaxation::SavRelaxation;
    let law = ContactLaw::lecture();
    let measure = |relaxed: bool| {
        let mut s = string(
            500,
            48e3,
            Losses::None,
            Obstacle::seed_sitar(),
            law,
            ContactScheme::Quadratised,
        );
        s.set_sav_relaxation(if relaxed {
            SavRelaxation::from_scene(2e-3, 1.0 / 48e3)
        } else {
            SavRelaxation::OFF
        });
        pluck(&mut s);
        let mut out = vec![vec![0.0; 1]; s.channels()];
        s.process(&mut out, 1);
        let e0 = s.energy();
        let (b0, h0) = (e0.total() + e0.dissipated, e0.total());
        let (mut gap, mut drift, mut over) = (0.0f64, 0.0f64, 0.0f64);
        for n in 1..48_000 {
            s.process(&mut out, 1);
            let e = s.energy();
            drift = drift.max((e.total() + e.dissipated - b0).abs() / h0);
            over = over.max(e.total() - h0);
            if n >= 24_000 {
                gap = gap.max(s.released_contact_energy() / h0);
            }
        }
        eprintln!(
            "sitar 48 kHz quadratised, relaxed {relaxed}: gap {gap:.2e} of H, balance {drift:.2e}, \
             relaxation removed {:.2e} of H",
            s.relaxed() / h0
        );
        assert!(drift < 1e-9, "{drift}");
        assert!(over <= 1e-9 * h0, "energy rose by {over}");
        gap
    };
    let (plain, relaxed) = (measure(false), measure(true));
    assert!(relaxed * 5.0 < plain, "{relaxed} vs {plain}");
}
