//! The nonlinear coupling tensor of the modal von Kármán plate, seen through the three
//! contractions the time schemes need, and a dense reference implementation.
//!
//! SEED.md section 3.1 (Ducceschi & Touzé, JSV 344, 2015, eqs. (10)-(12)): with transverse modes
//! `Φ_i` and in-plane (Airy) modes `Ψ_l`,
//! `H^l_{i,j} = ∫_S Ψ_l L(Φ_i, Φ_j) dS` and `E^s_{k,l} = ∫_S Φ_s L(Φ_k, Ψ_l) dS`. Because
//! `L(·,·)` is symmetric and, for the boundary conditions of SEED 3.1
//! (`Ψ = ∂Ψ/∂n = 0` on the edge), `∫ Φ_s L(Φ_k, Ψ_l) = ∫ Ψ_l L(Φ_s, Φ_k)`, one tensor serves
//! both: `E^s_{k,l} = H^l_{s,k}`, symmetric in its two lower indices. The model never needs the
//! tensor itself, only:
//!
//! - `η`-contraction: `out[l] = Σ_{i,j} H^l_{i,j} qa_i qb_j` (the in-plane amplitudes up to a
//!   factor `-Eh/(2ζ_l⁴)`);
//! - force application: `out[s] = Σ_{k,l} H^l_{s,k} q_k w_l` (`= Σ E^s_{k,l} q_k w_l`);
//! - the coupling matrix `G_{s,l} = Σ_k H^l_{s,k} q_k` (N_Φ × N_Ψ, row-major) that turns the
//!   conservative scheme into one linear solve per step.
//!
//! The tensor given here is the one the model multiplies by `coupling_scale` (see
//! [`super::PlateParams::coupling_scale`]), so it may be dimensionless.
//!
//! Threads: a coupling is built once on a worker thread and then shared read-only (`Arc`) with
//! the audio thread, which calls the kernels; kernels never allocate and run in bounded time.

use super::linalg::dot;
use crate::error::ParamError;

/// The coupling tensor `H^l_{i,j}` (symmetric in `i, j`) of a modal von Kármán plate, as the
/// contractions the time schemes use.
///
/// Implementations: [`DenseCoupling`] here; sparse ones (Bessel-mode data) live elsewhere.
/// Every kernel is called on the audio thread: it must not allocate, lock or block, and must
/// overwrite (not accumulate into) `out`/`g`.
pub trait ModalCoupling: Send + Sync {
    /// Number of transverse modes `N_Φ` (indices `i, j, k, s`).
    fn n_phi(&self) -> usize;
    /// Number of in-plane modes `N_Ψ` (index `l`).
    fn n_psi(&self) -> usize;
    /// `out[l] = Σ_{i,j} H^l_{i,j} qa_i qb_j` for every `l` (`qa`, `qb` of length `N_Φ`, `out`
    /// of length `N_Ψ`). Symmetric in `qa` and `qb`.
    fn contract_eta(&self, qa: &[f64], qb: &[f64], out: &mut [f64]);
    /// `out[s] = Σ_k Σ_l H^l_{s,k} q_k w_l` for every `s` (`q`, `out` of length `N_Φ`, `w` of
    /// length `N_Ψ`): the modal force `Σ_{k,l} E^s_{k,l} q_k w_l`.
    fn apply_force(&self, q: &[f64], w: &[f64], out: &mut [f64]);
    /// Fills the dense row-major `N_Φ × N_Ψ` matrix `g[s * N_Ψ + l] = Σ_k H^l_{s,k} q_k`.
    fn coupling_matrix(&self, q: &[f64], g: &mut [f64]);
    /// Scratch length (values) the `_with_scratch` kernels need; 0 (the default) when they
    /// need none. The model allocates it once at build (worker thread).
    fn kernel_scratch_len(&self) -> usize {
        0
    }
    /// [`Self::contract_eta`] with caller-owned `scratch` of length at least
    /// [`Self::kernel_scratch_len`] (the default ignores it). Audio thread, allocation-free.
    fn contract_eta_with_scratch(
        &self,
        qa: &[f64],
        qb: &[f64],
        out: &mut [f64],
        _scratch: &mut [f64],
    ) {
        self.contract_eta(qa, qb, out);
    }
    /// [`Self::apply_force`] with caller-owned `scratch` (as above).
    fn apply_force_with_scratch(
        &self,
        q: &[f64],
        w: &[f64],
        out: &mut [f64],
        _scratch: &mut [f64],
    ) {
        self.apply_force(q, w, out);
    }
    /// [`Self::coupling_matrix`] with caller-owned `scratch` (as above).
    fn coupling_matrix_with_scratch(&self, q: &[f64], g: &mut [f64], _scratch: &mut [f64]) {
        self.coupling_matrix(q, g);
    }
    /// Optional fused kernel: `eta[l] = Σ_{i,j} H^l_{i,j} q_i q_j` and
    /// `grad[s] = ∂/∂q_s Σ_l w_l eta_l² = 4 Σ_l w_l eta_l Σ_k H^l_{s,k} q_k`, with `scratch` of
    /// length at least `3 N_Φ + 8`. Returns `false` without writing anything when the implementation has no
    /// fused kernel (callers then use `contract_eta` and `apply_force`). The default runs
    /// [`Self::quartic_gradient_rows`] over every row.
    fn quartic_gradient(
        &self,
        q: &[f64],
        w: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) -> bool {
        self.quartic_gradient_rows(0..self.n_psi(), q, w, eta, grad, scratch)
    }
    /// Optional: [`Self::quartic_gradient`] over the in-plane rows `rows` only (`eta` of length
    /// `rows.len()`, `grad` the part of the gradient from those rows), so that two threads can
    /// share one step. Returns `false` without writing anything when the implementation has
    /// none (the default).
    fn quartic_gradient_rows(
        &self,
        _rows: std::ops::Range<usize>,
        _q: &[f64],
        _w: &[f64],
        _eta: &mut [f64],
        _grad: &mut [f64],
        _scratch: &mut [f64],
    ) -> bool {
        false
    }
    /// Optional: [`Self::quartic_gradient_rows`] of the shifted quartic
    /// `Σ_l w_l (eta_l - c_l)²` (`c = shift`, length `N_Ψ`): `grad` gets
    /// `4 Σ_{l ∈ rows} w_l (eta_l - c_l) Σ_k H^l_{s,k} q_k`, `eta` the unshifted contraction.
    /// A curved plate's potential at `q = r = q + a` with `c_l = Ĥ(a, a)_l`. Returns `false`
    /// without writing anything when the implementation has none (the default).
    #[allow(clippy::too_many_arguments)]
    fn quartic_gradient_shifted_rows(
        &self,
        _rows: std::ops::Range<usize>,
        _q: &[f64],
        _w: &[f64],
        _shift: &[f64],
        _eta: &mut [f64],
        _grad: &mut [f64],
        _scratch: &mut [f64],
    ) -> bool {
        false
    }
    /// The in-plane row that splits [`Self::quartic_gradient_rows`]'s work in two halves
    /// (default `N_Ψ / 2`).
    fn split_row(&self) -> usize {
        self.n_psi() / 2
    }
}

