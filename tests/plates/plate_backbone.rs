//! Backbone curve of the gong's axisymmetric (0,1) mode: the free-oscillation frequency of the
//! single-mode reduction of the von Kármán plate rises with amplitude as a hardening cubic, and
//! the simulated frequency matches the exact Duffing frequency whose cubic coefficient comes
//! from an INDEPENDENT derivation: the compatibility equation `ΔΔF = -½ L(Φ, Φ)` integrated
//! directly as a radial ODE (no in-plane modes; `tests/common/compat.rs`), not from the tensor
//! the simulation uses.

use crate::compat;

use noether::analysis::analytic::DuffingFree;
use noether::analysis::frequency::measure;
use noether::modal::{CircularEdge, CircularPlateSpec, PlateModes};
use noether::models::plate::{DenseCoupling, LinearSolve, PlateModel, PlateParams, PlateScheme};
use std::sync::Arc;

/// Dimensionless units (a = 1, D = ρh = Eh = 1). With `ω` the mode's pulsation and
/// `Γ = ½ Σ_l (H^l_pp)²/ζ_l⁴` the single-mode equation is `q̈ + ω² q + Γ q³ = 0`.
/// Time step: 400 steps per linear period; the conservative scheme's frequency error is
/// O((Ωh)²/12) ≈ 5e-5 at the largest amplitude, the in-plane truncation (300 Ψ) ~1e-6, so the
/// tolerance is 2e-4 relative, while the amplitude shifts tested are 0.3 % to 25 %: a cubic
/// coefficient wrong by even 2 % fails.
#[test]
fn simulated_backbone_matches_the_independent_duffing_coefficient() {
    let spec = CircularPlateSpec::new(CircularEdge::Free, 0.3, 3, 300, None).unwrap();
    let modes = PlateModes::build(&spec).unwrap();
    let p = modes.phi.iter().position(|m| (m.n, m.k) == (0, 1)).unwrap();
    let omega = modes.lambda2[p];
    let gamma_direct = -compat::compatibility_direct(&modes.phi[p], 20000);
    // The single-mode model: only the in-plane modes that couple to (0,1) (axisymmetric ones).
    let ls: Vec<usize> = (0..modes.psi.len())
        .filter(|&l| modes.coupling.get(l, p, p).is_some())
        .collect();
    let h_pp: Vec<f64> = ls
        .iter()
        .map(|&l| modes.coupling.get(l, p, p).unwrap())
        .collect();
    let zeta4: Vec<f64> = ls.iter().map(|&l| modes.zeta4[l]).collect();
    let coupling = Arc::new(DenseCoupling::from_fn(1, ls.len(), |l, _, _| h_pp[l]).unwrap());
    let h = std::f64::consts::TAU / omega / 400.0;
    let mut previous = omega;
    for ratio in [0.01, 0.3, 1.0] {
        // Γ a² / ω² = ratio.
        let a = (ratio * omega * omega / gamma_direct).sqrt();
        let params = PlateParams {
            omega: vec![omega],
            zeta4: zeta4.clone(),
            rho_h: 1.0,
            e_h: 1.0,
            coupling_scale: 1.0,
            fs: 1.0 / h,
            damping: vec![0.0],
            scheme: PlateScheme::ConservativeExact,
            solve: LinearSolve::Auto,
        };
        let mut model = PlateModel::new(&params, coupling.clone(), vec![1.0], vec![]).unwrap();
        model.set_state(&[a], &[0.0]).unwrap();
        let mut q = Vec::with_capacity(40_000);
        for _ in 0..40_000 {
            model.step(0.0).unwrap();
            q.push(model.q()[0]);
        }
        let measured = measure(&q, h).unwrap().omega;
        let exact = DuffingFree::new(omega, gamma_direct, a)
            .unwrap()
            .angular_frequency();
        assert!(
            (measured / exact - 1.0).abs() < 2e-4,
            "ratio {ratio}: simulated {measured}, Duffing {exact}"
        );
        assert!(
            measured > previous,
            "not hardening at ratio {ratio}: {measured} <= {previous}"
        );
        previous = measured;
    }
    // The largest amplitude raised the frequency by far more than the tolerance.
    assert!(previous / omega > 1.2, "{previous} vs {omega}");
}
