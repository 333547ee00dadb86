//! The curved plate (a static rest shape, `core/src/models/plate/model/rest_shape.rs`) in every
//! plate scheme: a free-edge circular plate shaped as a spherical cap (a shallow shell).
//!
//! Units: radius 1, `D = ρh = 1` (so `ω = λ²`, the crate's dimensionless modal units), thickness
//! `TH`, `Eh = 12(1-ν²) D / TH²`; the cap `w0/TH = (κ/2)(1 - r²)` projects to `a = TH ã`
//! (`Imperfection::project`). In these units the model's linear stiffness is exactly the
//! `shell_stiffness` of `noether::modal::shell`, so the shell's `λ²` are the model's linear
//! pulsations (rad/s). Figures print with `--nocapture`.

use std::sync::Arc;

use faer::{Mat, Side};
use noether::modal::circular::{CircularEdge, Parity, PlateModes};
use noether::modal::shell::{shell_stiffness, CapCoupling, Imperfection};
use noether::modal::{CircularPlateSpec, CouplingTensor};
use noether::models::plate::{LinearSolve, Mallet, PlateModel, PlateParams, PlateScheme};
use noether_testkit::alloc::count_allocations;

/// Plate thickness in units of the radius.
const TH: f64 = 0.01;
const NU: f64 = 0.3;

const CONSERVATIVE: [PlateScheme; 3] = [
    PlateScheme::ConservativeExact,
    PlateScheme::ConservativeTheta1,
    PlateScheme::SavExact,
];

/// The free plate's mirror basis, 40 transverse and 20 in-plane modes, ν = 0.3.
fn basis() -> PlateModes {
    let spec = CircularPlateSpec::new(CircularEdge::Free, NU, 40, 20, None)
        .unwrap()
        .mirror_symmetric();
    PlateModes::build(&spec).unwrap()
}

/// The model on `modes` at `fs` (Hz) with modal damping `c` (1/s) for every mode.
fn model(modes: &PlateModes, scheme: PlateScheme, fs: f64, c: f64) -> PlateModel<CouplingTensor> {
    let n = modes.lambda2.len();
    let params = PlateParams {
        omega: modes.lambda2.clone(),
        zeta4: modes.zeta4.clone(),
        rho_h: 1.0,
        e_h: 12.0 * (1.0 - NU * NU) / (TH * TH),
        coupling_scale: 1.0,
        fs,
        damping: vec![c; n],
        scheme,
        solve: LinearSolve::Auto,
    };
    // Force weights: the modes at r = 0.3 on the strike diameter.
    let weights: Vec<f64> = (0..n).map(|s| modes.phi_at(s, 0.3, 0.0)).collect();
    PlateModel::new(&params, Arc::new(modes.coupling.clone()), weights, vec![]).unwrap()
}

/// The cap of curvature `kappa` projected on `modes`, in units of `q`.
fn cap(modes: &PlateModes, kappa: f64) -> Vec<f64> {
    let imp = Imperfection::spherical_cap(kappa).unwrap();
    imp.project(modes).iter().map(|x| TH * x).collect()
}

/// The shell's lowest axisymmetric mode: `λ²` and its eigenvector (flat-mode coordinates),
/// from `shell_stiffness` with the same projection the model uses.
fn fundamental_axisymmetric(modes: &PlateModes, kappa: f64) -> (f64, Vec<f64>) {
    let imp = Imperfection::spherical_cap(kappa).unwrap();
    let k = shell_stiffness(modes, &imp, CapCoupling::ModalProjection).unwrap();
    let n = modes.lambda2.len();
    let idx: Vec<usize> = (0..n)
        .filter(|&s| modes.phi[s].n == 0 && modes.phi[s].parity == Parity::Cos)
        .collect();
    let m = idx.len();
    let block = Mat::<f64>::from_fn(m, m, |r, c| k[idx[r] * n + idx[c]]);
    let evd = block.self_adjoint_eigen(Side::Lower).unwrap();
    let (s, u) = (evd.S().column_vector(), evd.U());
    let lowest = (0..m).min_by(|&a, &b| s[a].total_cmp(&s[b])).unwrap();
    let mut v = vec![0.0; n];
    for (r, &i) in idx.iter().enumerate() {
        v[i] = u[(r, lowest)];
    }
    (s[lowest].sqrt(), v)
}

/// Pulsation (rad/s) of `x(n)` from its upward zero crossings (linear interpolation), over
/// whole periods. Shared with `plate_shell_backbone.rs`.
pub(crate) fn pulsation(x: &[f64], h: f64) -> f64 {
    let ups: Vec<f64> = x
        .windows(2)
        .enumerate()
        .filter(|(_, w)| w[0] < 0.0 && w[1] >= 0.0)
        .map(|(i, w)| (i as f64 + w[0] / (w[0] - w[1])) * h)
        .collect();
    let periods = (ups.len() - 1) as f64;
    std::f64::consts::TAU * periods / (ups[ups.len() - 1] - ups[0])
}

