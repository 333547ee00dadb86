//! Modal data of the simply supported rectangle with in-plane edges free of stress
//! (`noether::modal::rect`): closed-form Φ, Rayleigh-Ritz Ψ, coupling tensor H.

use noether::modal::rect::{RectModes, RectSpec};
use std::f64::consts::PI;

/// Gauss-Legendre rule on `[0, len]` from the identity `∫ x^k` (independent of the crate's
/// own rule): nodes by Newton on `L_n`.
fn gl(n: usize, len: f64) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        let mut t = (PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, t);
            for k in 1..n {
                let kf = k as f64;
                let p2 = ((2.0 * kf + 1.0) * t * p1 - kf * p0) / (kf + 1.0);
                p0 = p1;
                p1 = p2;
            }
            dp = n as f64 * (t * p1 - p0) / (t * t - 1.0);
            let dt = p1 / dp;
            t -= dt;
            if dt.abs() < 1e-16 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - t * t) * dp * dp);
        out.push((0.5 * len * (t + 1.0), 0.5 * len * w));
    }
    out
}

/// `[Φ, Φ_x, Φ_y, Φ_xx, Φ_yy, Φ_xy]` of mode (m, n) in dimensionless coordinates.
fn phi_derivs(aspect: f64, (m, n): (u32, u32), x: f64, y: f64) -> [f64; 6] {
    let (k, u) = (f64::from(m) * PI, f64::from(n) * PI / aspect);
    let c = 2.0 / aspect.sqrt();
    let (sx, cx, sy, cy) = ((k * x).sin(), (k * x).cos(), (u * y).sin(), (u * y).cos());
    [
        c * sx * sy,
        c * k * cx * sy,
        c * u * sx * cy,
        -c * k * k * sx * sy,
        -c * u * u * sx * sy,
        c * k * u * cx * cy,
    ]
}

/// `L(f, g) = f_xx g_yy + f_yy g_xx - 2 f_xy g_xy` from derivative arrays.
fn l_op(f: &[f64; 6], g: &[f64; 6]) -> f64 {
    f[3] * g[4] + f[4] * g[3] - 2.0 * f[5] * g[5]
}

#[test]
fn transverse_modes_match_closed_form() {
    // Tolerance 1e-12 relative: the closed form evaluated in two groupings differs by a few ulp.
    for aspect in [1.0, 1.5, 4.0 / 3.0, 0.37] {
        let m = RectModes::build(&RectSpec::new(aspect, 300, 1)).unwrap();
        assert_eq!(m.lambda2.len(), 300);
        for (k, &(mm, nn)) in m.labels.iter().enumerate() {
            let w = PI * PI * ((mm as f64).powi(2) + (nn as f64 / aspect).powi(2));
            assert!((m.lambda2[k] - w).abs() <= 1e-12 * w, "{aspect} {k}");
        }
        assert!(m.lambda2.windows(2).all(|p| p[0] <= p[1]));
        // No mode below the last one is missing: brute-force count of (m, n) with ω < ω_last.
        let last = m.lambda2[299];
        let below = (1..200u32)
            .flat_map(|a| (1..400u32).map(move |b| (a, b)))
            .filter(|&(a, b)| PI * PI * ((a as f64).powi(2) + (b as f64 / aspect).powi(2)) < last)
            .count();
        let listed_below = m.lambda2.iter().filter(|&&w| w < last).count();
        assert_eq!(below, listed_below, "aspect {aspect}");
    }
    // Square: ties broken by m, deterministically.
    let sq = RectModes::build(&RectSpec::new(1.0, 5, 1)).unwrap();
    assert_eq!(sq.labels, vec![(1, 1), (1, 2), (2, 1), (2, 2), (1, 3)]);
}

