//! Circular-plate modal data: eigenvalues, normalisation, coupling tensor, E/H identity.
//!
//! Reference values: Leissa, "Vibration of Plates", NASA SP-160, 1969, Table 2.1 (clamped) and
//! Table 2.3 (free, ν = 0.33); 30-digit mpmath 1.3.0 roots of the same characteristic equations
//! (Bessel functions and root finder independent of the crate's). Direct quadratures below use
//! the crate's Gauss-Legendre rule in r (itself tested against monomials) and a uniform
//! trapezoid rule in θ, exact for the trigonometric polynomials involved; they do not use the
//! crate's analytic angular integrals nor its A/B/C radial sampling.

use noether::modal::angular::Parity;
use noether::modal::basis::{circular_modes, omega_scale, CircularPlateSpec, Mode, PlateModes};
use noether::modal::circular::{characteristic, CircularEdge};
use noether::modal::quadrature::GaussLegendre;
use std::f64::consts::PI;
use std::sync::OnceLock;

/// The lecture's gong basis (free edge, ν = 0.3, N_Φ = 1000, N_Ψ = 300, default quadrature).
fn gong() -> &'static PlateModes {
    static G: OnceLock<PlateModes> = OnceLock::new();
    G.get_or_init(|| {
        let spec = CircularPlateSpec::new(CircularEdge::Free, 0.3, 1000, 300, None).unwrap();
        PlateModes::build(&spec).unwrap()
    })
}

fn lam2(m: &Mode) -> f64 {
    m.radial.lambda * m.radial.lambda
}

/// First distinct eigenvalues λ² of `modes`, with their (n, k) labels.
fn distinct(modes: &[Mode], count: usize) -> Vec<(u32, u32, f64)> {
    let mut out: Vec<(u32, u32, f64)> = Vec::new();
    for m in modes {
        if out.last().is_none_or(|l| (l.0, l.1) != (m.n, m.k)) {
            out.push((m.n, m.k, lam2(m)));
        }
    }
    out.truncate(count);
    out
}

#[test]
fn free_eigenvalues_match_mpmath_roots_and_counting() {
    // mpmath roots of Leissa eq. 2.14 (30 digits), printed to 16 digits: tolerance 1e-13
    // relative (the crate's roots are bracketed to adjacent doubles; Bessel accuracy ~1e-15).
    let nu03 = [
        (2, 0, 5.358329787899912),
        (0, 1, 9.003137350295527),
        (3, 0, 12.43898816540814),
        (1, 1, 20.47455011393814),
        (4, 0, 21.83516270416938),
        (5, 0, 33.4949315875084),
        (2, 1, 35.26010831537333),
        (0, 2, 38.44319824475232),
    ];
    let nu033 = [
        (2, 0, 5.262036960297072),
        (0, 1, 9.068898661786181),
        (3, 0, 12.24389425795421),
        (1, 1, 20.51308690567648),
        (4, 0, 21.52721721534074),
    ];
    for (nu, table) in [(0.3, &nu03[..]), (0.33, &nu033[..])] {
        let modes = circular_modes(CircularEdge::Free, nu, 20);
        let got = distinct(&modes, table.len());
        for (&(n, k, v), &(gn, gk, g)) in table.iter().zip(&got) {
            assert_eq!((n, k), (gn, gk), "ν={nu}: label order");
            assert!((g / v - 1.0).abs() < 1e-13, "ν={nu} ({n},{k}): {g} vs {v}");
        }
        // Counting: pairs count twice, rigid modes excluded: (2,0)c,(2,0)s,(0,1),(3,0)c,(3,0)s.
        let labels: Vec<_> = modes[..5].iter().map(|m| (m.n, m.k, m.parity)).collect();
        assert_eq!(
            labels,
            vec![
                (2, 0, Parity::Cos),
                (2, 0, Parity::Sin),
                (0, 1, Parity::Cos),
                (3, 0, Parity::Cos),
                (3, 0, Parity::Sin)
            ]
        );
    }
}

