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
//! # Single storage
//!
//! With [`super::TensorStorage::Single`] the blocks hold `f32` values in row panels
//! (`tensor/panels.rs`): the same classes, groups, touched ranges and remainder, only the
//! block values and their kernel differ (widened to `f64`, accumulated in `f64`). The
//! default `f64` blocks and their kernels above are unchanged by it.
//!
//! Threads: built on a worker thread with the tensor; the kernels run on the audio thread
//! without allocating.

use super::runs::RunLayout;
use dense::{dot, dot_axpy, madd, regs, two_mut};
use std::collections::HashMap;

/// Smallest fill (stored entries over block size) for which a class-pair group is stored as a
/// dense block; sparser groups stay in the gathered run layout. A dense block costs about one
/// multiply-add per stored element (zeros included) at contiguous-load speed, a run entry an
/// index load and a gather/scatter (about 2 ns measured, several times a dense element), so
/// dense pays well below full fill; 0.25 keeps the zero-padding overhead at most 4×.
pub(crate) const MIN_FILL: f64 = 0.25;

/// Cap on colour-refinement passes (each is `O(nnz)`; see the module docs).
pub(crate) const MAX_REFINE: usize = 200;

/// A dense `f64` block of one row: rows `r0..r0+nr`, columns `c0..c0+nc` (permuted indices),
/// values at `off..off + nr·⌈nc/4⌉·4` (row-major, rows padded to multiples of 4 columns).
/// Diagonal when `r0 == c0` (then `nr == nc`, full). Single storage keeps its blocks as the
/// column chunks of `tensor/panels.rs` instead.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Block {
    r0: u32,
    nr: u32,
    c0: u32,
    nc: u32,
    off: u32,
}

/// The values of the dense blocks, in one of two layouts.
#[derive(Debug, Clone, PartialEq)]
enum BlockValues {
    /// `f64`, row-major with rows padded to multiples of 4 columns (the [`regs`] and
    /// dot/axpy kernels; the default storage).
    Double(Vec<f64>),
    /// `f32` row panels and their column chunks (`tensor/panels.rs`; single storage).
    Single(panels::Panels),
}

impl Default for BlockValues {
    fn default() -> Self {
        Self::Double(Vec::new())
    }
}

impl BlockValues {
    fn heap_bytes(&self) -> usize {
        match self {
            Self::Double(v) => crate::modal::tensor::runs::vec_bytes(v),
            Self::Single(p) => p.heap_bytes(),
        }
    }

    fn len(&self) -> usize {
        match self {
            Self::Double(v) => v.len(),
            Self::Single(p) => p.len(),
        }
    }
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
    /// Block values (`H`, not halved): `f64` rows or `f32` row panels.
    values: BlockValues,
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

/// Scratch padding past each `N_Φ` buffer (the padded lanes of the `f64` register kernel and
/// of the single-storage row panels, at most 3).
pub(crate) const PAD: usize = 4;

impl BlockLayout {
    /// Heap bytes held (the vectors' capacities, the remainder's runs included). Any thread.
    pub(crate) fn heap_bytes(&self) -> usize {
        use crate::modal::tensor::runs::vec_bytes;
        vec_bytes(&self.orig)
            + vec_bytes(&self.class_start)
            + vec_bytes(&self.row_blocks)
            + vec_bytes(&self.blocks)
            + self.values.heap_bytes()
            + vec_bytes(&self.row_touched)
            + vec_bytes(&self.touched)
            + self.rest.heap_bytes()
    }

