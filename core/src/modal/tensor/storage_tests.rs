//! Tests of single storage (`tensor/storage.rs`): one set of rounded numbers in every layout,
//! the block kernels against the run kernels on it, and the negative control (runs left in
//! `f64` beside `f32` blocks) that the agreement check must reject.

use super::super::blocks::BlockLayout;
use super::super::runs::RunLayout;
use super::*;
use crate::modal::{CircularEdge, CircularPlateSpec, PlateModes};

/// A real free-plate tensor (Bessel modes, quadrature), mirror basis for odd class sizes.
fn gong(mirror: bool) -> CouplingTensor {
    let mut spec = CircularPlateSpec::new(CircularEdge::Free, 0.3, 70, 24, None).unwrap();
    if mirror {
        spec = spec.mirror_symmetric();
    }
    PlateModes::build(&spec).unwrap().coupling
}

/// Deterministic vectors in `[-0.5, 0.5)` (64-bit LCG).
fn vector(n: usize, mut seed: u64) -> Vec<f64> {
    (0..n)
        .map(|_| {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        })
        .collect()
}

/// The largest disagreement between the block kernels and the run kernels of `t`, each
/// relative to the sum of absolute terms of its sum: `η = q·H^l q` (fused SAV kernel and
/// `contract_eta`), `∇ Σ w η²`, `Σ_l w_l H^l q` and `G = [H^l q]`. Reordered sums of at most
/// ~10³ terms agree to ~1e-16 of that scale; a coefficient that differs between the layouts by
/// a relative δ shows as ~δ.
fn worst_disagreement(t: &CouplingTensor) -> f64 {
    let (nf, np) = (t.n_phi(), t.n_psi());
    let (rs, ri, rj, rv) = t.parts();
    let q = vector(nf, 5);
    let w: Vec<f64> = vector(np, 9).iter().map(|x| x + 1.0).collect();
    // Scales: Σ |H q q| per row, Σ_k |H^l_{sk} q_k| per (l, s).
    let mut escale = vec![0.0; np];
    let mut habs = vec![vec![0.0; nf]; np];
    for l in 0..np {
        for e in rs[l] as usize..rs[l + 1] as usize {
            let (i, j, x) = (ri[e] as usize, rj[e] as usize, rv[e].abs());
            escale[l] += if i == j { 1.0 } else { 2.0 } * x * (q[i] * q[j]).abs();
            habs[l][i] += x * q[j].abs();
            if i != j {
                habs[l][j] += x * q[i].abs();
            }
        }
    }
    let mut scratch = vec![0.0; t.kernel_scratch_len()];
    let (mut eb, mut er, mut gb, mut gr) =
        (vec![0.0; np], vec![0.0; np], vec![0.0; nf], vec![0.0; nf]);
    t.quartic_gradient(&q, &w, &mut eb, &mut gb, &mut scratch);
    t.quartic_gradient_runs(&q, &w, &mut er, &mut gr, &mut scratch);
    let mut worst = 0.0f64;
    for l in 0..np {
        worst = worst.max((eb[l] - er[l]).abs() / escale[l]);
    }
    for s in 0..nf {
        let scale: f64 = (0..np).map(|l| 4.0 * w[l] * escale[l] * habs[l][s]).sum();
        worst = worst.max((gb[s] - gr[s]).abs() / scale);
    }
    let (mut eta_b, mut eta_r) = (vec![0.0; np], vec![0.0; np]);
    t.contract_eta_with_scratch(&q, &q, &mut eta_b, &mut scratch);
    t.contract_eta(&q, &q, &mut eta_r);
    for l in 0..np {
        worst = worst.max((eta_b[l] - eta_r[l]).abs() / escale[l]);
    }
    let (mut fb, mut fr) = (vec![0.0; nf], vec![0.0; nf]);
    t.apply_force_with_scratch(&q, &w, &mut fb, &mut scratch);
    t.apply_force(&q, &w, &mut fr);
    let (mut mb, mut mr) = (vec![0.0; nf * np], vec![0.0; nf * np]);
    t.coupling_matrix_with_scratch(&q, &mut mb, &mut scratch);
    t.coupling_matrix(&q, &mut mr);
    for s in 0..nf {
        let scale: f64 = (0..np).map(|l| w[l] * habs[l][s]).sum();
        worst = worst.max((fb[s] - fr[s]).abs() / scale);
        for (l, h) in habs.iter().enumerate() {
            let k = s * np + l;
            if h[s] > 0.0 {
                worst = worst.max((mb[k] - mr[k]).abs() / h[s]);
            } else {
                assert_eq!((mb[k], mr[k]), (0.0, 0.0), "G[{s},{l}] outside the pattern");
            }
        }
    }
    worst
}

