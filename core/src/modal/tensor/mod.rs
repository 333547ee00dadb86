//! Geometry-independent storage of the von Kármán coupling tensor
//! `H^l_{ij} = ∫_S Ψ_l L(Φ_i, Φ_j) dS` and the kernels the time stepper streams through.
//!
//! Layout: one row per in-plane mode `l`; row `l` holds the nonzero entries with `j ≤ i`
//! (the tensor is symmetric in `i, j`), sorted by `(i, j)`, in struct-of-arrays form
//! (`row_start`, `i`, `j`, `value`), like a CSR matrix. Entries that vanish by a selection
//! rule are absent, never stored as zeros computed by quadrature.
//!
//! The second tensor of the projected equations, `E^s_{i,j} = ∫_S Φ_s L(Φ_i, Ψ_j) dS`, is not
//! stored: when every `Ψ_j` satisfies `Ψ_j = ∂Ψ_j/∂n = 0` on the edge, `E^s_{i,j} = H^j_{s,i}`
//! (integrate by parts twice, using the divergence form
//! `L(g, h) = ∂x(g_x h_yy - g_y h_xy) + ∂y(g_y h_xx - g_x h_xy)`: the bulk term is symmetric in
//! the three functions and every boundary term carries `Ψ` or `∇Ψ`; O. Thomas & S. Bilbao,
//! "Geometrically nonlinear flexural vibrations of plates: in-plane boundary conditions and
//! some symmetry properties", JSV 315, 2008, §3). [`CouplingTensor::apply_force`] uses it.
//!
//! Submodules: `blocks.rs` (the dense selection-rule blocks the time schemes stream, with the
//! dot helpers), `blocks_kernels.rs` (their SIMD/FMA kernels with caller-owned scratch),
//! `panels.rs` (the `f32` row panels of single storage), `runs.rs` (the run layout, kept as
//! the reference implementation the tests compare with), `storage.rs`
//! ([`CouplingTensor::with_storage`], single storage).
//!
//! Threads: built once on a worker thread (allocates); the kernels take `&self` and
//! caller-owned slices, never allocate, and are meant for the audio thread.

mod blocks;
mod runs;
mod storage;
mod truncate;

use crate::error::ParamError;
use blocks::{BlockLayout, PAD};
use runs::{vec_bytes, RunLayout, MAX_N_PHI};
use serde::{Deserialize, Serialize};

/// How a [`CouplingTensor`] stores its values (scene field `plate.tensor_storage`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum TensorStorage {
    /// `f64` values as computed (the default; the reference kernels).
    #[default]
    Double,
    /// Values rounded to `f32` once, every layout rebuilt from the rounded values; the block
    /// kernels read `f32` and accumulate in `f64` (see the module docs).
    Single,
}

impl TensorStorage {
    /// The storage's name in scenes and reports (`double`, `single`).
    pub fn name(self) -> &'static str {
        match self {
            TensorStorage::Double => "double",
            TensorStorage::Single => "single",
        }
    }
}

/// Sparse symmetric coupling tensor `H^l_{ij}` (dimensionless for the unit-radius plate with
/// unit-norm modes).
///
/// Built on a worker thread; read-only afterwards and shared with the audio thread.
#[derive(Debug, Clone, PartialEq)]
pub struct CouplingTensor {
    /// Number of transverse modes `N_Φ` (range of `i`, `j`).
    n_phi: usize,
    /// Number of in-plane modes `N_Ψ` (number of rows `l`).
    n_psi: usize,
    /// Row `l` occupies positions `row_start[l]..row_start[l + 1]`; length `N_Ψ + 1`.
    row_start: Vec<u32>,
    /// First transverse index of each entry (`i ≥ j`).
    i: Vec<u32>,
    /// Second transverse index of each entry (`j ≤ i`).
    j: Vec<u32>,
    /// `H^l_{ij}` of each entry.
    value: Vec<f64>,
    /// The same entries in the kernels' run layout (built from the arrays above).
    runs: RunLayout,
    /// The same entries as dense selection-rule blocks (the fused SAV kernel).
    blocks: BlockLayout,
    /// How the values are stored (every layout above holds the same numbers).
    storage: TensorStorage,
}