/// Free vibration of the shell's fundamental axisymmetric mode at `amplitude` (units of `q`,
/// along the linear eigenvector) for `seconds`: its pulsation measured on `vᵀ q(n)`.
fn measured_pulsation(
    modes: &PlateModes,
    scheme: PlateScheme,
    kappa: f64,
    fs: f64,
    amplitude: f64,
    seconds: f64,
) -> f64 {
    let (_, v) = fundamental_axisymmetric(modes, kappa);
    let mut p = model(modes, scheme, fs, 0.0);
    p.set_rest_shape(&cap(modes, kappa)).unwrap();
    let q0: Vec<f64> = v.iter().map(|x| amplitude * x).collect();
    p.set_state(&q0, &vec![0.0; q0.len()]).unwrap();
    let steps = (seconds * fs) as usize;
    let mut x = Vec::with_capacity(steps);
    for _ in 0..steps {
        p.step(0.0).unwrap();
        x.push(p.q().iter().zip(&v).map(|(q, v)| q * v).sum());
    }
    pulsation(&x, 1.0 / fs)
}

/// At small amplitude the curved plate vibrates at the shell's linear frequency: the
/// fundamental axisymmetric mode of a cap with κ = 10 (raised from the flat 9.08 to 34.2 rad/s
/// in these units) is reproduced by the conservative schemes with an `O(h²)` error (the
/// curvature's stiffness is integrated like the nonlinearity, `rest_shape.rs`). Checked:
/// relative error below 2e-4 at fs = 1000 (`hω = 0.034`; measured -8.8e-5), and the error
/// falls by 4 ± 0.4 when `h` halves (second order; measured 3.999). Leaving the rest shape out
/// is off by a factor 3.8. SAV is consistent but less accurate here: `√(2U)` of a potential
/// that is quadratic near rest is `|·|`-like, so its `g` flips where the motion crosses rest
/// (measured 7.9e-3 at 1 kHz, 2.4e-3 at 2 kHz; checked below 1e-2 and falling at least 2.5×
/// per halving). Amplitude 1e-9 thicknesses: the nonlinear shift is `O(1e-18)`.
#[test]
fn small_amplitude_frequency_is_the_shells() {
    let modes = basis();
    let kappa = 10.0;
    let (lam2, _) = fundamental_axisymmetric(&modes, kappa);
    println!("shell (0,1) λ² at κ = {kappa}: {lam2:.8}");
    assert!(lam2 > 30.0 && lam2 < 40.0, "{lam2}");
    for scheme in CONSERVATIVE {
        let e1 = measured_pulsation(&modes, scheme, kappa, 1000.0, 1e-9 * TH, 4.0) / lam2 - 1.0;
        let e2 = measured_pulsation(&modes, scheme, kappa, 2000.0, 1e-9 * TH, 4.0) / lam2 - 1.0;
        println!(
            "{scheme:?}: error {e1:.3e} at 1 kHz, {e2:.3e} at 2 kHz, ratio {:.3}",
            e1 / e2
        );
        if scheme == PlateScheme::SavExact {
            assert!(e1.abs() < 1e-2 && e1 / e2 > 2.5, "{scheme:?}: {e1} / {e2}");
        } else {
            assert!(e1.abs() < 2e-4, "{scheme:?}: {e1}");
            assert!((e1 / e2 - 4.0).abs() < 0.4, "{scheme:?}: {e1} / {e2}");
        }
    }
}

/// Lossless runs of the conservative schemes keep their discrete energy to round-off with a
/// rest shape (the SAV scheme its energy plus what its relaxation removed, which is never
/// negative in a lossless run: the energy never exceeds its start): κ = 20, the plate started at 3 thicknesses of the fundamental axisymmetric
/// mode's shape plus every mode at 0.3 thicknesses (strongly nonlinear: quadratic and cubic
/// terms both large), 20 000 steps at fs = 4 kHz. Tolerance 1e-11 of the energy: the flat
/// plate's bound (`plate_scheme.rs`), round-off of `O(N)` sums over 2·10⁴ steps (measured in
/// the printout: 2e-13 to 1.1e-12). Leaving the shift `σ` out of the conservative update (the
/// flat plate's right-hand side with the curved `G`) gives a drift of 2.6e-1.
#[test]
fn lossless_energy_is_conserved_to_round_off() {
    let modes = basis();
    let n = modes.lambda2.len();
    let (_, v) = fundamental_axisymmetric(&modes, 20.0);
    for scheme in CONSERVATIVE {
        let mut p = model(&modes, scheme, 4000.0, 0.0);
        p.set_rest_shape(&cap(&modes, 20.0)).unwrap();
        let q0: Vec<f64> = (0..n)
            .map(|s| 3.0 * TH * v[s] + 0.3 * TH * ((s * 7919 % 13) as f64 / 6.0 - 1.0))
            .collect();
        p.set_state(&q0, &vec![0.0; n]).unwrap();
        let e0 = p.energy();
        let (mut drift, mut over) = (0.0f64, 0.0f64);
        for _ in 0..20_000 {
            p.step(0.0).unwrap();
            let e = p.energy();
            drift = drift.max((e.balance() - e0.balance()).abs());
            over = over.max(e.total() - e0.total());
        }
        let (rel, relaxed) = (drift / e0.total(), p.energy().relaxed / e0.total());
        println!(
            "{scheme:?}: energy {:.4e} (nonlinear share {:.2}), drift {rel:.2e}, relaxed {relaxed:.2e}",
            e0.total(),
            e0.nonlinear / e0.total()
        );
        assert!(rel < 1e-11, "{scheme:?}: {rel}");
        assert!(
            over <= 1e-11 * e0.total(),
            "{scheme:?}: energy rose by {over:e}"
        );
    }
}

