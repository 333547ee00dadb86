//! Tests of the block layout (`tensor/blocks.rs`): planted selection rules against the run
//! kernel and direct sums, and a real free-plate tensor.

use super::*;
use crate::modal::{CircularEdge, CircularPlateSpec, Parity, PlateModes};

/// Deterministic uniform numbers in `[0, 1)` (64-bit LCG).
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// A tensor with a planted selection rule: modes in `k` classes (labels shuffled over the
/// index range), row `l` couples class pairs `(a, b)` with `(a + b + l) % 3 == 0` densely,
/// and class pair `(0, 1)` of row 0 sparsely: the `r`-th mode of class 0 with the `r`-th of
/// class 1 only (fill `1/|class|`, below [`MIN_FILL`], so that part of the row falls back
/// to the run layout; equal partner counts, so refinement keeps the classes).
/// Returns `(labels, row_start, i, j, value)`.
#[allow(clippy::type_complexity)]
fn planted(
    nf: usize,
    np: usize,
    k: u32,
    seed: &mut u64,
) -> (Vec<u32>, Vec<u32>, Vec<u32>, Vec<u32>, Vec<f64>) {
    let label: Vec<u32> = (0..nf).map(|_| (lcg(seed) * k as f64) as u32).collect();
    let rank: Vec<usize> = (0..nf)
        .map(|s| (0..s).filter(|&t| label[t] == label[s]).count())
        .collect();
    let (mut rs, mut ri, mut rj, mut rv) = (vec![0u32], vec![], vec![], vec![]);
    for l in 0..np {
        for i in 0..nf {
            for j in 0..=i {
                let (a, b) = (label[i], label[j]);
                let dense = (a + b + l as u32) % 3 == 0;
                let sparse = l == 0 && a.min(b) == 0 && a.max(b) == 1 && rank[i] == rank[j];
                if dense || sparse {
                    ri.push(i as u32);
                    rj.push(j as u32);
                    rv.push(lcg(seed) - 0.5);
                }
            }
        }
        rs.push(rv.len() as u32);
    }
    (label, rs, ri, rj, rv)
}

#[test]
fn refinement_recovers_planted_classes() {
    let mut seed = 7;
    let (label, rs, ri, rj, _) = planted(60, 6, 5, &mut seed);
    let class = mode_classes(60, &rs, &ri, &rj);
    // Same class iff same planted label, except that the matching of row 0 splits off the
    // unmatched modes of the larger of classes 0 and 1: check only the other labels.
    for s in 0..60 {
        for t in 0..60 {
            if label[s] >= 2 && label[t] >= 2 {
                assert_eq!(class[s] == class[t], label[s] == label[t], "modes {s}, {t}");
            }
        }
    }
}

/// Block kernel against the run kernel and against direct sums over the CSR entries, to
/// 1e-13 of the sum of absolute terms (the three evaluate the same sums in different
/// orders; terms number ~10³, so round-off stays near 1e-16 × Σ|terms| × a few).
#[test]
fn block_kernel_matches_runs_and_direct_sums() {
    // Classes of about 12 modes (4-lane register kernel, 1 to 4 lanes) and of about 33
    // (the general dot/axpy path).
    // Both storages: f64 blocks, and f32 row panels of the values rounded to f32 (the runs
    // and the direct sums then use the same rounded values).
    for single in [false, true] {
        check_block_kernel(70, 7, 6, 3, single);
        check_block_kernel(100, 5, 3, 11, single);
    }
}

