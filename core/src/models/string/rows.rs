//! Stored rows of the grid map `S` at a few nodes: the grid values a step needs (obstacle
//! nodes, the nodes a grid pickup interpolates between) without a full DST, and the modal
//! force of a few active contact nodes without the inverse DST.
//!
//! Row of node `i` (`1 ≤ i ≤ N-1`): `S_ij = √(2/L) sin(jπi/N)`, `j = 1..N-1` ([`super::transform`]),
//! the sine argument reduced exactly in integers (`ij mod 2N`) like [`super::ModalMap::dense`].
//! Since `S⁻¹ = Δx S` and `S` is symmetric, the row of `S⁻¹` at node `i` is `Δx` times the
//! same values: one stored row serves both directions.
//!
//! **Half rows.** `sin((N-j)πi/N) = sin(πi - jπi/N) = (-1)^{i+1} sin(jπi/N)`, so
//! `S_{i,N-j} = (-1)^{i+1} S_ij` and
//! `u_i = Σ_{j ≤ N/2} S_ij (w_j + (-1)^{i+1} w_{N-j})` (the middle mode `j = N/2` of an even
//! `N` counted once). Only `j = 1..⌊N/2⌋` is stored; one O(N/2) pass per step folds `w` into
//! its even and odd combinations, and each node's value is a dot product of half length. This
//! halves both the multiply-adds and the memory a step streams.
//!
//! Cost: `T · N/2` multiply-adds for `T` stored nodes against about `8 N log₂ N` flops (plus
//! the FFT's memory passes) for a DST of the whole grid. Nodes of one parity are summed four
//! at a time (one pass over the folded vector serves four rows), each row in two interleaved
//! SIMD partial sums ([`pulp`] picks AVX2+FMA or the portable lanes at run time), so the
//! result differs from the DST's by round-off only (and between machines by round-off too).
//!
//! Built on the control thread; [`NodeRows::synthesize`] and [`NodeRows::add_row`] run on the
//! audio thread without allocating.

use pulp::{Arch, Simd, WithSimd};
use std::f64::consts::PI;

/// Rows of `S` at a fixed list of interior nodes, stored as half rows.
///
/// Built on the control thread; used on the audio thread.
#[derive(Debug, Clone)]
pub struct NodeRows {
    /// Interior index (`i - 1`) of each stored node, in storage order.
    nodes: Vec<usize>,
    /// `rows[t·H + j-1] = S_{i_t j}`, `j = 1..H`, `H = ⌊N/2⌋`, in m^-1/2 (node-major).
    rows: Vec<f64>,
    /// Storage indices of the nodes with odd `i` (their values use `w_j + w_{N-j}`).
    odd: Vec<usize>,
    /// Storage indices of the nodes with even `i` (their values use `w_j - w_{N-j}`).
    even: Vec<usize>,
    /// Half-row length `H = ⌊N/2⌋`.
    half: usize,
    /// Number of pairs `j < N - j`, `j ≥ 1`: `⌊(N-1)/2⌋`.
    pairs: usize,
    /// Number of modes `N_m = N - 1`.
    modes: usize,
    /// Scratch: `w_j + w_{N-j}` for `j = 1..H` (m^3/2).
    sum: Vec<f64>,
    /// Scratch: `w_j - w_{N-j}` for `j = 1..H` (m^3/2).
    diff: Vec<f64>,
    /// The SIMD level detected at build.
    arch: Arch,
}

impl NodeRows {
    /// Stores the rows of `S` at `nodes` (interior indices `i - 1 < N - 1`, any order, no
    /// duplicates expected) for a string of length `length` (m) on `intervals = N` intervals.
    /// Allocates `nodes.len() · ⌊N/2⌋` values; control thread.
    pub fn new(length: f64, intervals: usize, nodes: Vec<usize>) -> Self {
        let half = intervals / 2;
        let norm = (2.0 / length).sqrt();
        let two_n = 2 * intervals;
        let mut rows = Vec::with_capacity(nodes.len() * half);
        for &k in &nodes {
            let i = k + 1;
            rows.extend((1..=half).map(|j| {
                let r = (i * j) % two_n;
                norm * (PI * r as f64 / intervals as f64).sin()
            }));
        }
        let (odd, even) = (0..nodes.len()).partition(|&t| nodes[t] % 2 == 0);
        Self {
            nodes,
            rows,
            odd,
            even,
            half,
            pairs: (intervals - 1) / 2,
            modes: intervals - 1,
            sum: vec![0.0; half],
            diff: vec![0.0; half],
            arch: Arch::new(),
        }
    }

    /// Number of stored nodes `T`.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether no node is stored.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Interior indices (`i - 1`) of the stored nodes, in storage order.
    pub fn nodes(&self) -> &[usize] {
        &self.nodes
    }

    /// Half row `t`: `S_{i_t j}` for `j = 1..⌊N/2⌋` (m^-1/2).
    pub fn half_row(&self, t: usize) -> &[f64] {
        &self.rows[t * self.half..(t + 1) * self.half]
    }