impl CouplingTensor {
    /// Builds a tensor from its flat arrays, checking every invariant: `row_start` has length
    /// `n_psi + 1`, starts at 0, is non-decreasing and ends at the entry count; the three entry
    /// arrays have equal lengths; `j ≤ i < n_phi`; each row is strictly increasing in `(i, j)`;
    /// every value is finite. Errors name the offending array and position.
    pub fn from_parts(
        n_phi: usize,
        n_psi: usize,
        row_start: Vec<u32>,
        i: Vec<u32>,
        j: Vec<u32>,
        value: Vec<f64>,
    ) -> Result<Self, ParamError> {
        let nnz = value.len();
        if i.len() != nnz || j.len() != nnz {
            return Err(ParamError::new(
                "coupling.i/j",
                format!("lengths {} and {}", i.len(), j.len()),
                format!("both equal to value.len() = {nnz}"),
            ));
        }
        if nnz > u32::MAX as usize {
            return Err(ParamError::new("coupling.nnz", nnz, "at most 2^32 - 1"));
        }
        if n_phi > MAX_N_PHI {
            return Err(ParamError::new(
                "coupling.n_phi",
                n_phi,
                format!("at most {MAX_N_PHI} (16-bit mode indices in the kernels)"),
            ));
        }
        if row_start.len() != n_psi + 1 || row_start[0] != 0 || row_start[n_psi] as usize != nnz {
            return Err(ParamError::new(
                "coupling.row_start",
                format!("length {}", row_start.len()),
                format!("length {} starting at 0 and ending at {nnz}", n_psi + 1),
            ));
        }
        for l in 0..n_psi {
            let (a, b) = (row_start[l] as usize, row_start[l + 1] as usize);
            if a > b {
                return Err(ParamError::new(
                    format!("coupling.row_start[{l}]"),
                    a,
                    format!("<= row_start[{}] = {b}", l + 1),
                ));
            }
            for e in a..b {
                let (ie, je) = (i[e] as usize, j[e] as usize);
                if ie >= n_phi || je > ie {
                    return Err(ParamError::new(
                        format!("coupling entry {e} (i, j)"),
                        format!("({ie}, {je})"),
                        format!("j <= i < {n_phi}"),
                    ));
                }
                if e > a && (i[e - 1], j[e - 1]) >= (i[e], j[e]) {
                    return Err(ParamError::new(
                        format!("coupling entry {e} of row {l}"),
                        format!("({ie}, {je})"),
                        "strictly increasing (i, j) within a row",
                    ));
                }
                if !value[e].is_finite() {
                    return Err(ParamError::new(
                        format!("coupling.value[{e}]"),
                        value[e],
                        "finite number",
                    ));
                }
            }
        }
        Ok(Self::assemble(
            n_phi,
            n_psi,
            row_start,
            i,
            j,
            value,
            TensorStorage::Double,
        ))
    }

    /// The tensor of validated parts, its run and block layouts built from the same `value`
    /// (already rounded to `f32` for [`TensorStorage::Single`]). Worker thread.
    fn assemble(
        n_phi: usize,
        n_psi: usize,
        row_start: Vec<u32>,
        i: Vec<u32>,
        j: Vec<u32>,
        value: Vec<f64>,
        storage: TensorStorage,
    ) -> Self {
        let runs = RunLayout::new(n_phi, &row_start, &i, &j, &value);
        let single = storage == TensorStorage::Single;
        let blocks = BlockLayout::new(n_phi, &row_start, &i, &j, &value, single);
        Self {
            runs,
            blocks,
            n_phi,
            n_psi,
            row_start,
            i,
            j,
            value,
            storage,
        }
    }

    /// Number of transverse modes `N_Φ`.
    pub fn n_phi(&self) -> usize {
        self.n_phi
    }

    /// Number of in-plane modes `N_Ψ`.
    pub fn n_psi(&self) -> usize {
        self.n_psi
    }