fn check_block_kernel(nf: usize, np: usize, k: u32, mut seed: u64, single: bool) {
    let (_, rs, ri, rj, mut rv) = planted(nf, np, k, &mut seed);
    if single {
        rv.iter_mut().for_each(|x| *x = f64::from(*x as f32));
    }
    let blocks = BlockLayout::new(nf, &rs, &ri, &rj, &rv, single);
    assert_eq!(blocks.is_single(), single);
    let runs = RunLayout::new(nf, &rs, &ri, &rj, &rv);
    let (_, n_blocks, _, n_rest) = blocks.stats();
    assert!(
        n_blocks > 0 && n_rest > 0,
        "both paths exercised: {n_blocks} {n_rest}"
    );
    let q: Vec<f64> = (0..nf).map(|_| lcg(&mut seed) - 0.5).collect();
    let w: Vec<f64> = (0..np).map(|_| lcg(&mut seed)).collect();
    let (mut eta_b, mut grad_b) = (vec![0.0; np], vec![0.0; nf]);
    let (mut eta_r, mut grad_r) = (vec![0.0; np], vec![0.0; nf]);
    let mut scratch = vec![f64::NAN; 3 * nf + 2 * PAD];
    runs.quartic_gradient(&q, &w, &mut eta_r, &mut grad_r, &mut scratch);
    // Both instantiations (plain and fused multiply-add), whatever this CPU has.
    let (mut eta_p, mut grad_p) = (vec![0.0; np], vec![0.0; nf]);
    blocks.quartic::<false>(0..np, &q, &w, None, &mut eta_p, &mut grad_p, &mut scratch);
    // The FMA instantiation runs AVX2 intrinsics on x86-64 (single storage): only where the
    // CPU has them (the layout's own dispatch otherwise).
    #[cfg(target_arch = "x86_64")]
    let fma = is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma");
    #[cfg(not(target_arch = "x86_64"))]
    let fma = true;
    if fma {
        blocks.quartic::<true>(0..np, &q, &w, None, &mut eta_b, &mut grad_b, &mut scratch);
    } else {
        blocks.quartic_gradient_rows(0..np, &q, &w, None, &mut eta_b, &mut grad_b, &mut scratch);
    }
    // The shifted quartic (a curved plate's `Σ_l w_l (eta_l - c_l)²`): zero offsets are the
    // plain kernel bit for bit; random offsets are checked against the direct sums below.
    let c: Vec<f64> = (0..np).map(|_| lcg(&mut seed) - 0.5).collect();
    let (mut eta_c, mut grad_c) = (vec![0.0; np], vec![0.0; nf]);
    let (mut eta_z, mut grad_z) = (vec![0.0; np], vec![0.0; nf]);
    let (mut eta_n, mut grad_n) = (vec![0.0; np], vec![0.0; nf]);
    let zeros = vec![0.0; np];
    blocks.quartic_gradient_rows(
        0..np,
        &q,
        &w,
        Some(&c),
        &mut eta_c,
        &mut grad_c,
        &mut scratch,
    );
    blocks.quartic_gradient_rows(
        0..np,
        &q,
        &w,
        Some(&zeros),
        &mut eta_z,
        &mut grad_z,
        &mut scratch,
    );
    blocks.quartic_gradient_rows(0..np, &q, &w, None, &mut eta_n, &mut grad_n, &mut scratch);
    assert_eq!(
        (&eta_z, &grad_z),
        (&eta_n, &grad_n),
        "zero offsets change the bits"
    );
    assert_eq!(eta_c, eta_n, "the offsets change eta");
    // Direct: dense H^l from the entries.
    let mut h = vec![0.0; np * nf * nf];
    for l in 0..np {
        for e in rs[l] as usize..rs[l + 1] as usize {
            let (i, j) = (ri[e] as usize, rj[e] as usize);
            h[(l * nf + i) * nf + j] = rv[e];
            h[(l * nf + j) * nf + i] = rv[e];
        }
    }
    // The same kernel in two row ranges (the split SAV step): the halves' `eta` make up the
    // whole and their gradients add up to it.
    let m = np / 3;
    let (mut eta_s, mut grad_s, mut grad_s2) = (vec![0.0; np], vec![0.0; nf], vec![0.0; nf]);
    let (e1, e2) = eta_s.split_at_mut(m);
    blocks.quartic_gradient_rows(0..m, &q, &w, None, e1, &mut grad_s, &mut scratch);
    blocks.quartic_gradient_rows(m..np, &q, &w, None, e2, &mut grad_s2, &mut scratch);
    for (g, g2) in grad_s.iter_mut().zip(&grad_s2) {
        *g += g2;
    }
    let mut grad_d = vec![0.0; nf];
    let mut gscale = vec![0.0; nf];
    let (mut grad_dc, mut gscale_c) = (vec![0.0; nf], vec![0.0; nf]);
    for l in 0..np {
        let hq: Vec<f64> = (0..nf)
            .map(|s| (0..nf).map(|k| h[(l * nf + s) * nf + k] * q[k]).sum())
            .collect();
        let habs: Vec<f64> = (0..nf)
            .map(|s| {
                (0..nf)
                    .map(|k| (h[(l * nf + s) * nf + k] * q[k]).abs())
                    .sum()
            })
            .collect();
        let eta: f64 = (0..nf).map(|s| q[s] * hq[s]).sum();
        let escale: f64 = (0..nf).map(|s| q[s].abs() * habs[s]).sum();
        assert!(
            (eta_b[l] - eta).abs() <= 1e-13 * escale,
            "eta {l} (single {single}): {} vs {eta} (runs {}, plain {}), scale {escale}",
            eta_b[l],
            eta_r[l],
            eta_p[l]
        );
        assert!(
            (eta_b[l] - eta_r[l]).abs() <= 1e-13 * escale,
            "eta runs {l}"
        );
        assert!((eta_p[l] - eta).abs() <= 1e-13 * escale, "eta plain {l}");
        assert!((eta_s[l] - eta).abs() <= 1e-13 * escale, "eta split {l}");
        for s in 0..nf {
            grad_d[s] += 4.0 * w[l] * eta * hq[s];
            gscale[s] += 4.0 * w[l] * escale * habs[s];
            grad_dc[s] += 4.0 * w[l] * (eta - c[l]) * hq[s];
            gscale_c[s] += 4.0 * w[l] * (escale + c[l].abs()) * habs[s];
        }
    }
    for s in 0..nf {
        assert!(
            (grad_c[s] - grad_dc[s]).abs() <= 1e-13 * gscale_c[s],
            "shifted grad {s}: {} vs {}",
            grad_c[s],
            grad_dc[s]
        );
    }
    for s in 0..nf {
        assert!(
            (grad_b[s] - grad_d[s]).abs() <= 1e-13 * gscale[s],
            "grad {s}"
        );
        assert!(
            (grad_b[s] - grad_r[s]).abs() <= 1e-13 * gscale[s],
            "grad runs {s}"
        );
        assert!(
            (grad_p[s] - grad_d[s]).abs() <= 1e-13 * gscale[s],
            "grad plain {s}"
        );
        assert!(
            (grad_s[s] - grad_d[s]).abs() <= 1e-13 * gscale[s],
            "grad split {s}"
        );
    }
}