    /// `out[i_t] = Σ_j S_{i_t j} w_j` for every stored node `t` (`w` in m^3/2, `out` in m, both
    /// of length `N - 1`); other entries of `out` are left untouched. One O(N) fold of `w`,
    /// then `T · ⌊N/2⌋` multiply-adds; no allocation.
    pub fn synthesize(&mut self, w: &[f64], out: &mut [f64]) {
        assert!(w.len() == self.modes && out.len() == self.modes);
        // Fold: sum_j = w_j + w_{N-j}, diff_j = w_j - w_{N-j} (j = 1..pairs); the middle mode
        // j = N/2 of an even N (if any) is counted once in both.
        let (p, m) = (self.pairs, self.modes);
        let upper = w[m - p..].iter().rev();
        for (((s, d), &a), &b) in self
            .sum
            .iter_mut()
            .zip(&mut self.diff)
            .zip(&w[..p])
            .zip(upper)
        {
            *s = a + b;
            *d = a - b;
        }
        if self.half > p {
            self.sum[p] = w[p];
            self.diff[p] = w[p];
        }
        let h = self.half;
        for (list, folded) in [(&self.odd, &self.sum), (&self.even, &self.diff)] {
            let mut blocks = list.chunks_exact(4);
            for b in blocks.by_ref() {
                let r = [b[0], b[1], b[2], b[3]].map(|t| &self.rows[t * h..(t + 1) * h]);
                let v = self.arch.dispatch(Dots { r, w: folded });
                for (&t, v) in b.iter().zip(v) {
                    out[self.nodes[t]] = v;
                }
            }
            for &t in blocks.remainder() {
                let r = [&self.rows[t * h..(t + 1) * h]];
                let [v] = self.arch.dispatch(Dots { r, w: folded });
                out[self.nodes[t]] = v;
            }
        }
    }

    /// `acc += a Σ_t f_t S_{i_t ·}` over the first `f.len()` stored rows (skipping `f_t = 0`):
    /// the modal force of the active obstacle nodes. The rows of each parity are first summed
    /// over the half range (`c_odd`, `c_even`, `active · ⌊N/2⌋` multiply-adds), then one pass
    /// writes `acc_j += c_odd,j + c_even,j` and `acc_{N-j} += c_odd,j - c_even,j`. No allocation.
    pub fn add_rows(&mut self, a: f64, f: &[f64], acc: &mut [f64]) {
        let active = f.iter().filter(|&&x| x != 0.0).count();
        if active <= 1 {
            for (t, &ft) in f.iter().enumerate() {
                if ft != 0.0 {
                    self.add_row(t, a * ft, acc);
                }
            }
            return;
        }
        let (h, p) = (self.half, self.pairs);
        self.sum.fill(0.0);
        self.diff.fill(0.0);
        for (t, &ft) in f.iter().enumerate() {
            if ft != 0.0 {
                let row = &self.rows[t * h..(t + 1) * h];
                let c = if self.nodes[t] % 2 == 0 {
                    &mut self.sum
                } else {
                    &mut self.diff
                };
                self.arch.dispatch(Axpy {
                    y: c,
                    a: a * ft,
                    x: row,
                });
            }
        }
        let (lower, upper) = acc.split_at_mut(h);
        debug_assert_eq!(upper.len(), p);
        self.arch.dispatch(Unfold {
            lower,
            upper,
            sum: &self.sum,
            diff: &self.diff,
        });
    }

    /// `acc += a · S_{i_t ·}`: adds `a` times the full row `t` to `acc` (length `N - 1`), the
    /// upper half from the stored half by `S_{i,N-j} = (-1)^{i+1} S_ij`. No allocation.
    pub fn add_row(&self, t: usize, a: f64, acc: &mut [f64]) {
        let row = self.half_row(t);
        let (h, p, m) = (self.half, self.pairs, self.modes);
        let (lower, upper) = acc.split_at_mut(h);
        for (d, r) in lower.iter_mut().zip(row) {
            *d += a * r;
        }
        let b = if self.nodes[t] % 2 == 0 { a } else { -a };
        // j = h+1..N-1 pairs with N-j = p..1: the upper part has exactly `p` entries.
        debug_assert_eq!(upper.len(), p);
        debug_assert_eq!(m - h, p);
        for (d, r) in upper.iter_mut().rev().zip(&row[..p]) {
            *d += b * r;
        }
    }
}

/// `y += a x` (same lengths), vectorised at the detected SIMD width.
struct Axpy<'a> {
    /// Accumulated in place.
    y: &'a mut [f64],
    /// Scale.
    a: f64,
    /// Added vector.
    x: &'a [f64],
}

impl WithSimd for Axpy<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        for (y, x) in self.y.iter_mut().zip(self.x) {
            *y += self.a * x;
        }
    }
}

