//! The selection-rule block layout of the coupling tensor, for the fused SAV kernel
//! [`BlockLayout::quartic_gradient`]: the transverse modes are permuted once so that every
//! *class* of modes is contiguous, and each row `l` of the tensor becomes a short list of dense
//! blocks `H^l[A, B]` (rows of class `A`, columns of class `B`) streamed as small dense
//! mat-vecs on contiguous slices: no index gathers or scatters in the hot loop.
//!
//! # Classes
//!
//! For a circular plate `H^l_{ij}` vanishes unless the angular orders and cos/sin types of
//! `Φ_i`, `Φ_j`, `Ψ_l` satisfy the selection rule ([`super::angular::triple`]), and is then
//! generically non-zero (a radial integral); for the rectangle the rule is the parity class of
//! the mode pair. Both partitions are recovered here from the sparsity pattern alone, so the
//! layout needs no labels and serves every tensor built by
//! [`super::CouplingTensor::from_parts`]: by colour refinement (Weisfeiler-Lehman), starting
//! from one class, two modes stay in one class while, for every row `l` and every current
//! class `C`, they have the same number of partners in `C` (multisets compared through a sum
//! of 64-bit mixes of `(l, C)`; a hash collision would only merge classes, which costs fill,
//! never correctness). Refinement stops when the class count no longer grows (at most
//! [`MAX_REFINE`] passes; any partition is correct, a coarser one is only slower).
//!
//! # Blocks and fall-back
//!
//! Row `l`'s entries are grouped by their class pair `{A, B}`. A group becomes a dense block
//! when its fill (entries over `|A||B|`, or over `|A|(|A|+1)/2` for `A = B`) is at least
//! [`MIN_FILL`]; off-diagonal blocks are stored once (`|R| × |C|`, row-major, the smaller class
//! as rows `R`), diagonal blocks full and symmetric. Entries of sparser groups go to a
//! [`RunLayout`] over the permuted indices (the gathered kernel of `tensor/runs.rs`).
//!
//! # Kernel
//!
//! With `v = H^l q` (full symmetric product, on the classes row `l` touches only):
//! `η_l = q · v`, `∇_q Σ_l w_l η_l² = Σ_l 4 w_l η_l v`. An off-diagonal block gives
//! `v_R += M q_C` and `v_C += Mᵀ q_R` from one pass over `M` (a dot product and an axpy per row
//! of `M`, four independent accumulators, `chunks_exact(4)`); a diagonal block `v_A += M q_A`.
//! `q` is permuted in and the gradient out once per call (`O(N_Φ)`).
//!
//! The same row product `v = H^l q` serves the kernels of the linearly implicit schemes
//! (`contract_eta`, `apply_force`, `coupling_matrix`, in `tensor/blocks_kernels.rs`).
//!
//! Threads: built on a worker thread with the tensor; the kernels run on the audio thread
//! without allocating.

use super::runs::RunLayout;
use std::collections::HashMap;

/// Smallest fill (stored entries over block size) for which a class-pair group is stored as a
/// dense block; sparser groups stay in the gathered run layout. A dense block costs about one
/// multiply-add per stored element (zeros included) at contiguous-load speed, a run entry an
/// index load and a gather/scatter (about 2 ns measured, several times a dense element), so
/// dense pays well below full fill; 0.25 keeps the zero-padding overhead at most 4×.
pub(crate) const MIN_FILL: f64 = 0.25;

/// Cap on colour-refinement passes (each is `O(nnz)`; see the module docs).
pub(crate) const MAX_REFINE: usize = 200;

/// A dense block of one row: rows `r0..r0+nr`, columns `c0..c0+nc` (permuted indices),
/// values at `off..off + nr*nc` (row-major). Diagonal when `r0 == c0` (then `nr == nc`, full).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Block {
    r0: u32,
    nr: u32,
    c0: u32,
    nc: u32,
    off: u32,
}