    /// Heap bytes the tensor holds: its entry arrays and both kernel layouts (the vectors'
    /// capacities). Any thread.
    pub fn heap_bytes(&self) -> usize {
        vec_bytes(&self.row_start)
            + vec_bytes(&self.i)
            + vec_bytes(&self.j)
            + vec_bytes(&self.value)
            + self.runs.heap_bytes()
            + self.blocks.heap_bytes()
    }

    /// Number of stored entries (nonzero `H^l_{ij}` with `j ≤ i`).
    pub fn nnz(&self) -> usize {
        self.value.len()
    }

    /// The flat arrays `(row_start, i, j, value)` (for serialisation and inspection).
    pub fn parts(&self) -> (&[u32], &[u32], &[u32], &[f64]) {
        (&self.row_start, &self.i, &self.j, &self.value)
    }

    /// Entries of row `l`: `(i, j, value)` slices with `j ≤ i`, sorted by `(i, j)`.
    pub fn row(&self, l: usize) -> (&[u32], &[u32], &[f64]) {
        let (a, b) = (self.row_start[l] as usize, self.row_start[l + 1] as usize);
        (&self.i[a..b], &self.j[a..b], &self.value[a..b])
    }

    /// Stored value `H^l_{ij}` (either order of `i, j`), or `None` when the entry is absent
    /// (an exact zero by selection rule). Binary search; no allocation.
    pub fn get(&self, l: usize, i: usize, j: usize) -> Option<f64> {
        let (a, b) = if i >= j { (i, j) } else { (j, i) };
        let (ri, rj, rv) = self.row(l);
        let key = (a as u32, b as u32);
        let mut lo = 0usize;
        let mut hi = ri.len();
        while lo < hi {
            let mid = (lo + hi) / 2;
            match (ri[mid], rj[mid]).cmp(&key) {
                std::cmp::Ordering::Less => lo = mid + 1,
                std::cmp::Ordering::Greater => hi = mid,
                std::cmp::Ordering::Equal => return Some(rv[mid]),
            }
        }
        None
    }

    /// `out[l] = Σ_{i,j} H^l_{ij} q_a[i] q_b[j]` for every `l` (the full double sum, evaluated
    /// from the `j ≤ i` half as `H (q_a[i] q_b[j] + q_a[j] q_b[i])` off the diagonal). Slices:
    /// `q_a`, `q_b` of length `N_Φ`, `out` of length `N_Ψ` (overwritten). Allocation-free,
    /// audio thread. Panics on wrong lengths (a programming error). Run layout: the reference
    /// of [`Self::contract_eta_with_scratch`], which the plate schemes use.
    pub fn contract_eta(&self, q_a: &[f64], q_b: &[f64], out: &mut [f64]) {
        assert_eq!(q_a.len(), self.n_phi, "contract_eta: q_a length");
        assert_eq!(q_b.len(), self.n_phi, "contract_eta: q_b length");
        assert_eq!(out.len(), self.n_psi, "contract_eta: out length");
        for (l, o) in out.iter_mut().enumerate() {
            *o = self.runs.contract_row(l, q_a, q_b);
        }
    }

    /// `out[s] = Σ_k Σ_l E^s_{k,l} q[k] η[l] = Σ_l η[l] Σ_k H^l_{s,k} q[k]` for every `s`
    /// (uses `E^s_{k,l} = H^l_{s,k}`, valid for in-plane modes with `Ψ = ∂Ψ/∂n = 0` on the
    /// edge; see the module docs). Slices: `q` of length `N_Φ`, `eta` of length `N_Ψ`, `out` of
    /// length `N_Φ` (overwritten). Allocation-free, audio thread. Panics on wrong lengths.
    /// Run layout: the reference of [`Self::apply_force_with_scratch`].
    pub fn apply_force(&self, q: &[f64], eta: &[f64], out: &mut [f64]) {
        assert_eq!(q.len(), self.n_phi, "apply_force: q length");
        assert_eq!(eta.len(), self.n_psi, "apply_force: eta length");
        assert_eq!(out.len(), self.n_phi, "apply_force: out length");
        out.fill(0.0);
        for (l, &e) in eta.iter().enumerate() {
            if e != 0.0 {
                self.runs.add_row_times(l, e, q, out, 1, 0);
            }
        }
    }
}