#[test]
fn phi_at_is_normalised_and_orthogonal() {
    let aspect = 1.5;
    let m = RectModes::build(&RectSpec::new(aspect, 40, 1)).unwrap();
    // Exact value at a point (1e-14: one product of sines).
    let (mm, nn) = m.labels[7];
    let v = 2.0 / aspect.sqrt() * (mm as f64 * PI * 0.3).sin() * (nn as f64 * PI * 0.8).sin();
    assert!((m.phi_at(7, 0.3, 0.8) - v).abs() < 1e-14);
    // ∫Φ_iΦ_j dS = δ_ij by 60×60 Gauss-Legendre in fractions (exact to ~1e-13 for m, n ≤ 10).
    let (qx, qy) = (gl(60, 1.0), gl(60, 1.0));
    for i in 0..40 {
        for j in 0..=i {
            let mut s = 0.0;
            for &(xi, wx) in &qx {
                for &(eta, wy) in &qy {
                    s += wx * wy * aspect * m.phi_at(i, xi, eta) * m.phi_at(j, xi, eta);
                }
            }
            let e = if i == j { 1.0 } else { 0.0 };
            assert!((s - e).abs() < 1e-12, "({i},{j}) {s}");
        }
    }
}

#[test]
fn lecture_plate_frequencies() {
    // SEED.md sec. 3.1: steel E = 200 GPa, ν = 0.3, ρ = 7860 kg/m³, h = 1 mm.
    let (e, nu, rho, h) = (200e9, 0.3, 7860.0, 1e-3);
    let d = e * h * h * h / (12.0 * (1.0 - nu * nu));
    // 0.4 × 0.6 m, N_Φ = 100: "f_NΦ = 1400 Hz" (4 digits: within 0.5 Hz after rounding).
    let a = RectModes::build(&RectSpec::new(0.6 / 0.4, 100, 1)).unwrap();
    let f100 = a.omega_physical(0.4, d, rho * h).unwrap()[99] / (2.0 * PI);
    assert!((f100 - 1400.0).abs() < 0.5, "f_100 = {f100}");
    // 0.6 × 0.8 m, N_Φ = 800: "f_NΦ = 5295 Hz". We get 5295.55 Hz: the printed figure is
    // truncated, so check the printed digits to within one unit of the last one.
    let b = RectModes::build(&RectSpec::new(0.8 / 0.6, 800, 1)).unwrap();
    let f800 = b.omega_physical(0.6, d, rho * h).unwrap()[799] / (2.0 * PI);
    assert!((f800 - 5295.0).abs() < 1.0, "f_800 = {f800}");
    assert_eq!(f800.trunc(), 5295.0);
}

#[test]
fn airy_eigenvalues_converge_when_basis_doubles() {
    // First 50 ζ⁴ for aspect 1.5: automatic basis vs twice as many functions per direction.
    // Spectral convergence: relative change < 1e-8 asked; we assert 1e-9 (observed ~1e-12).
    let spec = RectSpec::new(1.5, 4, 50);
    let base = RectModes::build(&spec).unwrap();
    let (nx, ny) = base.basis;
    let mut fine = spec.clone();
    fine.basis_x = Some(2 * nx);
    fine.basis_y = Some(2 * ny);
    let fine = RectModes::build(&fine).unwrap();
    let mut worst = 0.0f64;
    for k in 0..50 {
        let rel = (base.zeta4[k] - fine.zeta4[k]).abs() / fine.zeta4[k];
        assert!(
            rel < 1e-9,
            "mode {k}: {} vs {} ({rel:e})",
            base.zeta4[k],
            fine.zeta4[k]
        );
        worst = worst.max(rel);
    }
    eprintln!(
        "basis {:?} -> doubled: worst relative change of ζ⁴_1..50 {worst:.2e}",
        base.basis
    );
    // Rayleigh-Ritz on nested spaces: the finer basis never gives a larger eigenvalue (up to
    // roundoff of ~1e-13 relative).
    for k in 0..50 {
        assert!(fine.zeta4[k] <= base.zeta4[k] * (1.0 + 1e-12));
    }
}

#[test]
fn airy_lecture_size_is_converged() {
    // N_Ψ = 200 for the lecture's 0.4 × 0.6 plate: automatic basis vs 16 more functions per
    // direction; all 200 ζ⁴ agree to 1e-9 relative (observed ~2e-12).
    let spec = RectSpec::new(1.5, 4, 200);
    let base = RectModes::build(&spec).unwrap();
    let mut more = spec.clone();
    more.basis_x = Some(base.basis.0 + 16);
    more.basis_y = Some(base.basis.1 + 16);
    let more = RectModes::build(&more).unwrap();
    let mut worst = 0.0f64;
    for k in 0..200 {
        let rel = (base.zeta4[k] - more.zeta4[k]).abs() / more.zeta4[k];
        assert!(rel < 1e-9, "mode {k}: rel {rel:e}");
        worst = worst.max(rel);
    }
    eprintln!(
        "basis {:?} (+16): worst relative change of ζ⁴_1..200 {worst:.2e}",
        base.basis
    );
}

