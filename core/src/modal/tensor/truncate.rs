//! The coupling tensor of a truncated basis: the first `n_phi` transverse and `n_psi` in-plane
//! modes of a built tensor.
//!
//! Modes are sorted by increasing `λ` and `ζ` (see [`crate::modal::ModalBasis`]), and each
//! entry `H^l_{ij} = ∫ Ψ_l L(Φ_i, Φ_j) dS` depends only on its three modes, so the tensor of
//! the first modes is the sub-tensor `l < n_psi`, `j ≤ i < n_phi` of a larger one: no new
//! quadrature. The engine keeps one truncation per note tier (a high note keeps fewer modes
//! under its band limit). Worker thread (allocates).

use super::CouplingTensor;
use crate::error::ParamError;

impl CouplingTensor {
    /// The sub-tensor of the first `n_phi` transverse and `n_psi` in-plane modes, with its run
    /// and block layouts rebuilt, in this tensor's storage (the values of a single-storage
    /// tensor are already `f32`-representable: the copy is exact). Errors (naming the field, value and allowed range) when
    /// `n_phi` or `n_psi` is 0 or exceeds this tensor's counts.
    pub fn truncated(&self, n_phi: usize, n_psi: usize) -> Result<CouplingTensor, ParamError> {
        if n_phi == 0 || n_phi > self.n_phi() {
            return Err(ParamError::new(
                "coupling.n_phi",
                n_phi,
                format!("1 to {}", self.n_phi()),
            ));
        }
        if n_psi == 0 || n_psi > self.n_psi() {
            return Err(ParamError::new(
                "coupling.n_psi",
                n_psi,
                format!("1 to {}", self.n_psi()),
            ));
        }
        let (rs, ii, jj, vv) = self.parts();
        let mut row_start = Vec::with_capacity(n_psi + 1);
        let (mut i, mut j, mut value) = (Vec::new(), Vec::new(), Vec::new());
        row_start.push(0u32);
        for l in 0..n_psi {
            let (a, b) = (rs[l] as usize, rs[l + 1] as usize);
            // Rows are sorted by (i, j): the kept entries are a prefix of the row.
            for k in a..b {
                if (ii[k] as usize) < n_phi {
                    i.push(ii[k]);
                    j.push(jj[k]);
                    value.push(vv[k]);
                } else {
                    break;
                }
            }
            row_start.push(value.len() as u32);
        }
        CouplingTensor::from_parts(n_phi, n_psi, row_start, i, j, value)?
            .with_storage(self.storage())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tensor with every entry `H^l_{ij} = 1 + l + 10 i + 100 j` for `j ≤ i` (`n_phi`, `n_psi`).
    fn full(n_phi: usize, n_psi: usize) -> CouplingTensor {
        let mut rs = vec![0u32];
        let (mut i, mut j, mut v) = (Vec::new(), Vec::new(), Vec::new());
        for l in 0..n_psi {
            for a in 0..n_phi {
                for b in 0..=a {
                    i.push(a as u32);
                    j.push(b as u32);
                    v.push(1.0 + l as f64 + 10.0 * a as f64 + 100.0 * b as f64);
                }
            }
            rs.push(v.len() as u32);
        }
        CouplingTensor::from_parts(n_phi, n_psi, rs, i, j, v).unwrap()
    }

    /// Every entry of the truncation equals the original's (exactly: a copy), and entries
    /// outside it are absent; the kernels of the truncation equal the original's kernels on
    /// vectors that vanish beyond the kept modes (to 1e-12 relative: same terms, same order
    /// except for the dropped exact zeros).
    #[test]
    fn truncation_is_the_sub_tensor() {
        let t = full(9, 4);
        let s = t.truncated(5, 3).unwrap();
        assert_eq!((s.n_phi(), s.n_psi()), (5, 3));
        for l in 0..3 {
            for a in 0..5 {
                for b in 0..=a {
                    assert_eq!(s.get(l, a, b), t.get(l, a, b));
                }
            }
        }
        assert_eq!(s.nnz(), 3 * 15);
        let q: Vec<f64> = (0..9)
            .map(|k| if k < 5 { 0.3 - 0.1 * k as f64 } else { 0.0 })
            .collect();
        let (mut e_full, mut e_sub) = (vec![0.0; 4], vec![0.0; 3]);
        t.contract_eta(&q, &q, &mut e_full);
        s.contract_eta(&q[..5], &q[..5], &mut e_sub);
        for l in 0..3 {
            assert!((e_full[l] - e_sub[l]).abs() <= 1e-12 * e_full[l].abs().max(1.0));
        }
    }

    #[test]
    fn truncation_rejects_counts_out_of_range() {
        let t = full(4, 2);
        for (nf, np, field) in [
            (0, 1, "coupling.n_phi"),
            (5, 1, "coupling.n_phi"),
            (2, 0, "coupling.n_psi"),
            (2, 3, "coupling.n_psi"),
        ] {
            let e = t.truncated(nf, np).unwrap_err();
            assert_eq!(e.field, field);
        }
    }
}
