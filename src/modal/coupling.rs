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
//! Threads: built once on a worker thread (allocates); the kernels take `&self` and
//! caller-owned slices, never allocate, and are meant for the audio thread.

use crate::error::ParamError;

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
        if nnz > u32::MAX as usize || n_phi > u32::MAX as usize {
            return Err(ParamError::new("coupling.nnz", nnz, "at most 2^32 - 1"));
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
        Ok(Self {
            n_phi,
            n_psi,
            row_start,
            i,
            j,
            value,
        })
    }

    /// Number of transverse modes `N_Φ`.
    pub fn n_phi(&self) -> usize {
        self.n_phi
    }

    /// Number of in-plane modes `N_Ψ`.
    pub fn n_psi(&self) -> usize {
        self.n_psi
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
    /// audio thread. Panics on wrong lengths (a programming error).
    pub fn contract_eta(&self, q_a: &[f64], q_b: &[f64], out: &mut [f64]) {
        assert_eq!(q_a.len(), self.n_phi, "contract_eta: q_a length");
        assert_eq!(q_b.len(), self.n_phi, "contract_eta: q_b length");
        assert_eq!(out.len(), self.n_psi, "contract_eta: out length");
        for (l, o) in out.iter_mut().enumerate() {
            let (ri, rj, rv) = self.row(l);
            let mut acc = 0.0;
            for ((&i, &j), &v) in ri.iter().zip(rj).zip(rv) {
                let (i, j) = (i as usize, j as usize);
                let s = q_a[i] * q_b[j] + q_a[j] * q_b[i];
                acc += v * if i == j { 0.5 * s } else { s };
            }
            *o = acc;
        }
    }

    /// `out[s] = Σ_k Σ_l E^s_{k,l} q[k] η[l] = Σ_l η[l] Σ_k H^l_{s,k} q[k]` for every `s`
    /// (uses `E^s_{k,l} = H^l_{s,k}`, valid for in-plane modes with `Ψ = ∂Ψ/∂n = 0` on the
    /// edge; see the module docs). Slices: `q` of length `N_Φ`, `eta` of length `N_Ψ`, `out` of
    /// length `N_Φ` (overwritten). Allocation-free, audio thread. Panics on wrong lengths.
    pub fn apply_force(&self, q: &[f64], eta: &[f64], out: &mut [f64]) {
        assert_eq!(q.len(), self.n_phi, "apply_force: q length");
        assert_eq!(eta.len(), self.n_psi, "apply_force: eta length");
        assert_eq!(out.len(), self.n_phi, "apply_force: out length");
        out.fill(0.0);
        for (l, &e) in eta.iter().enumerate() {
            if e == 0.0 {
                continue;
            }
            let (ri, rj, rv) = self.row(l);
            for ((&i, &j), &v) in ri.iter().zip(rj).zip(rv) {
                let (i, j) = (i as usize, j as usize);
                let ev = e * v;
                out[i] += ev * q[j];
                if i != j {
                    out[j] += ev * q[i];
                }
            }
        }
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