/// Class-blocked copy of a `j ≤ i` sparse symmetric tensor (see the module docs).
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct BlockLayout {
    n_phi: usize,
    /// `orig[p]`: the original index of the mode at permuted position `p`.
    orig: Vec<u32>,
    /// Class `c` occupies permuted positions `class_start[c]..class_start[c + 1]`.
    class_start: Vec<u32>,
    /// Row `l` owns blocks `row_blocks[l]..row_blocks[l + 1]`.
    row_blocks: Vec<u32>,
    /// The dense blocks of all rows.
    blocks: Vec<Block>,
    /// Block values (`H`, not halved).
    values: Vec<f64>,
    /// Row `l` touches the ranges `touched[row_touched[l]..row_touched[l + 1]]`.
    row_touched: Vec<u32>,
    /// Permuted index ranges `(start, end)` of the classes each row touches (dense blocks and
    /// remainder), adjacent classes merged, ascending.
    touched: Vec<(u32, u32)>,
    /// Entries of the groups below [`MIN_FILL`], in permuted indices.
    rest: RunLayout,
    /// The CPU has AVX2 and FMA (detected at build; selects the kernel's instantiation).
    avx2_fma: bool,
}

/// 64-bit mix (splitmix64 finaliser).
fn mix(mut x: u64) -> u64 {
    x = (x ^ (x >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    x ^ (x >> 31)
}

/// Colour refinement of the modes by their partner counts per `(row, class)` (module docs).
/// Returns the class of each mode, classes numbered by their first mode.
pub(crate) fn mode_classes(n_phi: usize, row_start: &[u32], i: &[u32], j: &[u32]) -> Vec<u32> {
    let mut class = vec![0u32; n_phi];
    let mut count = usize::from(n_phi > 0);
    for _ in 0..MAX_REFINE {
        let mut sig = vec![0u64; n_phi];
        for l in 0..row_start.len().saturating_sub(1) {
            for e in row_start[l] as usize..row_start[l + 1] as usize {
                let (a, b) = (i[e] as usize, j[e] as usize);
                let key = |c: u32, diag: u64| mix(((l as u64) << 33) | (u64::from(c) << 1) | diag);
                if a == b {
                    sig[a] = sig[a].wrapping_add(key(class[a], 1));
                } else {
                    sig[a] = sig[a].wrapping_add(key(class[b], 0));
                    sig[b] = sig[b].wrapping_add(key(class[a], 0));
                }
            }
        }
        let mut ids: HashMap<(u32, u64), u32> = HashMap::new();
        let next: Vec<u32> = (0..n_phi)
            .map(|s| {
                let n = ids.len() as u32;
                *ids.entry((class[s], sig[s])).or_insert(n)
            })
            .collect();
        let grew = ids.len() > count;
        count = ids.len();
        class = next;
        if !grew {
            break;
        }
    }
    class
}

/// One block with `4 C` (padded) columns: `v_R += M x_C` and, off the diagonal
/// (`diag = false`), `v_C += Mᵀ x_R`, with `x_C` and the column sums held in `C` 4-lane
/// registers (no store-to-load chain through `v_C` from row to row). Rows of `m` are padded with
/// zeros to `4 C`, so the padded lanes read `x` past the class (times 0) and add exact zeros
/// to `v` past it: `x`, `v` must extend `4 C - nc` entries beyond `c0 + nc` (the scratch
/// padding of [`PAD`]).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn regs<const C: usize, const FMA: bool>(
    m: &[f64],
    x: &[f64],
    v: &mut [f64],
    r0: usize,
    nr: usize,
    c0: usize,
    diag: bool,
) {
    let mut xc = [[0.0f64; 4]; C];
    for (c, xs) in xc.iter_mut().enumerate() {
        xs.copy_from_slice(&x[c0 + 4 * c..c0 + 4 * c + 4]);
    }
    let mut acc = [[0.0f64; 4]; C];
    let rows = m.chunks_exact(4 * C).zip(&x[r0..r0 + nr]);
    for ((row, &s), o) in rows.zip(&mut v[r0..r0 + nr]) {
        let mut d = [0.0f64; 4];
        for c in 0..C {
            for k in 0..4 {
                let a = row[4 * c + k];
                d[k] = madd::<FMA>(a, xc[c][k], d[k]);
                acc[c][k] = madd::<FMA>(s, a, acc[c][k]);
            }
        }
        *o += (d[0] + d[1]) + (d[2] + d[3]);
    }
    if !diag {
        for (c, a) in acc.iter().enumerate() {
            for (o, &y) in v[c0 + 4 * c..c0 + 4 * c + 4].iter_mut().zip(a) {
                *o += y;
            }
        }
    }
}

/// Scratch padding past each `N_Φ` buffer (the padded lanes of [`regs`], at most 3).
pub(crate) const PAD: usize = 4;

/// Two disjoint sub-slices `x[a..a+na]` and `x[b..b+nb]` (`a + na ≤ b` or `b + nb ≤ a`).
#[inline(always)]
fn two_mut(x: &mut [f64], a: usize, na: usize, b: usize, nb: usize) -> (&mut [f64], &mut [f64]) {
    if a < b {
        let (lo, hi) = x.split_at_mut(b);
        (&mut lo[a..a + na], &mut hi[..nb])
    } else {
        let (lo, hi) = x.split_at_mut(a);
        (&mut hi[..na], &mut lo[b..b + nb])
    }
}

/// `a b + c`, fused (one rounding) when `FMA` (only instantiated where the CPU has FMA).
#[inline(always)]
fn madd<const FMA: bool>(a: f64, b: f64, c: f64) -> f64 {
    if FMA {
        a.mul_add(b, c)
    } else {
        a * b + c
    }
}

/// `Σ_k m_k x_k` with four independent sums (equal lengths).
#[inline(always)]
fn dot<const FMA: bool>(m: &[f64], x: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let (mc, xc) = (m.chunks_exact(4), x.chunks_exact(4));
    let mut tail = 0.0;
    for (a, b) in mc.remainder().iter().zip(xc.remainder()) {
        tail = madd::<FMA>(*a, *b, tail);
    }
    for (a, b) in mc.zip(xc) {
        acc[0] = madd::<FMA>(a[0], b[0], acc[0]);
        acc[1] = madd::<FMA>(a[1], b[1], acc[1]);
        acc[2] = madd::<FMA>(a[2], b[2], acc[2]);
        acc[3] = madd::<FMA>(a[3], b[3], acc[3]);
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Returns `Σ_k m_k x_k` and does `y_k += s m_k`, one pass over `m` (equal lengths).
#[inline(always)]
fn dot_axpy<const FMA: bool>(m: &[f64], x: &[f64], y: &mut [f64], s: f64) -> f64 {
    let mut acc = [0.0f64; 4];
    let (mc, xc, mut yc) = (m.chunks_exact(4), x.chunks_exact(4), y.chunks_exact_mut(4));
    let (mr, xr) = (mc.remainder(), xc.remainder());
    for ((a, b), c) in mc.zip(xc).zip(&mut yc) {
        acc[0] = madd::<FMA>(a[0], b[0], acc[0]);
        acc[1] = madd::<FMA>(a[1], b[1], acc[1]);
        acc[2] = madd::<FMA>(a[2], b[2], acc[2]);
        acc[3] = madd::<FMA>(a[3], b[3], acc[3]);
        c[0] = madd::<FMA>(s, a[0], c[0]);
        c[1] = madd::<FMA>(s, a[1], c[1]);
        c[2] = madd::<FMA>(s, a[2], c[2]);
        c[3] = madd::<FMA>(s, a[3], c[3]);
    }
    let mut tail = 0.0;
    for ((a, b), c) in mr.iter().zip(xr).zip(yc.into_remainder()) {
        tail = madd::<FMA>(*a, *b, tail);
        *c = madd::<FMA>(s, *a, *c);
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

impl BlockLayout {
    /// Builds the layout from validated CSR parts (`j ≤ i < n_phi ≤ 65 536`, rows sorted by
    /// `(i, j)`). Worker thread; allocates.
    pub(crate) fn new(n_phi: usize, row_start: &[u32], i: &[u32], j: &[u32], v: &[f64]) -> Self {
        let n_psi = row_start.len().saturating_sub(1);
        let class = mode_classes(n_phi, row_start, i, j);
        let n_class = class.iter().map(|&c| c as usize + 1).max().unwrap_or(0);
        let mut class_start = vec![0u32; n_class + 1];
        for &c in &class {
            class_start[c as usize + 1] += 1;
        }
        for c in 0..n_class {
            class_start[c + 1] += class_start[c];
        }
        let mut fill = class_start.clone();
        let (mut orig, mut pos) = (vec![0u32; n_phi], vec![0u32; n_phi]);
        for (s, &c) in class.iter().enumerate() {
            let p = fill[c as usize];
            fill[c as usize] += 1;
            orig[p as usize] = s as u32;
            pos[s] = p;
        }
        let size = |c: u32| (class_start[c as usize + 1] - class_start[c as usize]) as usize;
        let mut out = Self {
            n_phi,
            orig,
            row_blocks: vec![0],
            row_touched: vec![0],
            ..Self::default()
        };
        let (mut rest_start, mut rest_i, mut rest_j, mut rest_v) =
            (vec![0u32], vec![], vec![], vec![]);
        // (class A ≥ class B, permuted a, permuted b, value) per entry of one row.
        let mut ents: Vec<(u32, u32, u32, u32, f64)> = Vec::new();
        for l in 0..n_psi {
            ents.clear();
            for e in row_start[l] as usize..row_start[l + 1] as usize {
                let (mut a, mut b) = (i[e] as usize, j[e] as usize);
                if class[a] < class[b] || (class[a] == class[b] && pos[a] < pos[b]) {
                    std::mem::swap(&mut a, &mut b);
                }
                ents.push((class[a], class[b], pos[a], pos[b], v[e]));
            }
            ents.sort_by_key(|x| (x.0, x.1, x.2, x.3));
            let mut touched: Vec<u32> = Vec::new();
            let mut rest: Vec<(u32, u32, f64)> = Vec::new();
            let mut g0 = 0;
            while g0 < ents.len() {
                let (ca, cb) = (ents[g0].0, ents[g0].1);
                let mut g1 = g0;
                while g1 < ents.len() && (ents[g1].0, ents[g1].1) == (ca, cb) {
                    g1 += 1;
                }
                touched.extend([ca, cb]);
                let (na, nb) = (size(ca), size(cb));
                let cells = if ca == cb { na * (na + 1) / 2 } else { na * nb };
                if (g1 - g0) as f64 >= MIN_FILL * cells as f64 {
                    let (a0, b0) = (class_start[ca as usize], class_start[cb as usize]);
                    // Columns: the smaller class (its partial sums stay in registers).
                    let (r0, nr, c0, nc, swap) = if ca == cb || na >= nb {
                        (a0, na, b0, nb, false)
                    } else {
                        (b0, nb, a0, na, true)
                    };
                    let stride = nc.div_ceil(4) * 4;
                    let off = out.values.len();
                    out.values.resize(off + nr * stride, 0.0);
                    let m = &mut out.values[off..];
                    for &(_, _, pa, pb, x) in &ents[g0..g1] {
                        let (pr, pc) = if swap { (pb, pa) } else { (pa, pb) };
                        m[(pr - r0) as usize * stride + (pc - c0) as usize] = x;
                        if ca == cb {
                            m[(pc - c0) as usize * stride + (pr - r0) as usize] = x;
                        }
                    }
                    out.blocks.push(Block {
                        r0,
                        nr: nr as u32,
                        c0,
                        nc: nc as u32,
                        off: off as u32,
                    });
                } else {
                    rest.extend(
                        ents[g0..g1]
                            .iter()
                            .map(|&(_, _, pa, pb, x)| (pa.max(pb), pa.min(pb), x)),
                    );
                }
                g0 = g1;
            }
            touched.sort_unstable();
            touched.dedup();
            let first = out.touched.len();
            for &c in &touched {
                let (a, b) = (class_start[c as usize], class_start[c as usize + 1]);
                let merge = out.touched.len() > first;
                match out.touched.last_mut() {
                    Some(last) if merge && last.1 == a => last.1 = b,
                    _ => out.touched.push((a, b)),
                }
            }
            out.row_touched.push(out.touched.len() as u32);
            out.row_blocks.push(out.blocks.len() as u32);
            rest.sort_by_key(|x| (x.0, x.1));
            for (a, b, x) in rest {
                rest_i.push(a);
                rest_j.push(b);
                rest_v.push(x);
            }
            rest_start.push(rest_v.len() as u32);
        }
        assert!(
            out.values.len() <= u32::MAX as usize,
            "block values exceed u32 offsets"
        );
        out.rest = RunLayout::new(n_phi, &rest_start, &rest_i, &rest_j, &rest_v);
        out.class_start = class_start;
        #[cfg(target_arch = "x86_64")]
        {
            out.avx2_fma = is_x86_feature_detected!("avx2") && is_x86_feature_detected!("fma");
        }
        out
    }

    /// `(number of classes, number of dense blocks, stored dense values, remainder entries)`.
    pub(crate) fn stats(&self) -> (usize, usize, usize, usize) {
        (
            self.class_start.len().saturating_sub(1),
            self.blocks.len(),
            self.values.len(),
            self.rest.len(),
        )
    }

    /// Permuted ranges row `l` touches.
    #[inline(always)]
    fn touched(&self, l: usize) -> &[(u32, u32)] {
        &self.touched[self.row_touched[l] as usize..self.row_touched[l + 1] as usize]
    }

    /// `v = H^l x` on the classes row `l` touches (permuted indices; zeroed there first).
    #[inline(always)]
    fn row_apply<const FMA: bool>(&self, l: usize, x: &[f64], v: &mut [f64]) {
        for &(a, b) in self.touched(l) {
            v[a as usize..b as usize].fill(0.0);
        }
        let blocks = &self.blocks[self.row_blocks[l] as usize..self.row_blocks[l + 1] as usize];
        for b in blocks {
            let (r0, nr, c0, nc) = (b.r0 as usize, b.nr as usize, b.c0 as usize, b.nc as usize);
            let stride = nc.div_ceil(4) * 4;
            let m = &self.values[b.off as usize..b.off as usize + nr * stride];
            match (stride / 4, r0 == c0) {
                (1, d) => regs::<1, FMA>(m, x, v, r0, nr, c0, d),
                (2, d) => regs::<2, FMA>(m, x, v, r0, nr, c0, d),
                (3, d) => regs::<3, FMA>(m, x, v, r0, nr, c0, d),
                (4, d) => regs::<4, FMA>(m, x, v, r0, nr, c0, d),
                (_, true) => {
                    let xa = &x[r0..r0 + nr];
                    for (row, o) in m.chunks_exact(stride).zip(&mut v[r0..r0 + nr]) {
                        *o += dot::<FMA>(&row[..nc], xa);
                    }
                }
                (_, false) => {
                    let (xr, xc) = (&x[r0..r0 + nr], &x[c0..c0 + nc]);
                    let (vr, vc) = two_mut(v, r0, nr, c0, nc);
                    for ((row, o), &s) in m.chunks_exact(stride).zip(vr).zip(xr) {
                        *o += dot_axpy::<FMA>(&row[..nc], xc, vc, s);
                    }
                }
            }
        }
        self.rest.add_row_times(l, 1.0, x, v, 1, 0);
    }

    /// Fused `eta[l] = Σ_{ij} H^l_{ij} q_i q_j` and `grad = ∇_q Σ_l w_l eta_l²
    /// (= 4 Σ_l w_l eta_l H^l q)`, each row read once. `scratch` of length ≥ `3 N_Φ + 2 PAD`
    /// (permuted `q`, `H^l q`, permuted gradient). Audio thread, allocation-free. Runs the
    /// AVX2 + FMA instantiation when the CPU has both (detected at build, [`Self::new`]).
    pub(crate) fn quartic_gradient(
        &self,
        q: &[f64],
        w: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2_fma {
            // SAFETY: `avx2_fma` is set only when the running CPU reports both features.
            unsafe { self.quartic_avx2(q, w, eta, grad, scratch) };
            return;
        }
        self.quartic::<false>(q, w, eta, grad, scratch);
    }

    /// [`Self::quartic`] compiled for AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    unsafe fn quartic_avx2(
        &self,
        q: &[f64],
        w: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) {
        self.quartic::<true>(q, w, eta, grad, scratch);
    }

    /// The body of [`Self::quartic_gradient`] (`FMA`: fused multiply-adds).
    #[inline(always)]
    fn quartic<const FMA: bool>(
        &self,
        q: &[f64],
        w: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) {
        let n = self.n_phi;
        let (qp, rest) = scratch.split_at_mut(n + PAD);
        let (v, rest) = rest.split_at_mut(n + PAD);
        let gp = &mut rest[..n];
        for (x, &o) in qp.iter_mut().zip(&self.orig) {
            *x = q[o as usize];
        }
        qp[n..].fill(0.0);
        gp.fill(0.0);
        for (l, (el, &wl)) in eta.iter_mut().zip(w).enumerate() {
            self.row_apply::<FMA>(l, qp, v);
            let mut e = 0.0;
            for &(a, b) in self.touched(l) {
                let r = a as usize..b as usize;
                e += dot::<FMA>(&qp[r.clone()], &v[r]);
            }
            *el = e;
            let k = 4.0 * wl * e;
            if k == 0.0 {
                continue;
            }
            for &(a, b) in self.touched(l) {
                let r = a as usize..b as usize;
                for (g, &x) in gp[r.clone()].iter_mut().zip(&v[r]) {
                    *g = madd::<FMA>(k, x, *g);
                }
            }
        }
        for (&g, &o) in gp.iter().zip(&self.orig) {
            grad[o as usize] = g;
        }
    }
}

#[path = "blocks_kernels.rs"]
mod kernels;

#[cfg(test)]
#[path = "blocks_tests.rs"]
mod tests;