impl CouplingTensor {
    /// `g[s * N_Ψ + l] = Σ_k H^l_{s,k} q_k` (row-major `N_Φ × N_Ψ`, overwritten): the coupling
    /// matrix of the linearly implicit plate schemes. Allocation-free, audio thread. Panics on
    /// wrong lengths. Run layout: the reference of [`Self::coupling_matrix_with_scratch`].
    pub fn coupling_matrix(&self, q: &[f64], g: &mut [f64]) {
        assert_eq!(q.len(), self.n_phi, "coupling_matrix: q length");
        assert_eq!(
            g.len(),
            self.n_phi * self.n_psi,
            "coupling_matrix: g length"
        );
        g.fill(0.0);
        for l in 0..self.n_psi {
            self.runs.add_row_times(l, 1.0, q, g, self.n_psi, l);
        }
    }

    /// Fused `eta[l] = Σ_{ij} H^l_{ij} q_i q_j` and `grad[s] = ∂/∂q_s Σ_l w_l eta_l²
    /// = 4 Σ_l w_l eta_l Σ_k H^l_{s,k} q_k`, reading each row of the tensor from memory once
    /// (the gradient of a non-negative quartic potential when `w ≥ 0`). Slices: `q`, `grad` of
    /// length `N_Φ`, `scratch` of length at least [`Self::quartic_scratch_len`]; `w`, `eta` of length `N_Ψ` (`eta`,
    /// `grad` overwritten). Streams the dense selection-rule blocks of `tensor/blocks.rs`.
    /// Allocation-free, audio thread. Panics on wrong lengths.
    pub fn quartic_gradient(
        &self,
        q: &[f64],
        w: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) {
        self.quartic_gradient_rows(0..self.n_psi, q, w, eta, grad, scratch);
    }

    /// [`Self::quartic_gradient`] over the rows `rows` only: `eta` of length `rows.len()` gets
    /// `eta[l - rows.start]`, `grad` (length `N_Φ`) the part `4 Σ_{l ∈ rows} w_l eta_l H^l q`
    /// of the gradient. Two threads can run two disjoint row ranges of one step at once, each
    /// with its own `grad` and `scratch` (see [`Self::split_row`]). Allocation-free, audio
    /// thread or a worker sharing its step. Panics on wrong lengths or a range past `N_Ψ`.
    pub fn quartic_gradient_rows(
        &self,
        rows: std::ops::Range<usize>,
        q: &[f64],
        w: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) {
        self.quartic_rows_checked(rows, q, w, None, eta, grad, scratch);
    }

    /// [`Self::quartic_gradient_rows`] of the shifted quartic `Σ_l w_l (eta_l - c_l)²`, whose
    /// gradient is `4 Σ_{l ∈ rows} w_l (eta_l - c_l) H^l q` (`eta` is still the unshifted
    /// `Σ_{ij} H^l_{ij} q_i q_j`). With `q = r = q + a` and `c_l = Ĥ(a, a)_l` it is the
    /// potential of a plate with the rest shape `a` (`models/plate/model/rest_shape.rs`), in the
    /// same single pass over the tensor as the flat plate's. `shift` of length `N_Ψ`; otherwise
    /// as [`Self::quartic_gradient_rows`]. Allocation-free, audio thread or a worker sharing
    /// its step.
    #[allow(clippy::too_many_arguments)]
    pub fn quartic_gradient_rows_shifted(
        &self,
        rows: std::ops::Range<usize>,
        q: &[f64],
        w: &[f64],
        shift: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) {
        assert_eq!(
            shift.len(),
            self.n_psi,
            "quartic_gradient_rows: shift length"
        );
        self.quartic_rows_checked(rows, q, w, Some(shift), eta, grad, scratch);
    }