    /// Builds the layout from validated CSR parts (`j ≤ i < n_phi ≤ 65 536`, rows sorted by
    /// `(i, j)`), with `f64` block values, or `f32` row panels when `single` (then every `v`
    /// must be an `f32` value, so that the blocks hold exactly `v`). Worker thread; allocates.
    pub(crate) fn new(
        n_phi: usize,
        row_start: &[u32],
        i: &[u32],
        j: &[u32],
        v: &[f64],
        single: bool,
    ) -> Self {
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
            values: if single {
                BlockValues::Single(panels::Panels::new(n_phi, PAD))
            } else {
                BlockValues::Double(Vec::new())
            },
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
                    let a = (class_start[ca as usize], na);
                    let b = (class_start[cb as usize], nb);
                    out.push_block(a, b, ca == cb, &ents[g0..g1]);
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
            if let BlockValues::Single(p) = &mut out.values {
                p.end_row();
            }
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

    /// Appends the dense block of one class-pair group: row class `a`, column class `b`
    /// (`(first permuted index, size)`; `diag` when they are the same class), entries
    /// `(class, class, permuted a, permuted b, value)` with the first index in `a`.
    fn push_block(
        &mut self,
        a: (u32, usize),
        b: (u32, usize),
        diag: bool,
        ents: &[(u32, u32, u32, u32, f64)],
    ) {
        let ((a0, na), (b0, nb)) = (a, b);
        match &mut self.values {
            BlockValues::Double(values) => {
                // Columns: the smaller class (its partial sums stay in registers).
                let (r0, nr, c0, nc, swap) = if diag || na >= nb {
                    (a0, na, b0, nb, false)
                } else {
                    (b0, nb, a0, na, true)
                };
                let stride = nc.div_ceil(4) * 4;
                let off = values.len();
                values.resize(off + nr * stride, 0.0);
                let m = &mut values[off..];
                for &(_, _, pa, pb, x) in ents {
                    let (pr, pc) = if swap { (pb, pa) } else { (pa, pb) };
                    m[(pr - r0) as usize * stride + (pc - c0) as usize] = x;
                    if diag {
                        m[(pc - c0) as usize * stride + (pr - r0) as usize] = x;
                    }
                }
                self.blocks.push(Block {
                    r0,
                    nr: nr as u32,
                    c0,
                    nc: nc as u32,
                    off: off as u32,
                });
            }
            BlockValues::Single(p) => {
                // Rows: the larger class (module docs of `tensor/panels.rs`).
                let (r0, nr, c0, nc, swap) = if diag || na >= nb {
                    (a0, na, b0, nb, false)
                } else {
                    (b0, nb, a0, na, true)
                };
                let entries = ents.iter().map(|&(_, _, pa, pb, x)| {
                    let (pr, pc) = if swap { (pb, pa) } else { (pa, pb) };
                    // `x` is an f32 value (single storage rounds the tensor first): exact.
                    ((pr - r0) as usize, (pc - c0) as usize, x as f32)
                });
                p.push_block((r0 as usize, nr), (c0 as usize, nc), diag, entries);
            }
        }
    }

    /// Whether the block values are the `f32` row panels (single storage).
    #[cfg(test)]
    pub(crate) fn is_single(&self) -> bool {
        matches!(self.values, BlockValues::Single(_))
    }

    /// `(number of classes, number of dense blocks, stored dense values, remainder entries)`.
    pub(crate) fn stats(&self) -> (usize, usize, usize, usize) {
        let blocks = match &self.values {
            BlockValues::Double(_) => self.blocks.len(),
            BlockValues::Single(p) => p.blocks(),
        };
        (
            self.class_start.len().saturating_sub(1),
            blocks,
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
        match &self.values {
            BlockValues::Double(values) => Self::blocks_f64::<FMA>(blocks, values, x, v),
            BlockValues::Single(p) => p.row_apply::<FMA>(l, x, v),
        }
        self.rest.add_row_times(l, 1.0, x, v, 1, 0);
    }

    /// The `f64` blocks of one row: `v += H^l x` (see [`Self::row_apply`]).
    #[inline(always)]
    fn blocks_f64<const FMA: bool>(blocks: &[Block], values: &[f64], x: &[f64], v: &mut [f64]) {
        for b in blocks {
            let (r0, nr, c0, nc) = (b.r0 as usize, b.nr as usize, b.c0 as usize, b.nc as usize);
            let stride = nc.div_ceil(4) * 4;
            let m = &values[b.off as usize..b.off as usize + nr * stride];
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
    }

    /// Fused `eta[l] = Σ_{ij} H^l_{ij} q_i q_j` and `grad = ∇_q Σ_l w_l (eta_l - c_l)²
    /// (= 4 Σ_l w_l (eta_l - c_l) H^l q)` over the rows `rows` of the tensor, each row read
    /// once, with the offsets `c = shift` (whole length `N_Ψ`; `None` is `c = 0`, the flat
    /// plate, bit for bit as without it; a curved plate's `c_l = Ĥ(a, a)_l`):
    /// `eta` holds `eta[l - rows.start]` for `l` in `rows` (length `rows.len()`), `w` is the
    /// whole weight vector, and `grad` receives `4 Σ_{l ∈ rows} w_l eta_l H^l q` only (the
    /// gradients of a partition of `0..N_Ψ` add up to the whole). `scratch` of length
    /// ≥ `3 N_Φ + 2 PAD` (permuted `q`, `H^l q`, permuted gradient). Audio thread or a worker
    /// sharing one step, allocation-free. Runs the AVX2 + FMA instantiation when the CPU has
    /// both (detected at build, [`Self::new`]).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn quartic_gradient_rows(
        &self,
        rows: std::ops::Range<usize>,
        q: &[f64],
        w: &[f64],
        shift: Option<&[f64]>,
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) {
        #[cfg(target_arch = "x86_64")]
        if self.avx2_fma {
            // SAFETY: `avx2_fma` is set only when the running CPU reports both features.
            unsafe { self.quartic_avx2(rows, q, w, shift, eta, grad, scratch) };
            return;
        }
        self.quartic::<false>(rows, q, w, shift, eta, grad, scratch);
    }

    /// [`Self::quartic`] compiled for AVX2 and FMA.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2,fma")]
    #[allow(clippy::too_many_arguments)]
    unsafe fn quartic_avx2(
        &self,
        rows: std::ops::Range<usize>,
        q: &[f64],
        w: &[f64],
        shift: Option<&[f64]>,
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) {
        self.quartic::<true>(rows, q, w, shift, eta, grad, scratch);
    }

    /// The body of [`Self::quartic_gradient_rows`] (`FMA`: fused multiply-adds).
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn quartic<const FMA: bool>(
        &self,
        rows: std::ops::Range<usize>,
        q: &[f64],
        w: &[f64],
        shift: Option<&[f64]>,
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
        let l0 = rows.start;
        for (l, (el, &wl)) in (l0..).zip(eta.iter_mut().zip(&w[rows])) {
            self.row_apply::<FMA>(l, qp, v);
            let mut e = 0.0;
            for &(a, b) in self.touched(l) {
                let r = a as usize..b as usize;
                e += dot::<FMA>(&qp[r.clone()], &v[r]);
            }
            *el = e;
            let k = match shift {
                None => 4.0 * wl * e,
                Some(c) => 4.0 * wl * (e - c[l]),
            };
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

#[path = "blocks_dense.rs"]
mod dense;

#[path = "blocks_kernels.rs"]
mod kernels;

#[path = "panels.rs"]
mod panels;

#[cfg(test)]
#[path = "blocks_tests.rs"]
mod tests;