/// With losses, a force pulse, the player's hand and a mallet, the power balance of the curved
/// plate closes to round-off in the conservative schemes (joint balance with the mallet's
/// energy). Tolerance 1e-11 of the largest stored energy, as above (measured 7e-13 to
/// 1.4e-12); leaving the shift `σ` out of the conservative update gives 5.9e-2.
#[test]
fn power_balance_closes_with_losses_forcing_hand_and_mallet() {
    let modes = basis();
    let n = modes.lambda2.len();
    let fs = 8000.0;
    for scheme in CONSERVATIVE {
        let mut p = model(&modes, scheme, fs, 0.5);
        p.set_rest_shape(&cap(&modes, 15.0)).unwrap();
        let hand: Vec<f64> = (0..n).map(|s| modes.phi_at(s, 0.6, 0.4)).collect();
        p.set_hand(&hand, 0.05).unwrap();
        // A pulse of 2 ms, peak 0.5 (force units of D/a), then a mallet.
        let mut top = 0.0f64;
        let mut worst = 0.0f64;
        for i in 0..16 {
            let t = i as f64 / fs;
            let f = 0.25 * (1.0 - (std::f64::consts::TAU * t / 2e-3).cos());
            p.step(f).unwrap();
            top = top.max(p.energy().total());
        }
        let mut m = Mallet::new(0.02, 2e6, 2.5, 0.3, p.h()).unwrap();
        p.launch_mallet(&mut m, 0.5).unwrap();
        let mb0 = m.energy().joint_balance(&p.energy());
        for _ in 0..8000 {
            p.step_with_mallet(&mut m).unwrap();
            let e = p.energy();
            top = top.max(e.total());
            worst = worst.max((m.energy().joint_balance(&e) - mb0).abs());
        }
        println!(
            "{scheme:?}: largest energy {top:.3e}, joint balance drift {:.2e}",
            worst / top
        );
        assert!(worst / top < 1e-11, "{scheme:?}: {}", worst / top);
    }
}

/// A zero rest shape is the flat plate, bit for bit, in every scheme; and stepping a curved
/// plate allocates nothing.
#[test]
fn zero_rest_shape_is_the_flat_plate_and_steps_do_not_allocate() {
    let modes = basis();
    let n = modes.lambda2.len();
    let q0: Vec<f64> = (0..n).map(|s| TH * (s % 5) as f64 / 4.0).collect();
    for scheme in [
        PlateScheme::ConservativeExact,
        PlateScheme::ConservativeTheta1,
        PlateScheme::SavExact,
        PlateScheme::StormerVerletExact,
    ] {
        let mut flat = model(&modes, scheme, 8000.0, 1.0);
        let mut zero = model(&modes, scheme, 8000.0, 1.0);
        zero.set_rest_shape(&vec![0.0; n]).unwrap();
        assert!(zero.rest_shape().is_none());
        flat.set_state(&q0, &vec![0.0; n]).unwrap();
        zero.set_state(&q0, &vec![0.0; n]).unwrap();
        for _ in 0..500 {
            flat.step(0.1).unwrap();
            zero.step(0.1).unwrap();
        }
        assert_eq!(flat.q(), zero.q(), "{scheme:?}");
        assert_eq!(flat.energy(), zero.energy(), "{scheme:?}");

        let mut curved = model(&modes, scheme, 8000.0, 1.0);
        curved.set_rest_shape(&cap(&modes, 10.0)).unwrap();
        curved.set_state(&q0, &vec![0.0; n]).unwrap();
        let mut m = Mallet::new(0.02, 2e6, 2.5, 0.3, curved.h()).unwrap();
        curved.launch_mallet(&mut m, 0.5).unwrap();
        let ((), count) = count_allocations(|| {
            for _ in 0..200 {
                curved.step(0.1).unwrap();
                curved.step_with_mallet(&mut m).unwrap();
            }
        });
        assert_eq!(count, 0, "{scheme:?}");
        assert!(curved.q().iter().all(|x| x.is_finite()));
    }
}

/// Bad rest shapes are refused with the field named.
#[test]
fn rejects_bad_rest_shapes() {
    let modes = basis();
    let mut p = model(&modes, PlateScheme::ConservativeExact, 8000.0, 0.0);
    let e = p.set_rest_shape(&[0.0; 3]).unwrap_err().to_string();
    assert!(
        e.contains("rest_shape.len") && e.contains("n_phi = 40"),
        "{e}"
    );
    let mut a = vec![0.0; 40];
    a[7] = f64::NAN;
    let e = p.set_rest_shape(&a).unwrap_err().to_string();
    assert!(e.contains("rest_shape[7]"), "{e}");
}