/// The final pass of [`NodeRows::add_rows`]: `lower_j += s_j + e_j`, `upper_{N-j} += s_j - e_j`.
struct Unfold<'a> {
    /// `acc_j`, `j = 1..H`.
    lower: &'a mut [f64],
    /// `acc_j`, `j = H+1..N-1` (as many as there are pairs).
    upper: &'a mut [f64],
    /// Sum of the odd-node rows.
    sum: &'a [f64],
    /// Sum of the even-node rows.
    diff: &'a [f64],
}

impl WithSimd for Unfold<'_> {
    type Output = ();

    #[inline(always)]
    fn with_simd<S: Simd>(self, _simd: S) {
        for ((d, s), e) in self.lower.iter_mut().zip(self.sum).zip(self.diff) {
            *d += s + e;
        }
        let p = self.upper.len();
        let upper = self.upper.iter_mut().rev();
        for ((d, s), e) in upper.zip(&self.sum[..p]).zip(&self.diff[..p]) {
            *d += s - e;
        }
    }
}

/// `R` dot products `⟨r_k, w⟩` in one pass over `w`, each in two interleaved SIMD partial sums
/// (lanes of the detected width), the scalar tail added last.
struct Dots<'a, const R: usize> {
    /// The rows (each as long as `w`).
    r: [&'a [f64]; R],
    /// The vector.
    w: &'a [f64],
}

impl<const R: usize> WithSimd for Dots<'_, R> {
    type Output = [f64; R];

    #[inline(always)]
    fn with_simd<S: Simd>(self, simd: S) -> [f64; R] {
        let (wh, wt) = S::as_simd_f64s(self.w);
        let rs = self.r.map(|x| S::as_simd_f64s(x));
        let z = simd.splat_f64s(0.0);
        let mut acc = [[z; 2]; R];
        let n2 = wh.len() - wh.len() % 2;
        for (j, wv) in wh[..n2].chunks_exact(2).enumerate() {
            for (a, r) in acc.iter_mut().zip(&rs) {
                let x = &r.0[2 * j..2 * j + 2];
                a[0] = simd.mul_add_e_f64s(x[0], wv[0], a[0]);
                a[1] = simd.mul_add_e_f64s(x[1], wv[1], a[1]);
            }
        }
        if n2 < wh.len() {
            for (a, r) in acc.iter_mut().zip(&rs) {
                a[0] = simd.mul_add_e_f64s(r.0[n2], wh[n2], a[0]);
            }
        }
        let mut out = [0.0; R];
        for ((o, a), r) in out.iter_mut().zip(&acc).zip(&rs) {
            let mut s = simd.reduce_sum_f64s(simd.add_f64s(a[0], a[1]));
            for (x, y) in r.1.iter().zip(wt) {
                s += x * y;
            }
            *o = s;
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::models::string::ModalMap;

    /// The stored rows reproduce the DST synthesis at their nodes to round-off, for row counts
    /// that exercise the 4-row blocks and the remainder, and lengths not divisible by 4.
    /// Tolerance: both are sums of `N - 1` products of size ≤ `√(2/L)·max|w|`; their
    /// round-off is at most a few ulps times `√N` of that scale (FFT error grows like
    /// `log N`, a pairwise-like sum like `√N` in the mean): `1e-14 · √(2/L) Σ|w|` is a bound
    /// with margin, and far below any physical effect.
    #[test]
    fn rows_match_the_dst() {
        for (l, n) in [(1.0, 65), (0.7, 64), (1.3, 1008)] {
            let m = n - 1;
            let nodes: Vec<usize> = [0, 3, m / 2, m - 1, 7, m / 3, 11]
                .into_iter()
                .filter(|&x| x < m)
                .collect();
            let mut rows = NodeRows::new(l, n, nodes.clone());
            let w: Vec<f64> = (0..m).map(|j| ((j * 37 + 5) % 17) as f64 - 8.0).collect();
            let mut full = w.clone();
            ModalMap::new(l, n).synthesis(&mut full);
            let mut out = vec![f64::NAN; m];
            rows.synthesize(&w, &mut out);
            let scale = (2.0 / l).sqrt() * w.iter().map(|x| x.abs()).sum::<f64>();
            for &i in &nodes {
                let err = (out[i] - full[i]).abs();
                assert!(err <= 1e-14 * scale, "N = {n}, node {i}: {err:e}");
            }
            // add_row rebuilds each full row from its half (upper half by the symmetry):
            // equal to the dense S to the round-off of two sines whose arguments (≤ 2π) carry
            // a relative error of an ulp, so an absolute error ≤ 2π ε √(2/L) each.
            let dense = ModalMap::dense(l, n);
            for (t, &i) in nodes.iter().enumerate() {
                let mut acc = vec![0.0; m];
                rows.add_row(t, 1.0, &mut acc);
                for (a, b) in acc.iter().zip(&dense[i * m..(i + 1) * m]) {
                    assert!(
                        (a - b).abs() <= 4.0 * PI * f64::EPSILON * (2.0 / l).sqrt(),
                        "{a} {b}"
                    );
                }
            }
            let untouched = (0..m)
                .filter(|i| !nodes.contains(i))
                .all(|i| out[i].is_nan());
            assert!(untouched, "only stored nodes are written");
        }
    }
}