    /// The length checks of [`Self::quartic_gradient_rows`] (and its shifted form), then the
    /// block kernel with the offsets `shift` (`None`: 0).
    #[allow(clippy::too_many_arguments)]
    fn quartic_rows_checked(
        &self,
        rows: std::ops::Range<usize>,
        q: &[f64],
        w: &[f64],
        shift: Option<&[f64]>,
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) {
        assert!(
            rows.start <= rows.end && rows.end <= self.n_psi,
            "quartic_gradient_rows: rows"
        );
        assert_eq!(q.len(), self.n_phi, "quartic_gradient_rows: q length");
        assert_eq!(grad.len(), self.n_phi, "quartic_gradient_rows: grad length");
        assert!(
            scratch.len() >= self.quartic_scratch_len(),
            "quartic_gradient_rows: scratch length"
        );
        assert_eq!(w.len(), self.n_psi, "quartic_gradient_rows: w length");
        assert_eq!(eta.len(), rows.len(), "quartic_gradient_rows: eta length");
        self.blocks
            .quartic_gradient_rows(rows, q, w, shift, eta, grad, scratch);
    }

    /// The row `m` that splits the tensor's stored entries most evenly into rows `0..m` and
    /// `m..N_Ψ` (the work of [`Self::quartic_gradient_rows`] is proportional to the entries).
    pub fn split_row(&self) -> usize {
        let half = self.value.len() as u64;
        (0..=self.n_psi)
            .min_by_key(|&m| (2 * u64::from(self.row_start[m])).abs_diff(half))
            .unwrap_or(0)
    }

    /// Scratch length [`Self::quartic_gradient`] needs: `3 N_Φ + 8` (permuted `q`, `H^l q` and
    /// gradient, plus the zero padding of the 4-lane block kernel).
    pub fn quartic_scratch_len(&self) -> usize {
        3 * self.n_phi + 2 * PAD
    }

    /// The run-layout version of [`Self::quartic_gradient`] (gathers and scatters through
    /// 16-bit indices; `scratch` of length at least `N_Φ`), kept as the reference the block
    /// kernel is tested and benchmarked against. Allocation-free, audio thread.
    pub fn quartic_gradient_runs(
        &self,
        q: &[f64],
        w: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) {
        assert_eq!(q.len(), self.n_phi, "quartic_gradient: q length");
        assert_eq!(grad.len(), self.n_phi, "quartic_gradient: grad length");
        assert!(
            scratch.len() >= self.runs.max_runs(),
            "quartic_gradient: scratch"
        );
        assert_eq!(w.len(), self.n_psi, "quartic_gradient: w length");
        assert_eq!(eta.len(), self.n_psi, "quartic_gradient: eta length");
        self.runs.quartic_gradient(q, w, eta, grad, scratch);
    }

    /// Scratch length of the block kernels [`Self::contract_eta_with_scratch`],
    /// [`Self::apply_force_with_scratch`] and [`Self::coupling_matrix_with_scratch`]: the same
    /// `3 N_Φ + 8` as [`Self::quartic_scratch_len`] (permuted input, `H^l q`, one more `N_Φ`
    /// vector, zero padding). Allocate it once on the worker thread.
    pub fn kernel_scratch_len(&self) -> usize {
        self.quartic_scratch_len()
    }

    /// [`Self::contract_eta`] streamed from the dense selection-rule blocks (same result up to
    /// summation order); `scratch` of length at least [`Self::kernel_scratch_len`].
    /// Allocation-free, audio thread. Panics on wrong lengths.
    pub fn contract_eta_with_scratch(
        &self,
        q_a: &[f64],
        q_b: &[f64],
        out: &mut [f64],
        scratch: &mut [f64],
    ) {
        assert_eq!(q_a.len(), self.n_phi, "contract_eta: q_a length");
        assert_eq!(q_b.len(), self.n_phi, "contract_eta: q_b length");
        assert_eq!(out.len(), self.n_psi, "contract_eta: out length");
        assert!(
            scratch.len() >= self.kernel_scratch_len(),
            "contract_eta: scratch"
        );
        self.blocks.contract_eta(q_a, q_b, out, scratch);
    }