/// On a real free-plate tensor (Bessel modes, quadrature): colour refinement finds exactly
/// the selection-rule classes `(n, cos|sin)` (one class per distinct label), and the block
/// kernel matches the run kernel to 1e-13 of the sum of absolute terms.
#[test]
fn gong_tensor_classes_and_kernel() {
    let spec = CircularPlateSpec::new(CircularEdge::Free, 0.3, 60, 20, None).unwrap();
    let modes = PlateModes::build(&spec).unwrap();
    let t = &modes.coupling;
    let mut labels: Vec<(u32, bool)> = modes
        .phi
        .iter()
        .map(|m| (m.n, m.parity == Parity::Sin))
        .collect();
    labels.sort_unstable();
    labels.dedup();
    let (classes, _, _, rest) = t.block_stats();
    assert_eq!(classes, labels.len(), "classes = distinct (n, cos|sin)");
    assert_eq!(rest, 0, "every selection-rule block is dense");
    let (nf, np) = (t.n_phi(), t.n_psi());
    let q: Vec<f64> = (0..nf)
        .map(|s| ((s * 37) % 11) as f64 / 11.0 - 0.45)
        .collect();
    let w: Vec<f64> = (0..np).map(|l| 1.0 + l as f64 * 0.1).collect();
    let (mut eb, mut gb, mut er, mut gr) =
        (vec![0.0; np], vec![0.0; nf], vec![0.0; np], vec![0.0; nf]);
    let mut scratch = vec![0.0; t.quartic_scratch_len()];
    t.quartic_gradient(&q, &w, &mut eb, &mut gb, &mut scratch);
    t.quartic_gradient_runs(&q, &w, &mut er, &mut gr, &mut scratch);
    // Scales: Σ |H q q| per row and Σ_l 4 w_l |η_l| Σ_k |H_sk q_k| per mode.
    let (rs, ri, rj, rv) = t.parts();
    let mut escale = vec![0.0; np];
    let mut habs = vec![vec![0.0; nf]; np];
    for l in 0..np {
        for e in rs[l] as usize..rs[l + 1] as usize {
            let (i, j, x) = (ri[e] as usize, rj[e] as usize, rv[e].abs());
            let mult = if i == j { 1.0 } else { 2.0 };
            escale[l] += mult * x * (q[i] * q[j]).abs();
            habs[l][i] += x * q[j].abs();
            if i != j {
                habs[l][j] += x * q[i].abs();
            }
        }
    }
    for l in 0..np {
        assert!((eb[l] - er[l]).abs() <= 1e-13 * escale[l], "eta {l}");
    }
    for s in 0..nf {
        let scale: f64 = (0..np).map(|l| 4.0 * w[l] * escale[l] * habs[l][s]).sum();
        assert!(
            (gb[s] - gr[s]).abs() <= 1e-13 * scale,
            "grad {s}: {} vs {}",
            gb[s],
            gr[s]
        );
    }
}