/// Single storage rounds each value once, to the nearest `f32`, and every layout holds the
/// rounded numbers: the CSR values exactly, and the block kernels agree with the run kernels
/// to 1e-13 of the sum of absolute terms (reordered `f64` sums; the `f32` rounding itself is
/// ~6e-8, so a layout holding unrounded values would show 10⁵× above the tolerance: see
/// [`mixing_f64_runs_with_f32_blocks_is_caught`]).
#[test]
fn single_storage_is_one_rounded_tensor() {
    for mirror in [false, true] {
        let t = gong(mirror);
        let s = t.with_storage(TensorStorage::Single).unwrap();
        assert_eq!(s.storage(), TensorStorage::Single);
        assert!(s.blocks.is_single() && !t.blocks.is_single());
        assert_eq!(s.nnz(), t.nnz());
        let (sv, tv) = (s.parts().3, t.parts().3);
        let mut changed = 0;
        for (e, (&a, &b)) in sv.iter().zip(tv).enumerate() {
            assert_eq!(a, f64::from(b as f32), "value {e}");
            assert!(
                (a - b).abs() <= b.abs() * 2f64.powi(-24),
                "value {e}: {a} vs {b}"
            );
            changed += usize::from(a != b);
        }
        assert!(changed > sv.len() / 2, "the values were rounded: {changed}");
        let worst = worst_disagreement(&s);
        eprintln!("single, mirror {mirror}: block vs runs {worst:.2e}");
        assert!(worst < 1e-13, "mirror {mirror}: {worst:.2e}");
        // The double tensor's own kernels agree as well (the reference of the check).
        assert!(worst_disagreement(&t) < 1e-13);
    }
}

/// The negative control: a tensor whose runs keep the `f64` values beside `f32` blocks (the
/// inconsistent rounding single storage must avoid) fails the agreement check by orders of
/// magnitude.
#[test]
fn mixing_f64_runs_with_f32_blocks_is_caught() {
    let t = gong(true);
    let s = t.with_storage(TensorStorage::Single).unwrap();
    let (rs, ri, rj, rv) = t.parts();
    let mixed = CouplingTensor {
        runs: RunLayout::new(t.n_phi(), rs, ri, rj, rv),
        ..s
    };
    let worst = worst_disagreement(&mixed);
    eprintln!("f64 runs beside f32 blocks: {worst:.2e}");
    assert!(worst > 1e-10, "{worst:.2e}");
    // And the other way round: f32 blocks of unrounded values do not exist (the layout stores
    // `value as f32`), but f64 blocks beside rounded runs are caught alike.
    let s = t.with_storage(TensorStorage::Single).unwrap();
    let (rs, ri, rj, _) = s.parts();
    let mixed = CouplingTensor {
        blocks: BlockLayout::new(t.n_phi(), rs, ri, rj, rv, false),
        ..s
    };
    assert!(worst_disagreement(&mixed) > 1e-10);
}

/// Double storage is the tensor as built (no copy differs), single → double keeps the rounded
/// values in the `f64` layouts, and a value outside the `f32` range is refused by index.
#[test]
fn double_is_unchanged_and_round_trips() {
    let t = gong(false);
    assert_eq!(t.storage(), TensorStorage::Double);
    assert_eq!(t.with_storage(TensorStorage::Double).unwrap(), t);
    let s = t.with_storage(TensorStorage::Single).unwrap();
    let d = s.with_storage(TensorStorage::Double).unwrap();
    assert_eq!(d.storage(), TensorStorage::Double);
    assert_eq!(d.parts(), s.parts());
    assert_ne!(d.parts().3, t.parts().3);
    assert!(worst_disagreement(&d) < 1e-13);
    let big = CouplingTensor::from_parts(2, 1, vec![0, 2], vec![0, 1], vec![0, 0], vec![1.0, 1e39])
        .unwrap();
    let e = big.with_storage(TensorStorage::Single).unwrap_err();
    assert!(e.to_string().contains("coupling.value[1]"), "{e}");
}