    /// [`Self::apply_force`] streamed from the dense selection-rule blocks; `scratch` of
    /// length at least [`Self::kernel_scratch_len`]. Allocation-free, audio thread. Panics on
    /// wrong lengths.
    pub fn apply_force_with_scratch(
        &self,
        q: &[f64],
        eta: &[f64],
        out: &mut [f64],
        scratch: &mut [f64],
    ) {
        assert_eq!(q.len(), self.n_phi, "apply_force: q length");
        assert_eq!(eta.len(), self.n_psi, "apply_force: eta length");
        assert_eq!(out.len(), self.n_phi, "apply_force: out length");
        assert!(
            scratch.len() >= self.kernel_scratch_len(),
            "apply_force: scratch"
        );
        self.blocks.apply_force(q, eta, out, scratch);
    }

    /// [`Self::coupling_matrix`] streamed from the dense selection-rule blocks; `scratch` of
    /// length at least [`Self::kernel_scratch_len`]. Allocation-free, audio thread. Panics on
    /// wrong lengths.
    pub fn coupling_matrix_with_scratch(&self, q: &[f64], g: &mut [f64], scratch: &mut [f64]) {
        assert_eq!(q.len(), self.n_phi, "coupling_matrix: q length");
        assert_eq!(
            g.len(),
            self.n_phi * self.n_psi,
            "coupling_matrix: g length"
        );
        assert!(
            scratch.len() >= self.kernel_scratch_len(),
            "coupling_matrix: scratch"
        );
        self.blocks.coupling_matrix(q, g, scratch);
    }