#[test]
fn free_eigenvalues_agree_with_leissa_table_to_its_accuracy() {
    // Leissa Table 2.3 (ν = 0.33) prints 5.253, 9.084, 12.23, 20.52 for (2,0), (0,1), (3,0),
    // (1,1). Those older values differ from the exact roots by up to 0.17 % (the mpmath roots
    // of the same equation are 5.2620, 9.0689, 12.244, 20.513), so the tolerance here is
    // 0.25 %: it catches a wrong edge condition (ν-terms alone move these by > 1 %), not digits.
    let leissa = [(2, 0, 5.253), (0, 1, 9.084), (3, 0, 12.23), (1, 1, 20.52)];
    let modes = circular_modes(CircularEdge::Free, 0.33, 10);
    for (&(n, k, v), &(gn, gk, g)) in leissa.iter().zip(&distinct(&modes, 4)) {
        assert_eq!((n, k), (gn, gk));
        assert!((g / v - 1.0).abs() < 2.5e-3, "({n},{k}): {g} vs {v}");
    }
}

#[test]
fn clamped_eigenvalues_match_leissa_table() {
    // Leissa Table 2.1, λ² = ω a² √(ρh/D); tolerance: half a unit of the last printed digit.
    let leissa = [
        (0, 0, 10.2158, 1e-4),
        (1, 0, 21.26, 1e-2),
        (2, 0, 34.88, 1e-2),
        (0, 1, 39.771, 1e-3),
        (4, 0, 69.666, 1e-3),
        (0, 2, 89.104, 1e-3),
        (5, 0, 90.739, 1e-3),
    ];
    let modes = circular_modes(CircularEdge::Clamped, 0.3, 40);
    let got = distinct(&modes, 30);
    for &(n, k, v, ulp) in &leissa {
        let g = got.iter().find(|t| (t.0, t.1) == (n, k)).unwrap().2;
        assert!((g - v).abs() <= 0.5 * ulp + 1e-12, "({n},{k}): {g} vs {v}");
    }
    // and the mpmath roots to 1e-13 relative
    for &(n, k, v) in &[
        (0, 0, 10.21582622986728),
        (3, 0, 51.03003548377612),
        (1, 2, 120.0792365826225),
    ] {
        let g = got.iter().find(|t| (t.0, t.1) == (n, k)).unwrap().2;
        assert!((g / v - 1.0).abs() < 1e-13, "({n},{k}): {g} vs {v}");
    }
}

#[test]
fn characteristic_residual_and_bracket_at_every_root() {
    // Each root must be bracketed by a sign change within ±1e-13 relative (root located to
    // that accuracy), and the relative residual |f|/(|a|+|b|) must be below 1e-12.
    let g = gong();
    for (edge, modes) in [
        (CircularEdge::Free, &g.phi),
        (CircularEdge::Clamped, &g.psi),
    ] {
        for m in modes.iter() {
            let x = m.radial.lambda;
            let (f, s) = characteristic(edge, 0.3, m.n, x);
            assert!(
                f.abs() <= 1e-12 * s,
                "{edge:?} ({},{}): {f} / {s}",
                m.n,
                m.k
            );
            let lo = characteristic(edge, 0.3, m.n, x * (1.0 - 1e-13)).0;
            let hi = characteristic(edge, 0.3, m.n, x * (1.0 + 1e-13)).0;
            assert!(lo * hi <= 0.0, "{edge:?} ({},{}) not bracketed", m.n, m.k);
        }
    }
}

#[test]
fn gong_thousandth_mode_frequency() {
    // SEED "Facts": the 1000th elastic mode of the lecture's gong (a = 0.4 m, h = 1 mm,
    // E = 2e11 Pa, ν = 0.3, ρ = 7860 kg/m³) is near 5.77 kHz (tolerance ±5 Hz, the printed
    // precision); counting the 3 rigid modes among 1000 (the 997th elastic mode) gives the
    // lecture's stability bound π f = 18055 Hz (tolerance 0.05 %: the bound is printed to 5
    // digits and was computed by the lecture's own code).
    let g = gong();
    let s = omega_scale(0.4, 1e-3, 2e11, 7860.0, 0.3).unwrap();
    let f = |i: usize| s * g.omega[i] / (2.0 * PI);
    assert!((f(999) - 5770.0).abs() < 5.0, "f_1000 = {}", f(999));
    assert!(
        (PI * f(996) / 18055.0 - 1.0).abs() < 5e-4,
        "π f_997 = {}",
        PI * f(996)
    );
}