/// A dense coupling tensor stored as `N_Ψ × N_Φ × N_Φ` (`H^l_{i,j}` at
/// `(l * N_Φ + i) * N_Φ + j`), for tests, benchmarks and small plates.
///
/// Built on a worker thread; read-only afterwards (shared with the audio thread).
#[derive(Debug, Clone, PartialEq)]
pub struct DenseCoupling {
    n_phi: usize,
    n_psi: usize,
    h: Vec<f64>,
}

impl DenseCoupling {
    /// Wraps a dense tensor, `data[(l * n_phi + i) * n_phi + j] = H^l_{i,j}` (units: those the
    /// caller's `coupling_scale` expects, for example dimensionless).
    ///
    /// Errors: `n_phi` must be ≥ 1, `data.len()` must be `n_psi * n_phi²`, every entry finite,
    /// and `H^l_{i,j} = H^l_{j,i}` (to 1e-12 of the largest entry).
    pub fn new(n_phi: usize, n_psi: usize, data: Vec<f64>) -> Result<Self, ParamError> {
        if n_phi == 0 {
            return Err(ParamError::new("coupling.n_phi", n_phi, "integer >= 1"));
        }
        let expected = n_psi * n_phi * n_phi;
        if data.len() != expected {
            return Err(ParamError::new(
                "coupling.data.len",
                data.len(),
                format!("n_psi * n_phi^2 = {expected}"),
            ));
        }
        if let Some(bad) = data.iter().position(|x| !x.is_finite()) {
            return Err(ParamError::new(
                format!("coupling.data[{bad}]"),
                data[bad],
                "finite number",
            ));
        }
        let scale = data.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for l in 0..n_psi {
            for i in 0..n_phi {
                for j in 0..i {
                    let a = data[(l * n_phi + i) * n_phi + j];
                    let b = data[(l * n_phi + j) * n_phi + i];
                    if (a - b).abs() > 1e-12 * scale {
                        return Err(ParamError::new(
                            format!("coupling.H[{l}][{i}][{j}]"),
                            a,
                            format!("equal to H[{l}][{j}][{i}] = {b} (H symmetric in i, j)"),
                        ));
                    }
                }
            }
        }
        Ok(Self {
            n_phi,
            n_psi,
            h: data,
        })
    }

