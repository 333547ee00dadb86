//! The block-layout kernels of the linearly implicit plate schemes
//! (`CouplingTensor::{contract_eta, apply_force, coupling_matrix}_with_scratch`) against the run
//! kernels they replace and against direct sums over the CSR entries, on the three tensor
//! families the plate model uses: circular free (full basis), circular mirror basis, rectangle;
//! each with double storage and with single storage (`f32` row panels of the rounded tensor).
//!
//! Tolerance: 1e-13 of the sum of absolute terms of each sum (the kernels evaluate the same
//! sums in different orders, some with fused multiply-adds; with at most ~10⁴ terms the
//! round-off stays below ~1e-15 × Σ|terms|, so 1e-13 fails on any wrong or missing entry of
//! size above 1e-13 of the scale).

use noether::modal::rect::{RectModes, RectSpec};
use noether::modal::{CircularEdge, CircularPlateSpec, CouplingTensor, PlateModes, TensorStorage};

/// Deterministic uniform numbers in `[-0.5, 0.5)` (64-bit LCG).
fn rnd(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

fn circular(mirror: bool) -> CouplingTensor {
    let mut spec = CircularPlateSpec::new(CircularEdge::Free, 0.3, 60, 24, None).unwrap();
    if mirror {
        spec = spec.mirror_symmetric();
    }
    PlateModes::build(&spec).unwrap().coupling
}

fn rectangle() -> CouplingTensor {
    RectModes::build(&RectSpec::new(1.5, 50, 30))
        .unwrap()
        .coupling
}

/// Checks the three block kernels on `t` for two random draws of the vectors.
fn check(t: &CouplingTensor, mut seed: u64) {
    let (nf, np) = (t.n_phi(), t.n_psi());
    // Dense copy of the tensor for the direct sums (both orders of i, j).
    let mut h = vec![0.0; np * nf * nf];
    let (rs, ri, rj, rv) = t.parts();
    for l in 0..np {
        for e in rs[l] as usize..rs[l + 1] as usize {
            let (i, j) = (ri[e] as usize, rj[e] as usize);
            h[(l * nf + i) * nf + j] = rv[e];
            h[(l * nf + j) * nf + i] = rv[e];
        }
    }
    let hh = |l: usize, i: usize, j: usize| h[(l * nf + i) * nf + j];
    let mut scratch = vec![f64::NAN; t.kernel_scratch_len()];
    for _ in 0..2 {
        let qa: Vec<f64> = (0..nf).map(|_| rnd(&mut seed)).collect();
        let qb: Vec<f64> = (0..nf).map(|_| rnd(&mut seed)).collect();
        let w: Vec<f64> = (0..np).map(|_| rnd(&mut seed)).collect();
        // η: block, run, direct.
        let (mut eb, mut er) = (vec![0.0; np], vec![0.0; np]);
        t.contract_eta_with_scratch(&qa, &qb, &mut eb, &mut scratch);
        t.contract_eta(&qa, &qb, &mut er);
        for l in 0..np {
            let (mut want, mut scale) = (0.0, 0.0);
            for (i, &a) in qa.iter().enumerate() {
                for (j, &b) in qb.iter().enumerate() {
                    want += hh(l, i, j) * a * b;
                    scale += (hh(l, i, j) * a * b).abs();
                }
            }
            assert!(
                (eb[l] - want).abs() <= 1e-13 * scale,
                "eta {l}: {} vs {want}",
                eb[l]
            );
            assert!((eb[l] - er[l]).abs() <= 1e-13 * scale, "eta {l} vs runs");
        }
        // Symmetric call (same slice twice).
        t.contract_eta_with_scratch(&qa, &qa, &mut eb, &mut scratch);
        t.contract_eta(&qa, &qa, &mut er);
        for l in 0..np {
            let scale: f64 = (0..nf)
                .flat_map(|i| (0..nf).map(move |j| (i, j)))
                .map(|(i, j)| (hh(l, i, j) * qa[i] * qa[j]).abs())
                .sum();
            assert!((eb[l] - er[l]).abs() <= 1e-13 * scale, "eta(q, q) {l}");
        }
        // Force and coupling matrix.
        let (mut fb, mut fr) = (vec![f64::NAN; nf], vec![0.0; nf]);
        t.apply_force_with_scratch(&qa, &w, &mut fb, &mut scratch);
        t.apply_force(&qa, &w, &mut fr);
        let (mut gb, mut gr) = (vec![f64::NAN; nf * np], vec![0.0; nf * np]);
        t.coupling_matrix_with_scratch(&qa, &mut gb, &mut scratch);
        t.coupling_matrix(&qa, &mut gr);
        for s in 0..nf {
            let (mut want_f, mut fscale) = (0.0, 0.0);
            for l in 0..np {
                let gsl: f64 = (0..nf).map(|k| hh(l, s, k) * qa[k]).sum();
                let gabs: f64 = (0..nf).map(|k| (hh(l, s, k) * qa[k]).abs()).sum();
                let got = gb[s * np + l];
                assert!(
                    (got - gsl).abs() <= 1e-13 * gabs,
                    "G[{s},{l}]: {got} vs {gsl}"
                );
                assert!(
                    (got - gr[s * np + l]).abs() <= 1e-13 * gabs,
                    "G[{s},{l}] vs runs"
                );
                want_f += w[l] * gsl;
                fscale += (w[l] * gabs).abs();
            }
            assert!(
                (fb[s] - want_f).abs() <= 1e-13 * fscale,
                "force {s}: {} vs {want_f}",
                fb[s]
            );
            assert!((fb[s] - fr[s]).abs() <= 1e-13 * fscale, "force {s} vs runs");
        }
    }
}

/// The tensor with single storage (`f32` row panels; the runs and the direct sums read the
/// same rounded values from `parts`).
fn single(t: CouplingTensor) -> CouplingTensor {
    let s = t.with_storage(TensorStorage::Single).unwrap();
    assert_eq!(s.storage(), TensorStorage::Single);
    s
}

#[test]
fn circular_full_tensor() {
    check(&circular(false), 1);
    check(&single(circular(false)), 4);
}

#[test]
fn circular_mirror_tensor() {
    check(&circular(true), 2);
    check(&single(circular(true)), 5);
}

#[test]
fn rectangle_tensor() {
    check(&rectangle(), 3);
    check(&single(rectangle()), 6);
}
