//! The kernel layout of the coupling tensor: each row `l` split into runs of equal first index
//! `i`, with the second indices `j` as `u16` and the values halved on the diagonal, so that
//! every kernel is branch-free and streams 10 bytes per entry (the `(u32, u32, f64)` entry
//! arrays of [`super::CouplingTensor`] stream 16).
//!
//! With `ĥ_e = H_e` off the diagonal and `H_e / 2` on it, the stored `j ≤ i` half gives, for
//! each row `l` and each run `r` (first index `i_r`, entries `e ∈ r`):
//!
//! ```text
//! Σ_{i,j} H^l_{ij} a_i b_j = Σ_r (a_{i_r} S_r(b) + b_{i_r} S_r(a)),   S_r(x) = Σ_{e∈r} ĥ_e x_{j_e},
//! Σ_k H^l_{s,k} x_k       = Σ_{r: i_r = s} S_r(x) + Σ_{e: j_e = s} ĥ_e x_{i_{r(e)}}.
//! ```
//!
//! The first index `i_r` of a run is loaded once, `S_r` is a gathered dot product with four
//! independent sums, and the second sum is a scatter whose targets are distinct within a run
//! (`j` strictly increasing), so consecutive updates do not depend on each other. Indices are
//! checked once at construction (`j ≤ i < N_Φ ≤ 65 536`); the hot loops index with
//! `get_unchecked` on that guarantee. Rows are the selection-rule blocks of the tensor (for
//! circular plates, only `(i, j)` whose angular orders combine to that of `Ψ_l` are stored), so
//! each kernel touches one block at a time and the fused [`RunLayout::quartic_gradient`]
//! re-reads a block while it is still in cache.
//!
//! The fused SAV kernel of [`super::CouplingTensor::quartic_gradient`] now streams the dense
//! selection-rule blocks of `tensor/blocks.rs` (about 3-4× faster on the gong's tensors);
//! [`RunLayout::quartic_gradient`] stays as its reference (`quartic_gradient_runs`) and as the
//! fall-back for sparse class pairs; the schemes' `contract_eta`, `apply_force` and
//! `coupling_matrix` also stream the blocks (`*_with_scratch`), and the run kernels here stay
//! as their references (the plain `CouplingTensor` methods).
//!
//! Threads: built on a worker thread with the tensor; kernels run on the audio thread without
//! allocating.

/// Run-structured copy of a `j ≤ i` sparse symmetric tensor (see the module docs).
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct RunLayout {
    n_phi: usize,
    /// Row `l` owns runs `row_runs[l]..row_runs[l + 1]`.
    row_runs: Vec<u32>,
    /// First index `i` of each run.
    run_i: Vec<u16>,
    /// Run `r` owns entries `run_end[r - 1]..run_end[r]` (from 0 for the first run).
    run_end: Vec<u32>,
    /// Second index `j` of each entry.
    col: Vec<u16>,
    /// `ĥ`: the value, halved when `i = j`.
    half: Vec<f64>,
}

/// Heap bytes of a vector's allocation (its capacity), for the layouts' `heap_bytes`. Any
/// thread.
pub(crate) fn vec_bytes<T>(v: &Vec<T>) -> usize {
    v.capacity() * std::mem::size_of::<T>()
}

/// Largest `N_Φ` the layout can index (`u16`).
pub(crate) const MAX_N_PHI: usize = 1 << 16;

impl RunLayout {
    /// Heap bytes held (the vectors' capacities). Any thread.
    pub(crate) fn heap_bytes(&self) -> usize {
        vec_bytes(&self.row_runs)
            + vec_bytes(&self.run_i)
            + vec_bytes(&self.run_end)
            + vec_bytes(&self.col)
            + vec_bytes(&self.half)
    }

    /// Builds the layout from validated CSR parts (`j ≤ i < n_phi ≤ MAX_N_PHI`, rows sorted by
    /// `(i, j)`). Worker thread.
    pub(crate) fn new(n_phi: usize, row_start: &[u32], i: &[u32], j: &[u32], v: &[f64]) -> Self {
        assert!(n_phi <= MAX_N_PHI);
        let n_psi = row_start.len().saturating_sub(1);
        let mut out = Self {
            n_phi,
            row_runs: Vec::with_capacity(n_psi + 1),
            col: j.iter().map(|&x| x as u16).collect(),
            half: i
                .iter()
                .zip(j)
                .zip(v)
                .map(|((a, b), x)| if a == b { 0.5 * x } else { *x })
                .collect(),
            ..Self::default()
        };
        out.row_runs.push(0);
        for l in 0..n_psi {
            let (a, b) = (row_start[l] as usize, row_start[l + 1] as usize);
            let mut e = a;
            while e < b {
                let ie = i[e];
                while e < b && i[e] == ie {
                    e += 1;
                }
                out.run_i.push(ie as u16);
                out.run_end.push(e as u32);
            }
            out.row_runs.push(out.run_i.len() as u32);
        }
        out
    }

    /// Runs of row `l` as `(first run, end run, first entry)`.
    #[inline]
    fn row(&self, l: usize) -> (usize, usize, usize) {
        let (r0, r1) = (self.row_runs[l] as usize, self.row_runs[l + 1] as usize);
        let e0 = if r0 == 0 {
            0
        } else {
            self.run_end[r0 - 1] as usize
        };
        (r0, r1, e0)
    }