    /// Layout statistics of the block kernel: `(classes, dense blocks, stored dense values
    /// including zero padding, entries left in the gathered remainder)`.
    pub fn block_stats(&self) -> (usize, usize, usize, usize) {
        self.blocks.stats()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> CouplingTensor {
        // Two rows over three modes; row 0: H_00 = 2, H_21 = -1; row 1: H_10 = 0.5.
        CouplingTensor::from_parts(
            3,
            2,
            vec![0, 2, 3],
            vec![0, 2, 1],
            vec![0, 1, 0],
            vec![2.0, -1.0, 0.5],
        )
        .unwrap()
    }

    #[test]
    fn kernels_match_dense_sums() {
        // Exact small-integer arithmetic: results compared with dense double sums to 1e-15.
        let t = small();
        let mut dense = [[[0.0; 3]; 3]; 2];
        for (l, d) in dense.iter_mut().enumerate() {
            for (i, row) in d.iter_mut().enumerate() {
                for (j, x) in row.iter_mut().enumerate() {
                    *x = t.get(l, i, j).unwrap_or(0.0);
                }
            }
        }
        let qa = [0.3, -1.2, 2.0];
        let qb = [1.1, 0.4, -0.7];
        let mut eta = [0.0; 2];
        t.contract_eta(&qa, &qb, &mut eta);
        for l in 0..2 {
            let mut s = 0.0;
            for i in 0..3 {
                for j in 0..3 {
                    s += dense[l][i][j] * qa[i] * qb[j];
                }
            }
            assert!((eta[l] - s).abs() < 1e-15, "{l}: {} vs {s}", eta[l]);
        }
        let e = [0.7, -2.0];
        let mut f = [0.0; 3];
        t.apply_force(&qa, &e, &mut f);
        for s in 0..3 {
            let mut acc = 0.0;
            for k in 0..3 {
                for (l, el) in e.iter().enumerate() {
                    acc += dense[l][s][k] * qa[k] * el;
                }
            }
            assert!((f[s] - acc).abs() < 1e-15);
        }
        assert_eq!(t.get(0, 1, 2), Some(-1.0));
        assert_eq!(t.get(1, 2, 2), None);
    }

    /// A random sparse tensor (about a third of the `j ≤ i` entries, diagonal included) and
    /// deterministic vectors: the run-layout kernels against direct sums over the CSR entries,
    /// to 1e-13 of the sum of absolute terms (reordered floating-point sums of ~300 terms).
    #[test]
    fn run_kernels_match_direct_sums() {
        let (nf, np) = (37, 5);
        let mut seed = 99u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut rs, mut ri, mut rj, mut rv) = (vec![0u32], vec![], vec![], vec![]);
        for _ in 0..np {
            for i in 0..nf {
                for j in 0..=i {
                    if rnd() < 0.33 {
                        ri.push(i as u32);
                        rj.push(j as u32);
                        rv.push(rnd() - 0.5);
                    }
                }
            }
            rs.push(rv.len() as u32);
        }
        let t = CouplingTensor::from_parts(nf, np, rs, ri, rj, rv).unwrap();
        let qa: Vec<f64> = (0..nf).map(|_| rnd() - 0.5).collect();
        let qb: Vec<f64> = (0..nf).map(|_| rnd() - 0.5).collect();
        let w: Vec<f64> = (0..np).map(|_| rnd()).collect();
        // Direct sums from the CSR entries: H^l_{ij} for both orders of (i, j).
        let full = |l: usize, i: usize, j: usize| t.get(l, i, j).unwrap_or(0.0);
        let close = |got: f64, want: f64, scale: f64| {
            assert!((got - want).abs() <= 1e-13 * scale, "{got} vs {want}");
        };
        let mut eta = vec![0.0; np];
        let mut eta_sym = vec![0.0; np];
        t.contract_eta(&qa, &qb, &mut eta);
        t.contract_eta(&qa, &qa, &mut eta_sym);
        for l in 0..np {
            let (mut want, mut want_sym, mut scale) = (0.0, 0.0, 0.0);
            for i in 0..nf {
                for j in 0..nf {
                    want += full(l, i, j) * qa[i] * qb[j];
                    want_sym += full(l, i, j) * qa[i] * qa[j];
                    scale += (full(l, i, j) * qa[i] * qb[j]).abs();
                }
            }
            close(eta[l], want, scale);
            close(eta_sym[l], want_sym, scale);
        }
        let mut f = vec![0.0; nf];
        let mut g = vec![0.0; nf * np];
        t.apply_force(&qa, &w, &mut f);
        t.coupling_matrix(&qa, &mut g);
        let (mut eta_q, mut grad, mut scratch) = (
            vec![0.0; np],
            vec![0.0; nf],
            vec![0.0; t.quartic_scratch_len()],
        );
        t.quartic_gradient(&qa, &w, &mut eta_q, &mut grad, &mut scratch);
        for s in 0..nf {
            let (mut want_f, mut want_grad, mut scale) = (0.0, 0.0, 0.0);
            for l in 0..np {
                let gsl: f64 = (0..nf).map(|k| full(l, s, k) * qa[k]).sum();
                let gabs: f64 = (0..nf).map(|k| (full(l, s, k) * qa[k]).abs()).sum();
                close(g[s * np + l], gsl, gabs);
                want_f += w[l] * gsl;
                want_grad += 4.0 * w[l] * eta_sym[l] * gsl;
                scale += 4.0 * (w[l] * eta_sym[l]).abs() * gabs + w[l] * gabs;
            }
            close(f[s], want_f, scale);
            close(grad[s], want_grad, scale);
        }
        for l in 0..np {
            // Block kernel (q·H^l q) against the run kernel: reordered sums, 1e-13 of Σ|terms|.
            let scale: f64 = (0..nf)
                .flat_map(|i| (0..nf).map(move |j| (i, j)))
                .map(|(i, j)| (full(l, i, j) * qa[i] * qa[j]).abs())
                .sum();
            close(eta_q[l], eta_sym[l], scale);
        }
    }

    #[test]
    fn rejects_broken_layouts() {
        let bad_j = CouplingTensor::from_parts(3, 1, vec![0, 1], vec![0], vec![1], vec![1.0]);
        assert!(bad_j.unwrap_err().to_string().contains("j <= i"));
        let unsorted =
            CouplingTensor::from_parts(3, 1, vec![0, 2], vec![2, 1], vec![0, 0], vec![1.0, 1.0]);
        assert!(unsorted.is_err());
        let bad_rows = CouplingTensor::from_parts(3, 2, vec![0, 1], vec![0], vec![0], vec![1.0]);
        assert!(bad_rows.is_err());
        let nan = CouplingTensor::from_parts(3, 1, vec![0, 1], vec![0], vec![0], vec![f64::NAN]);
        assert!(nan.is_err());
    }
}