#[test]
fn square_clamped_plate_against_leissa() {
    // Ψ modes are the clamped-plate modes: λ² = sqrt(ζ⁴) with a = 1. Leissa (NASA SP-160,
    // 1969; JSV 31, 1973) prints 35.992, 73.413, 108.27, 131.64, 132.24, 165.15 from a
    // 36-term beam-function Ritz, an upper bound: converged values must lie below and within
    // 0.1 % (his Ritz error), and the two modes related by x <-> y must be degenerate.
    let m = RectModes::build(&RectSpec::new(1.0, 4, 12)).unwrap();
    let lam: Vec<f64> = m.zeta4.iter().map(|z| z.sqrt()).collect();
    // The square has the (2,1)/(1,2)-like pair at index 1, 2 (classes odd-even, even-odd).
    assert!((lam[1] - lam[2]).abs() < 1e-10 * lam[1]);
    let ours = [lam[0], lam[1], lam[3], lam[4], lam[5], lam[6]];
    eprintln!("square clamped λ²: {ours:.10?}");
    let leissa = [35.992, 73.413, 108.27, 131.64, 132.24, 165.15];
    for (k, (&o, &l)) in ours.iter().zip(&leissa).enumerate() {
        assert!(o <= l && (l - o) / o < 1e-3, "mode {k}: {o} vs Leissa {l}");
    }
    // The fundamental rounds to Leissa's printed 35.99 (his error there is below the 4th digit).
    assert_eq!((lam[0] * 100.0).round() / 100.0, 35.99);
}

#[test]
fn airy_modes_orthonormal_and_clamped() {
    let aspect = 1.5;
    let m = RectModes::build(&RectSpec::new(aspect, 4, 200)).unwrap();
    let picks: Vec<usize> = (0..24).chain([100, 150, 199]).collect();
    // Ψ are polynomials of degree ≤ basis + 3 per direction: Gauss-Legendre with basis + 8
    // points is exact, leaving roundoff only; tolerance 1e-10 as required.
    let (nx, ny) = m.basis;
    let (qx, qy) = (gl(nx + 8, 1.0), gl(ny + 8, 1.0));
    let vals: Vec<Vec<f64>> = picks
        .iter()
        .map(|&l| {
            let mut v = Vec::with_capacity(qx.len() * qy.len());
            for &(x, _) in &qx {
                for &(yf, _) in &qy {
                    v.push(m.psi_derivs_at(l, x, yf)[0]);
                }
            }
            v
        })
        .collect();
    let w: Vec<f64> = qx
        .iter()
        .flat_map(|&(_, wx)| qy.iter().map(move |&(_, wy)| wx * wy * aspect))
        .collect();
    let mut worst = 0.0f64;
    for a in 0..picks.len() {
        for b in 0..=a {
            let s: f64 = (0..w.len()).map(|k| w[k] * vals[a][k] * vals[b][k]).sum();
            let e = if a == b { 1.0 } else { 0.0 };
            assert!(
                (s - e).abs() < 1e-10,
                "<Ψ{}, Ψ{}> = {s}",
                picks[a],
                picks[b]
            );
            worst = worst.max((s - e).abs());
        }
    }
    eprintln!("Ψ Gram matrix: worst deviation from identity {worst:.2e}");
    // Boundary: Ψ = ∇Ψ = 0 on the edges, to roundoff of O(ζ²)-sized derivatives.
    for &l in &picks {
        for t in [0.0, 0.13, 0.5, 0.77, 1.0] {
            for (x, y) in [(0.0, t), (1.0, t), (t, 0.0), (t, 1.0)] {
                let d = m.psi_derivs_at(l, x, y);
                assert!(d[0].abs() < 1e-11, "Ψ{l}({x},{y}) = {}", d[0]);
                assert!(d[1].abs() < 1e-8 && d[2].abs() < 1e-8, "∇Ψ{l}({x},{y})");
            }
        }
    }
}

/// `∫ f g dS` by tensor Gauss-Legendre, with `f`, `g` given as closures on dimensionless x, y.
fn quad2(aspect: f64, n: usize, f: impl Fn(f64, f64) -> f64) -> f64 {
    let (qx, qy) = (gl(n, 1.0), gl(n, aspect));
    let mut s = 0.0;
    for &(x, wx) in &qx {
        for &(y, wy) in &qy {
            s += wx * wy * f(x, y);
        }
    }
    s
}

