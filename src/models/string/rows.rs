//! Stored rows of the grid map `S` at a few nodes: the grid values a step needs (obstacle
//! nodes, the nodes a grid pickup interpolates between) without a full DST, and the modal
//! force of a few active contact nodes without the inverse DST.
//!
//! Row of node `i` (`1 ≤ i ≤ N-1`): `S_ij = √(2/L) sin(jπi/N)`, `j = 1..N-1` ([`super::transform`]),
//! the sine argument reduced exactly in integers (`ij mod 2N`) like [`super::ModalMap::dense`].
//! Since `S⁻¹ = Δx S` and `S` is symmetric, the row of `S⁻¹` at node `i` is `Δx` times the
//! same values: one stored row serves both directions.
//!
//! Cost: `T · N_m` multiply-adds for `T` stored nodes against about `8 N log₂ N` flops (plus
//! the FFT's memory passes) for a DST of the whole grid. The products are summed four rows at
//! a time, each row in four interleaved partial sums (`j mod 4`), so one pass over the modal
//! vector serves four nodes and the inner loop vectorises without reassociating a sum (strict
//! IEEE order is kept within each partial sum; the result differs from the DST's by round-off).
//!
//! Built on the control thread; [`NodeRows::synthesize`] and [`NodeRows::add_row`] run on the
//! audio thread without allocating.

use std::f64::consts::PI;

/// Rows of `S` at a fixed list of interior nodes.
///
/// Built on the control thread; read on the audio thread.
#[derive(Debug, Clone, Default)]
pub struct NodeRows {
    /// Interior index (`i - 1`) of each stored node, in storage order.
    nodes: Vec<usize>,
    /// `rows[t·N_m + j-1] = S_{i_t j}` in m^-1/2 (node-major, contiguous rows).
    rows: Vec<f64>,
    /// Number of modes `N_m = N - 1` (row length).
    modes: usize,
}

impl NodeRows {
    /// Stores the rows of `S` at `nodes` (interior indices `i - 1 < N - 1`, any order, no
    /// duplicates expected) for a string of length `length` (m) on `intervals = N` intervals.
    /// Allocates `nodes.len() · (N - 1)` values; control thread.
    pub fn new(length: f64, intervals: usize, nodes: Vec<usize>) -> Self {
        let m = intervals - 1;
        let norm = (2.0 / length).sqrt();
        let two_n = 2 * intervals;
        let mut rows = Vec::with_capacity(nodes.len() * m);
        for &k in &nodes {
            let i = k + 1;
            rows.extend((1..=m).map(|j| {
                let r = (i * j) % two_n;
                norm * (PI * r as f64 / intervals as f64).sin()
            }));
        }
        Self {
            nodes,
            rows,
            modes: m,
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

    /// Row `t` of `S` (m^-1/2), length `N - 1`.
    pub fn row(&self, t: usize) -> &[f64] {
        &self.rows[t * self.modes..(t + 1) * self.modes]
    }

    /// `out[i_t] = Σ_j S_{i_t j} w_j` for every stored node `t` (`w` in m^3/2, `out` in m, both
    /// of length `N - 1`); other entries of `out` are left untouched. `T · N_m` multiply-adds,
    /// no allocation.
    pub fn synthesize(&self, w: &[f64], out: &mut [f64]) {
        let m = self.modes;
        assert!(w.len() == m && out.len() == m);
        let mut quads = self.rows.chunks_exact(4 * m);
        let mut t = 0;
        for block in quads.by_ref() {
            let (r0, rest) = block.split_at(m);
            let (r1, rest) = rest.split_at(m);
            let (r2, r3) = rest.split_at(m);
            let s = dot4([r0, r1, r2, r3], w);
            for (n, v) in s.into_iter().enumerate() {
                out[self.nodes[t + n]] = v;
            }
            t += 4;
        }
        for row in quads.remainder().chunks_exact(m) {
            out[self.nodes[t]] = dot1(row, w);
            t += 1;
        }
    }

    /// `acc += a · S_{i_t ·}`: adds `a` times row `t` to `acc` (length `N - 1`). No allocation.
    pub fn add_row(&self, t: usize, a: f64, acc: &mut [f64]) {
        for (d, r) in acc.iter_mut().zip(self.row(t)) {
            *d += a * r;
        }
    }
}

/// Four dot products `⟨r_k, w⟩` in one pass over `w`, each summed in four interleaved partial
/// sums (lanes `j mod 4`) that vectorise without reassociation.
#[inline]
fn dot4(r: [&[f64]; 4], w: &[f64]) -> [f64; 4] {
    let mut acc = [[0.0f64; 4]; 4];
    let n4 = w.len() - w.len() % 4;
    let wc = w[..n4].chunks_exact(4);
    let rc = r.map(|x| x[..n4].chunks_exact(4));
    let [c0, c1, c2, c3] = rc;
    for ((((wv, x0), x1), x2), x3) in wc.zip(c0).zip(c1).zip(c2).zip(c3) {
        for l in 0..4 {
            acc[0][l] += x0[l] * wv[l];
            acc[1][l] += x1[l] * wv[l];
            acc[2][l] += x2[l] * wv[l];
            acc[3][l] += x3[l] * wv[l];
        }
    }
    for j in n4..w.len() {
        for k in 0..4 {
            acc[k][0] += r[k][j] * w[j];
        }
    }
    acc.map(|a| (a[0] + a[1]) + (a[2] + a[3]))
}

/// One dot product `⟨r, w⟩` in four interleaved partial sums.
#[inline]
fn dot1(r: &[f64], w: &[f64]) -> f64 {
    let mut acc = [0.0f64; 4];
    let n4 = w.len() - w.len() % 4;
    for (wv, x) in w[..n4].chunks_exact(4).zip(r[..n4].chunks_exact(4)) {
        for l in 0..4 {
            acc[l] += x[l] * wv[l];
        }
    }
    for j in n4..w.len() {
        acc[0] += r[j] * w[j];
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3])
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
            let rows = NodeRows::new(l, n, nodes.clone());
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
            let untouched = (0..m)
                .filter(|i| !nodes.contains(i))
                .all(|i| out[i].is_nan());
            assert!(untouched, "only stored nodes are written");
        }
    }
}