/// Radial profile samples `R, R', R''` of `m` on the nodes of `gl`.
fn samples(m: &Mode, gl: &GaussLegendre) -> Vec<[f64; 3]> {
    gl.nodes.iter().map(|&r| m.radial.eval(r)).collect()
}

/// Angular factor of `m` and its θ-derivative at `theta`.
fn ang(m: &Mode, theta: f64) -> (f64, f64) {
    let n = m.n as f64;
    match m.parity {
        Parity::Cos => ((n * theta).cos(), -n * (n * theta).sin()),
        Parity::Sin => ((n * theta).sin(), n * (n * theta).cos()),
    }
}

#[test]
fn modes_are_orthonormal_by_quadrature() {
    // ∫ Φ_i Φ_j dS = δ_ij to 1e-10 by a 2D rule (300 Gauss points in r, trapezoid in θ exact
    // for degree < M): checks the closed-form (Lommel) normalisation and the eigenfunctions.
    let g = gong();
    let gl = GaussLegendre::new(300).unwrap();
    let pick: Vec<usize> = (0..60).chain(940..1000).collect();
    for (modes, idx) in [
        (&g.phi, &pick),
        (&g.psi, &(0..120).chain(280..300).collect()),
    ] {
        let nmax = idx.iter().map(|&i| modes[i].n).max().unwrap() as usize;
        let mt = 2 * nmax + 8;
        let rad: Vec<Vec<[f64; 3]>> = idx.iter().map(|&i| samples(&modes[i], &gl)).collect();
        let th: Vec<Vec<f64>> = idx
            .iter()
            .map(|&i| {
                (0..mt)
                    .map(|t| ang(&modes[i], 2.0 * PI * t as f64 / mt as f64).0)
                    .collect()
            })
            .collect();
        for a in 0..idx.len() {
            for b in 0..=a {
                let rr: f64 = (0..gl.len())
                    .map(|q| gl.weights[q] * gl.nodes[q] * rad[a][q][0] * rad[b][q][0])
                    .sum();
                let tt: f64 =
                    (0..mt).map(|t| th[a][t] * th[b][t]).sum::<f64>() * 2.0 * PI / mt as f64;
                let want = if a == b { 1.0 } else { 0.0 };
                assert!(
                    (rr * tt - want).abs() < 1e-10,
                    "modes {} {}: {}",
                    idx[a],
                    idx[b],
                    rr * tt
                );
            }
        }
    }
}

#[test]
fn edge_conditions_hold() {
    // Clamped-type Ψ: R(1) = R'(1) = 0; free Φ: M_r ∝ R'' + ν(R' - n² R) = 0 at r = 1.
    // Tolerance 1e-11 relative to max(|R|, |R'|, |R''|) at the edge (λ up to 62: derivatives
    // carry λ² and cancellation of two terms of that size).
    let g = gong();
    for m in &g.psi {
        let [r0, r1, _] = m.radial.eval(1.0);
        let scale = m.radial.eval(0.9)[0].abs().max(1.0) * m.radial.lambda;
        assert!(
            r0.abs() < 1e-11 * scale && r1.abs() < 1e-11 * scale,
            "{:?}",
            (r0, r1)
        );
    }
    for m in &g.phi {
        let [r0, r1, r2] = m.radial.eval(1.0);
        let n2 = (m.n * m.n) as f64;
        let mr = r2 + 0.3 * (r1 - n2 * r0);
        let scale = r0.abs().max(r1.abs()).max(r2.abs()).max(n2 * r0.abs());
        assert!(
            mr.abs() < 1e-11 * scale,
            "({},{}): M_r {mr} scale {scale}",
            m.n,
            m.k
        );
    }
}