    /// Builds the tensor from `f(l, i, j)`, evaluated for `j ≤ i` only and mirrored, so the
    /// result is symmetric by construction. Errors as [`Self::new`] (non-finite values).
    pub fn from_fn(
        n_phi: usize,
        n_psi: usize,
        mut f: impl FnMut(usize, usize, usize) -> f64,
    ) -> Result<Self, ParamError> {
        let mut data = vec![0.0; n_psi * n_phi * n_phi];
        for l in 0..n_psi {
            for i in 0..n_phi {
                for j in 0..=i {
                    let v = f(l, i, j);
                    data[(l * n_phi + i) * n_phi + j] = v;
                    data[(l * n_phi + j) * n_phi + i] = v;
                }
            }
        }
        Self::new(n_phi, n_psi, data)
    }

    /// The entry `H^l_{i,j}`. Panics when an index is out of range.
    pub fn get(&self, l: usize, i: usize, j: usize) -> f64 {
        assert!(l < self.n_psi && i < self.n_phi && j < self.n_phi);
        self.h[(l * self.n_phi + i) * self.n_phi + j]
    }

    /// The `N_Φ × N_Φ` slice `H^l` (row-major).
    fn slab(&self, l: usize) -> &[f64] {
        let n2 = self.n_phi * self.n_phi;
        &self.h[l * n2..(l + 1) * n2]
    }
}

impl ModalCoupling for DenseCoupling {
    fn n_phi(&self) -> usize {
        self.n_phi
    }

    fn n_psi(&self) -> usize {
        self.n_psi
    }

    fn contract_eta(&self, qa: &[f64], qb: &[f64], out: &mut [f64]) {
        let n = self.n_phi;
        for (l, o) in out.iter_mut().enumerate().take(self.n_psi) {
            let slab = self.slab(l);
            let mut acc = 0.0;
            for (row, &a) in slab.chunks_exact(n).zip(qa) {
                acc += a * dot(row, qb);
            }
            *o = acc;
        }
    }

    fn apply_force(&self, q: &[f64], w: &[f64], out: &mut [f64]) {
        let n = self.n_phi;
        out[..n].fill(0.0);
        for (l, &wl) in w.iter().enumerate().take(self.n_psi) {
            if wl == 0.0 {
                continue;
            }
            for (row, o) in self.slab(l).chunks_exact(n).zip(out.iter_mut()) {
                *o += wl * dot(row, q);
            }
        }
    }

    fn coupling_matrix(&self, q: &[f64], g: &mut [f64]) {
        let (n, m) = (self.n_phi, self.n_psi);
        for l in 0..m {
            for (s, row) in self.slab(l).chunks_exact(n).enumerate() {
                g[s * m + l] = dot(row, q);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tensor() -> DenseCoupling {
        DenseCoupling::from_fn(3, 2, |l, i, j| {
            (1 + l) as f64 * 0.5 + (i * j) as f64 - i as f64
        })
        .unwrap()
    }

    #[test]
    fn kernels_match_their_definitions() {
        let c = tensor();
        let (qa, qb, w) = ([0.3, -1.2, 0.7], [1.1, 0.4, -0.9], [0.6, -2.0]);
        let mut eta = [0.0; 2];
        c.contract_eta(&qa, &qb, &mut eta);
        let mut f = [0.0; 3];
        c.apply_force(&qa, &w, &mut f);
        let mut g = [0.0; 6];
        c.coupling_matrix(&qa, &mut g);
        for (l, &got) in eta.iter().enumerate() {
            let want: f64 = (0..3)
                .flat_map(|i| (0..3).map(move |j| (i, j)))
                .map(|(i, j)| c.get(l, i, j) * qa[i] * qb[j])
                .sum();
            assert!((got - want).abs() < 1e-14, "{got} vs {want}");
        }
        for s in 0..3 {
            let mut want = 0.0;
            for l in 0..2 {
                let gsl: f64 = (0..3).map(|k| c.get(l, s, k) * qa[k]).sum();
                assert!((g[s * 2 + l] - gsl).abs() < 1e-14);
                want += gsl * w[l];
            }
            assert!((f[s] - want).abs() < 1e-14);
        }
    }

    #[test]
    fn rejects_bad_tensors() {
        assert!(DenseCoupling::new(2, 1, vec![0.0; 3]).is_err());
        let e = DenseCoupling::new(2, 1, vec![1.0, 2.0, 3.0, 4.0]).unwrap_err();
        assert!(e.to_string().contains("symmetric"), "{e}");
        assert!(DenseCoupling::new(1, 1, vec![f64::NAN]).is_err());
        assert!(DenseCoupling::new(0, 1, vec![]).is_err());
    }
}
