//! The strike-mirror basis (`plate.symmetry = "strike-mirror"`): a strike excites only motion
//! even about its diameter, and that subspace is invariant under the von Kármán coupling (odd
//! numbers of `sin` factors integrate to exactly 0), so the mirror model is the full model
//! restricted to it. Checked end to end: a full basis whose truncation splits no `cos/sin`
//! pair, struck off the basis axis, against the mirror basis of the same band (its `cos`
//! modes, in the strike's frame).

use noether::modal::{circular_modes_with, CircularEdge, Parity};
use noether::render::scene::render_scene;
use noether::scene::Scene;

/// Smallest count ≥ `at_least` whose truncation keeps every `cos/sin` pair whole, and how
/// many `cos` modes it holds.
fn whole_pairs(edge: CircularEdge, at_least: usize) -> (usize, usize) {
    let modes = circular_modes_with(edge, 0.3, at_least + 2, false);
    let mut n = at_least;
    while modes[n - 1].n > 0 && modes[n - 1].parity == Parity::Cos {
        n += 1;
    }
    let cos = modes[..n]
        .iter()
        .filter(|m| m.parity == Parity::Cos)
        .count();
    (n, cos)
}

fn scene(n_phi: usize, n_psi: usize, symmetry: &str) -> Scene {
    let text = format!(
        r#"
[output]
sample_rate = 48000
seconds = 0.05
[plate]
shape = "circular-free"
radius = 0.3
thickness = 0.001
n_phi = {n_phi}
n_psi = {n_psi}
symmetry = "{symmetry}"
sim_rate = 48000
scheme = "conservative-exact"
damping = {{ law = "power", a = 0.005, b = 0.6 }}
excitation = {{ kind = "strike", at = {{ r = 0.62, angle = 0.7 }}, duration = 0.001, peak_force = 200.0 }}
pickups = [
  {{ at = {{ r = 0.85, angle = -0.4 }}, quantity = "velocity" }},
  {{ at = {{ r = 0.5, angle = 2.0 }}, quantity = "displacement" }},
]
"#
    );
    noether_testkit::env::test_cache_dir();
    Scene::from_toml(&text, "mirror-test", &[]).unwrap()
}

/// The two renders agree to round-off: 1e-9 of each channel's peak (both evaluate the same
/// recursion on the same tensor entries — the quadrature order depends only on the band —
/// in a rotated basis, so only the summation order differs; the run is 2400 steps of a
/// 200 N strike whose in-plane energy share is checked to be non-negligible, so the
/// nonlinear coupling is exercised), and the energies agree to 1e-9 relative.
#[test]
fn mirror_basis_is_the_full_model_on_the_struck_subspace() {
    let (n_phi, m_phi) = whole_pairs(CircularEdge::Free, 40);
    let (n_psi, m_psi) = whole_pairs(CircularEdge::Clamped, 14);
    assert!(m_phi < n_phi && m_psi < n_psi);
    let (full, full_report) = render_scene(&scene(n_phi, n_psi, "full"), |_| {}).unwrap();
    let (mirror, mirror_report) =
        render_scene(&scene(m_phi, m_psi, "strike-mirror"), |_| {}).unwrap();
    let share = full
        .energy
        .iter()
        .map(|e| e.nonlinear / (e.kinetic + e.linear + e.nonlinear).max(f64::MIN_POSITIVE))
        .fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for (a, b) in full.out.iter().zip(&mirror.out) {
        let peak = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let diff = a
            .iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(peak > 0.0);
        worst = worst.max(diff / peak);
    }
    let (ef, em) = (full.energy.last().unwrap(), mirror.energy.last().unwrap());
    let (tf, tm) = (
        ef.kinetic + ef.linear + ef.nonlinear,
        em.kinetic + em.linear + em.nonlinear,
    );
    eprintln!(
        "full {n_phi} x {n_psi} ({} nonzeros, {:.3} s) vs mirror {m_phi} x {m_psi} ({} nonzeros, {:.3} s): \
         output difference {worst:.2e} of peak, energy {:.2e} relative, in-plane share {share:.2e}",
        full_report.details["tensor_nonzeros"],
        full_report.wall_seconds,
        mirror_report.details["tensor_nonzeros"],
        mirror_report.wall_seconds,
        (tf - tm).abs() / tf
    );
    assert!(
        share > 1e-3,
        "the strike should load the in-plane modes: {share}"
    );
    assert!(worst < 1e-9, "{worst}");
    assert!((tf - tm).abs() / tf < 1e-9);
}

/// `strike-mirror` is refused on rectangles with the field, the value and the allowed values.
#[test]
fn mirror_is_refused_on_rectangles() {
    let text = r#"
[output]
sample_rate = 48000
seconds = 0.01
[plate]
shape = "rect-ss"
lx = 0.4
ly = 0.6
thickness = 0.001
n_phi = 10
n_psi = 5
symmetry = "strike-mirror"
sim_rate = 48000
scheme = "sav"
excitation = { kind = "strike", at = { x = 0.3, y = 0.4 }, duration = 0.001, peak_force = 10.0 }
"#;
    let e = Scene::from_toml(text, "rect", &[]).unwrap_err().to_string();
    assert!(
        e.contains("plate.symmetry") && e.contains("strike-mirror") && e.contains("full"),
        "{e}"
    );
}