#[test]
fn coupling_symmetry_and_parity_rules_are_exact() {
    let aspect = 1.5;
    let m = RectModes::build(&RectSpec::new(aspect, 60, 40)).unwrap();
    let c = m.triplets();
    assert_eq!((c.n_phi, c.n_psi), (60, 40));
    // Sorted by (l, i, j), j ≤ i, and every stored entry obeys the parity rule.
    for k in 0..c.len() {
        assert!(c.j[k] <= c.i[k]);
        if k > 0 {
            assert!((c.l[k - 1], c.i[k - 1], c.j[k - 1]) < (c.l[k], c.i[k], c.j[k]));
        }
        let (mi, ni) = m.labels[c.i[k] as usize];
        let (mj, nj) = m.labels[c.j[k] as usize];
        let (px, py) = m.psi_parity[c.l[k] as usize];
        assert_eq!(((mi + mj) % 2) as u8, px);
        assert_eq!(((ni + nj) % 2) as u8, py);
    }
    // Every allowed pair is stored: count them independently.
    let mut allowed = 0;
    for l in 0..40 {
        let (px, py) = m.psi_parity[l];
        for i in 0..60 {
            for j in 0..=i {
                let (li, lj) = (m.labels[i], m.labels[j]);
                if ((li.0 + lj.0) % 2) as u8 == px && ((li.1 + lj.1) % 2) as u8 == py {
                    allowed += 1;
                }
                // Exact symmetry (bitwise) and equality with the stored value.
                let (a, b) = (m.h_entry(l, i, j), m.h_entry(l, j, i));
                assert_eq!(a.to_bits(), b.to_bits(), "H^{l}_{i}{j}");
                assert_eq!(a.to_bits(), c.get(l, i, j).to_bits());
            }
        }
    }
    assert_eq!(allowed, c.len());
    // The rule is right, not only consistent: forbidden entries vanish by direct quadrature
    // (to 1e-12 of the largest entry: odd integrands on symmetric nodes), allowed ones match
    // the separated computation (1e-11 of the largest; observed ~1e-15).
    let scale = c.value.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let forbidden = [(0, 1, 0), (1, 0, 0), (3, 7, 2), (7, 4, 1)];
    let allowed: Vec<(usize, usize, usize)> = (1..5)
        .map(|q| q * c.len() / 5)
        .map(|k| (c.l[k] as usize, c.i[k] as usize, c.j[k] as usize))
        .collect();
    for &(l, i, j) in forbidden.iter().chain(&allowed) {
        let direct = quad2(aspect, 60, |x, y| {
            let psi = m.psi_derivs_at(l, x, y / aspect)[0];
            let (fi, fj) = (
                phi_derivs(aspect, m.labels[i], x, y),
                phi_derivs(aspect, m.labels[j], x, y),
            );
            psi * l_op(&fi, &fj)
        });
        let stored = c.get(l, i, j);
        eprintln!("H^{l}_{i},{j}: stored {stored:.6e}, direct quadrature {direct:.6e}");
        if forbidden.contains(&(l, i, j)) {
            assert_eq!(stored, 0.0, "H^{l}_{i}{j} should be forbidden by parity");
            assert!(
                direct.abs() < 1e-12 * scale,
                "forbidden H^{l}_{i}{j} = {direct}"
            );
        } else {
            assert!((direct - stored).abs() < 1e-11 * scale, "H^{l}_{i}{j}");
        }
    }
}

