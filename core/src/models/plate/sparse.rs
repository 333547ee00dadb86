//! The sparse modal coupling tensor of [`crate::modal`] as the plate model's [`ModalCoupling`]:
//! the `_with_scratch` kernels (which the model calls) stream the dense selection-rule blocks,
//! the plain ones the run layout (kept as references).

use super::coupling::ModalCoupling;
use crate::modal::CouplingTensor;

impl ModalCoupling for CouplingTensor {
    fn n_phi(&self) -> usize {
        CouplingTensor::n_phi(self)
    }

    fn n_psi(&self) -> usize {
        CouplingTensor::n_psi(self)
    }

    fn contract_eta(&self, qa: &[f64], qb: &[f64], out: &mut [f64]) {
        CouplingTensor::contract_eta(self, qa, qb, out);
    }

    fn apply_force(&self, q: &[f64], w: &[f64], out: &mut [f64]) {
        CouplingTensor::apply_force(self, q, w, out);
    }

    fn coupling_matrix(&self, q: &[f64], g: &mut [f64]) {
        CouplingTensor::coupling_matrix(self, q, g);
    }

    fn kernel_scratch_len(&self) -> usize {
        CouplingTensor::kernel_scratch_len(self)
    }

    fn contract_eta_with_scratch(&self, qa: &[f64], qb: &[f64], out: &mut [f64], s: &mut [f64]) {
        CouplingTensor::contract_eta_with_scratch(self, qa, qb, out, s);
    }

    fn apply_force_with_scratch(&self, q: &[f64], w: &[f64], out: &mut [f64], s: &mut [f64]) {
        CouplingTensor::apply_force_with_scratch(self, q, w, out, s);
    }

    fn coupling_matrix_with_scratch(&self, q: &[f64], g: &mut [f64], s: &mut [f64]) {
        CouplingTensor::coupling_matrix_with_scratch(self, q, g, s);
    }

    fn quartic_gradient_rows(
        &self,
        rows: std::ops::Range<usize>,
        q: &[f64],
        w: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) -> bool {
        CouplingTensor::quartic_gradient_rows(self, rows, q, w, eta, grad, scratch);
        true
    }
    fn quartic_gradient_shifted_rows(
        &self,
        rows: std::ops::Range<usize>,
        q: &[f64],
        w: &[f64],
        shift: &[f64],
        eta: &mut [f64],
        grad: &mut [f64],
        scratch: &mut [f64],
    ) -> bool {
        CouplingTensor::quartic_gradient_rows_shifted(self, rows, q, w, shift, eta, grad, scratch);
        true
    }
    fn split_row(&self) -> usize {
        CouplingTensor::split_row(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modal::{CircularEdge, CircularPlateSpec, PlateModes};

    /// `coupling_matrix` agrees with `apply_force` (`Σ_l G_{s,l} w_l`) and with
    /// `contract_eta` (`Σ_s G_{s,l} q_s`) on the real Bessel tensor, to round-off.
    #[test]
    fn matrix_agrees_with_the_kernels() {
        let spec = CircularPlateSpec::new(CircularEdge::Free, 0.3, 30, 12, None).unwrap();
        let m = PlateModes::build(&spec).unwrap();
        let t = &m.coupling;
        let (nf, np) = (30, 12);
        let q: Vec<f64> = (0..nf)
            .map(|k| ((k * 7 + 3) % 11) as f64 / 11.0 - 0.4)
            .collect();
        let w: Vec<f64> = (0..np)
            .map(|l| ((l * 5 + 1) % 7) as f64 / 7.0 - 0.3)
            .collect();
        let mut g = vec![0.0; nf * np];
        t.coupling_matrix(&q, &mut g);
        let mut f = vec![0.0; nf];
        ModalCoupling::apply_force(t, &q, &w, &mut f);
        let mut eta = vec![0.0; np];
        ModalCoupling::contract_eta(t, &q, &q, &mut eta);
        let scale = g.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        for s in 0..nf {
            let gw: f64 = (0..np).map(|l| g[s * np + l] * w[l]).sum();
            assert!(
                (gw - f[s]).abs() < 1e-12 * scale,
                "row {s}: {gw} vs {}",
                f[s]
            );
        }
        for l in 0..np {
            let gq: f64 = (0..nf).map(|s| g[s * np + l] * q[s]).sum();
            assert!(
                (gq - eta[l]).abs() < 1e-12 * scale * nf as f64,
                "col {l}: {gq} vs {}",
                eta[l]
            );
        }
    }
}