    /// `S = Σ_{e ∈ e0..e1} ĥ_e x[j_e]` with four partial sums.
    #[inline]
    fn gather_dot(&self, e0: usize, e1: usize, x: &[f64]) -> f64 {
        debug_assert!(x.len() >= self.n_phi);
        let (cols, vals) = (&self.col[e0..e1], &self.half[e0..e1]);
        let mut acc = [0.0f64; 4];
        let (cc, vc) = (cols.chunks_exact(4), vals.chunks_exact(4));
        let (cr, vr) = (cc.remainder(), vc.remainder());
        for (c, v) in cc.zip(vc) {
            // SAFETY: every `j` was checked `< n_phi <= x.len()` when the tensor was built.
            unsafe {
                acc[0] += v[0] * x.get_unchecked(c[0] as usize);
                acc[1] += v[1] * x.get_unchecked(c[1] as usize);
                acc[2] += v[2] * x.get_unchecked(c[2] as usize);
                acc[3] += v[3] * x.get_unchecked(c[3] as usize);
            }
        }
        let mut tail = 0.0;
        for (&c, &v) in cr.iter().zip(vr) {
            // SAFETY: as above.
            tail += v * unsafe { x.get_unchecked(c as usize) };
        }
        (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
    }

    /// `out[j_e] += k ĥ_e` for `e ∈ e0..e1`, with `out[j] = base[j * stride]`.
    #[inline]
    fn scatter(&self, e0: usize, e1: usize, k: f64, out: &mut [f64], stride: usize, off: usize) {
        debug_assert!(out.len() > (self.n_phi - 1) * stride + off);
        for (&c, &v) in self.col[e0..e1].iter().zip(&self.half[e0..e1]) {
            // SAFETY: `j < n_phi`, and callers pass `out` of length ≥ (n_phi - 1) stride + off + 1.
            unsafe { *out.get_unchecked_mut(c as usize * stride + off) += k * v };
        }
    }

    /// `Σ_{i,j} H^l_{ij} a_i b_j` for row `l`.
    pub(crate) fn contract_row(&self, l: usize, a: &[f64], b: &[f64]) -> f64 {
        assert!(
            a.len().min(b.len()) >= self.n_phi,
            "gather_dot's unchecked reads"
        );
        let (r0, r1, mut e0) = self.row(l);
        let mut acc = 0.0;
        for r in r0..r1 {
            let (i, e1) = (self.run_i[r] as usize, self.run_end[r] as usize);
            acc += if std::ptr::eq(a, b) {
                2.0 * a[i] * self.gather_dot(e0, e1, a)
            } else {
                a[i] * self.gather_dot(e0, e1, b) + b[i] * self.gather_dot(e0, e1, a)
            };
            e0 = e1;
        }
        acc
    }

    /// `out[s * stride + off] += w Σ_k H^l_{s,k} x_k` for every `s` (row `l`).
    pub(crate) fn add_row_times(
        &self,
        l: usize,
        w: f64,
        x: &[f64],
        out: &mut [f64],
        stride: usize,
        off: usize,
    ) {
        assert!(x.len() >= self.n_phi, "gather_dot's unchecked reads");
        assert!(
            out.len() > (self.n_phi - 1) * stride + off,
            "scatter's unchecked writes"
        );
        let (r0, r1, mut e0) = self.row(l);
        for r in r0..r1 {
            let (i, e1) = (self.run_i[r] as usize, self.run_end[r] as usize);
            out[i * stride + off] += w * self.gather_dot(e0, e1, x);
            self.scatter(e0, e1, w * x[i], out, stride, off);
            e0 = e1;
        }
    }

    /// Fused `eta[l] = Σ_{ij} H^l_{ij} q_i q_j` and `grad = ∇_q Σ_l w_l eta_l²`
    /// (`= 4 Σ_l w_l eta_l Σ_k H^l_{s,k} q_k`), one row at a time so that each row is read
    /// from memory once: the run sums `S_r(q)` of the first pass are kept in `runs`
    /// (scratch, length ≥ the longest row's run count, see [`Self::max_runs`]).
    pub(crate) fn quartic_gradient(
        &self,
        q: &[f64],
        w: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        runs: &mut [f64],
    ) {
        assert!(q.len() >= self.n_phi, "gather_dot's unchecked reads");
        grad[..self.n_phi].fill(0.0);
        for (l, (el, &wl)) in eta.iter_mut().zip(w).enumerate() {
            let (r0, r1, e_start) = self.row(l);
            let mut e0 = e_start;
            let mut acc = 0.0;
            for (r, sr) in (r0..r1).zip(runs.iter_mut()) {
                let e1 = self.run_end[r] as usize;
                *sr = self.gather_dot(e0, e1, q);
                acc += q[self.run_i[r] as usize] * *sr;
                e0 = e1;
            }
            *el = 2.0 * acc;
            let k = 4.0 * wl * *el;
            if k == 0.0 {
                continue;
            }
            let mut e0 = e_start;
            for (r, &sr) in (r0..r1).zip(runs.iter()) {
                let (i, e1) = (self.run_i[r] as usize, self.run_end[r] as usize);
                grad[i] += k * sr;
                self.scatter(e0, e1, k * q[i], grad, 1, 0);
                e0 = e1;
            }
        }
    }

    /// Number of stored entries.
    pub(crate) fn len(&self) -> usize {
        self.half.len()
    }

    /// The largest number of runs in one row (scratch size of [`Self::quartic_gradient`]).
    pub(crate) fn max_runs(&self) -> usize {
        self.row_runs
            .windows(2)
            .map(|w| (w[1] - w[0]) as usize)
            .max()
            .unwrap_or(0)
    }
}