#[test]
fn e_tensor_equals_h_by_integration_by_parts() {
    // E^s_{i,j} = ∫Φ_s L(Φ_i, Ψ_j) dS (derivatives on Ψ, direct quadrature) must equal
    // H^j_{s,i}, because Ψ = ∇Ψ = 0 on the edges. Quadrature 80×80 Gauss-Legendre: the
    // integrand is a polynomial times trig functions of low order, resolved to ~1e-12;
    // tolerance 1e-11 of the largest |H| (observed ~1e-15).
    let aspect = 4.0 / 3.0;
    let m = RectModes::build(&RectSpec::new(aspect, 30, 30)).unwrap();
    let scale = m
        .triplets()
        .value
        .iter()
        .fold(0.0f64, |a, v| a.max(v.abs()));
    // Nonzero H entries spread over the stored list give (s, i, j) = (i_t, j_t, l_t) and
    // (j_t, i_t, l_t); plus two parity-forbidden triples where both sides must vanish.
    let c = m.triplets();
    let mut triples = vec![(10, 4, 7), (29, 17, 29)];
    for q in 1..5 {
        let k = q * c.len() / 5;
        triples.push((c.i[k] as usize, c.j[k] as usize, c.l[k] as usize));
        triples.push((c.j[k] as usize, c.i[k] as usize, c.l[k] as usize));
    }
    for (s, i, j) in triples {
        let e = quad2(aspect, 80, |x, y| {
            let psi = m.psi_derivs_at(j, x, y / aspect);
            let fs = phi_derivs(aspect, m.labels[s], x, y)[0];
            fs * l_op(&phi_derivs(aspect, m.labels[i], x, y), &psi)
        });
        let h = c.get(j, s, i);
        eprintln!(
            "E^{s}_{i},{j} - H^{j}_{s},{i} = {:.2e} (H = {h:.6e}, max|H| {scale:.3e})",
            e - h
        );
        assert!(
            (e - h).abs() < 1e-11 * scale,
            "E^{s}_{i},{j} = {e}, H^{j}_{s},{i} = {h}"
        );
    }
}

#[test]
fn coupling_converged_when_quadrature_doubles() {
    // The 1D cosine integrals use Gauss-Legendre; doubling the points changes no entry by more
    // than 1e-12 of the largest (roundoff level of sums of ~100 terms).
    let spec = RectSpec::new(1.5, 100, 50);
    let a = RectModes::build(&spec).unwrap();
    let mut s2 = spec.clone();
    s2.quad_points = Some(2 * a.quad_points);
    let b = RectModes::build(&s2).unwrap();
    let (a_h, b_h) = (a.triplets(), b.triplets());
    assert_eq!(a_h.len(), b_h.len());
    let scale = a_h.value.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let worst = a_h
        .value
        .iter()
        .zip(&b_h.value)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    eprintln!(
        "quadrature {} -> {}: worst |ΔH| {worst:.2e} of max|H| {scale:.3e}",
        a.quad_points, b.quad_points
    );
    assert!(worst < 1e-12 * scale, "worst change {worst:e} of {scale:e}");
}

#[test]
fn invalid_specs_are_rejected_with_field_names() {
    let e = RectModes::build(&RectSpec::new(0.0, 10, 10)).unwrap_err();
    assert_eq!(e.field, "aspect");
    let e = RectModes::build(&RectSpec::new(1.0, 0, 10)).unwrap_err();
    assert_eq!(e.field, "n_phi");
    let e = RectModes::build(&RectSpec::new(1.0, 10, 5000)).unwrap_err();
    assert!(e.field == "n_psi" && e.allowed.contains("[1, 1000]"));
    let mut s = RectSpec::new(1.0, 10, 10);
    s.basis_x = Some(2);
    assert_eq!(RectModes::build(&s).unwrap_err().field, "basis_x");
    let e = RectModes::build(&RectSpec::new(1.0, 5000, 1000)).unwrap_err();
    assert_eq!(e.field, "n_phi");
    let m = RectModes::build(&RectSpec::new(1.0, 4, 4)).unwrap();
    assert_eq!(m.omega_physical(-1.0, 1.0, 1.0).unwrap_err().field, "lx");
}

#[test]
fn lecture_800_mode_plate_builds_quickly() {
    // 0.6 × 0.8 m, N_Φ = 800, N_Ψ = 200: must build "well under a minute" on 2 cores; the
    // bound is loose (measured ~2 s) so a busy CI machine does not fail it spuriously.
    let t = std::time::Instant::now();
    let m = RectModes::build(&RectSpec::new(0.8 / 0.6, 800, 200)).unwrap();
    let secs = t.elapsed().as_secs_f64();
    assert!(secs < 30.0, "build took {secs} s");
    assert_eq!(m.coupling.n_phi(), 800);
    assert!(m.coupling.parts().3.iter().all(|v| v.is_finite()));
    eprintln!(
        "N_Φ=800 N_Ψ=200 build {secs:.2} s, {} entries",
        m.coupling.nnz()
    );
}