/// The AVX2 `dot` and `dot_axpy` of the `FMA` instantiation are the portable ones bit for bit
/// (same lanes, same fused multiply-adds, same final order), for every length 0 to 40 and
/// random data, so
/// the default `f64` kernels' results did not change when it replaced the compiler's
/// vectorisation. Exact equality (`to_bits`): any reordering would show in the last bits of
/// these ~40-term sums of mixed signs.
#[test]
fn avx2_dot_is_the_portable_dot_bit_for_bit() {
    #[cfg(target_arch = "x86_64")]
    if is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma") {
        let mut seed = 17;
        let mut differing = 0;
        for n in 0..=40 {
            let m: Vec<f64> = (0..n).map(|_| lcg(&mut seed) - 0.5).collect();
            let x: Vec<f64> = (0..n).map(|_| lcg(&mut seed) * 1e3 - 5e2).collect();
            // SAFETY: the CPU has AVX2 and FMA (checked above).
            let fast = unsafe { dot_avx2_for_tests(&m, &x) };
            assert_eq!(
                fast.to_bits(),
                super::dense::dot_portable::<true>(&m, &x).to_bits(),
                "n = {n}"
            );
            // The same for the dot product with an axpy (the wide blocks' kernel).
            let (mut y_fast, mut y_slow) = (x.clone(), x.clone());
            let s = lcg(&mut seed) - 0.5;
            // SAFETY: as above.
            let d_fast = unsafe { dot_axpy_avx2_for_tests(&m, &x, &mut y_fast, s) };
            let d_slow = dense::dot_axpy_portable::<true>(&m, &x, &mut y_slow, s);
            assert_eq!(d_fast.to_bits(), d_slow.to_bits(), "dot_axpy n = {n}");
            for (a, b) in y_fast.iter().zip(&y_slow) {
                assert_eq!(a.to_bits(), b.to_bits(), "axpy n = {n}");
            }
            // The control: a plain left-to-right sum differs in the last bits for most n.
            let naive: f64 = m.iter().zip(&x).map(|(a, b)| a * b).sum();
            differing += usize::from(naive.to_bits() != fast.to_bits());
        }
        assert!(
            differing > 10,
            "the comparison sees reordering: {differing}"
        );
    }
}

/// [`dot_axpy`]'s `FMA` instantiation compiled with AVX2 and FMA enabled.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn dot_axpy_avx2_for_tests(m: &[f64], x: &[f64], y: &mut [f64], s: f64) -> f64 {
    dot_axpy::<true>(m, x, y, s)
}

/// [`dot`]'s `FMA` instantiation compiled with AVX2 and FMA enabled, as inside the layout's
/// entry points.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
unsafe fn dot_avx2_for_tests(m: &[f64], x: &[f64]) -> f64 {
    dot::<true>(m, x)
}

/// The AVX2 register kernel of the `f64` blocks is the portable one bit for bit, for every
/// register count (1 to 4 column groups), diagonal or not, on random values (exact equality of
/// every output: the same fused multiply-adds in the same order; the default storage's
/// results did not change).
#[test]
fn avx2_register_kernel_is_the_portable_one_bit_for_bit() {
    #[cfg(target_arch = "x86_64")]
    if is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma") {
        let mut seed = 23;
        for diag in [false, true] {
            for c in 1..=4 {
                let (nr, n) = (if diag { 4 * c } else { 13 }, 64);
                let (r0, c0) = if diag { (8, 8) } else { (40, 8) };
                let m: Vec<f64> = (0..nr * 4 * c).map(|_| lcg(&mut seed) - 0.5).collect();
                let x: Vec<f64> = (0..n).map(|_| lcg(&mut seed) * 20.0 - 10.0).collect();
                let v0: Vec<f64> = (0..n).map(|_| lcg(&mut seed) - 0.5).collect();
                let (mut fast, mut slow) = (v0.clone(), v0.clone());
                // SAFETY: the CPU has AVX2 and FMA (checked above).
                unsafe { regs_avx2_for_tests(c, &m, &x, &mut fast, r0, nr, c0, diag) };
                match c {
                    1 => dense::regs_portable::<1, true>(&m, &x, &mut slow, r0, nr, c0, diag),
                    2 => dense::regs_portable::<2, true>(&m, &x, &mut slow, r0, nr, c0, diag),
                    3 => dense::regs_portable::<3, true>(&m, &x, &mut slow, r0, nr, c0, diag),
                    _ => dense::regs_portable::<4, true>(&m, &x, &mut slow, r0, nr, c0, diag),
                }
                assert_ne!(fast, v0, "the kernel wrote");
                for (k, (a, b)) in fast.iter().zip(&slow).enumerate() {
                    assert_eq!(a.to_bits(), b.to_bits(), "C {c} diag {diag} entry {k}");
                }
            }
        }
    }
}

/// [`regs`]'s `FMA` instantiation compiled with AVX2 and FMA enabled (as inside the layout's
/// entry points), for `c` column groups.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma")]
#[allow(clippy::too_many_arguments)]
unsafe fn regs_avx2_for_tests(
    c: usize,
    m: &[f64],
    x: &[f64],
    v: &mut [f64],
    r0: usize,
    nr: usize,
    c0: usize,
    diag: bool,
) {
    match c {
        1 => regs::<1, true>(m, x, v, r0, nr, c0, diag),
        2 => regs::<2, true>(m, x, v, r0, nr, c0, diag),
        3 => regs::<3, true>(m, x, v, r0, nr, c0, diag),
        _ => regs::<4, true>(m, x, v, r0, nr, c0, diag),
    }
}
