//! Solver, exactness, impulse, `process` and backbone tests of the modal plate schemes
//! (`noether::models::plate`) on random plates, over the four schemes (SAV-specific tests in
//! `plate_sav.rs`). Energy conservation and the power balance with losses and forcing, for
//! every scheme on real plates, are the catalogue's (`tests/schemes/catalogue.rs`).
//!
//! Figures are printed with `--nocapture` for the report.

use std::f64::consts::PI;
use std::sync::Arc;

use noether::analysis::frequency::measure;
use noether::models::plate::{
    damping_law, impulse_force, DenseCoupling, LinearSolve, ModalCoupling, PickupKind,
    PickupWeights, PlateModel, PlateParams, PlateScheme, RaisedCosine,
};
use noether_testkit::alloc::allocations;

// ---------------------------------------------------------------- random plates

const ALL: [PlateScheme; 4] = [
    PlateScheme::ConservativeTheta1,
    PlateScheme::ConservativeExact,
    PlateScheme::StormerVerletExact,
    PlateScheme::SavExact,
];
const CONSERVATIVE: [PlateScheme; 2] = [
    PlateScheme::ConservativeTheta1,
    PlateScheme::ConservativeExact,
];

/// SplitMix64: deterministic uniform numbers in [-1, 1).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    fn vec(&mut self, n: usize) -> Vec<f64> {
        (0..n).map(|_| self.next()).collect()
    }
}

/// A random plate: `n_phi` modes between 20 Hz and 200 Hz, random symmetric tensor, steel-like
/// `ρh`, `Eh`, `fs` = 10 kHz (h ω_max = 0.13: θ = 1 is stable, and the nonlinear stiffening at
/// u ≈ 50 % of the energy stays resolved, so Störmer-Verlet does not blow up).
struct Case {
    n_phi: usize,
    n_psi: usize,
    seed: u64,
    damped: bool,
}

impl Case {
    fn coupling(&self) -> Arc<DenseCoupling> {
        let mut rng = Rng(self.seed);
        Arc::new(DenseCoupling::from_fn(self.n_phi, self.n_psi, |_, _, _| rng.next()).unwrap())
    }

    fn params(&self, scheme: PlateScheme, solve: LinearSolve) -> PlateParams {
        let mut rng = Rng(self.seed ^ 0xABCD);
        let omega: Vec<f64> = (0..self.n_phi)
            .map(|s| {
                let f = 20.0 + 180.0 * s as f64 / (self.n_phi.max(2) - 1) as f64;
                2.0 * PI * f * (1.0 + 0.02 * rng.next())
            })
            .collect();
        let damping = if self.damped {
            damping_law(&omega, 0.05, 0.6, 0.0).unwrap()
        } else {
            vec![0.0; self.n_phi]
        };
        PlateParams {
            zeta4: (0..self.n_psi).map(|l| 1e4 * (1.0 + l as f64)).collect(),
            omega,
            rho_h: 7.86,
            e_h: 2e8,
            coupling_scale: 1.0,
            fs: 10_000.0,
            damping,
            scheme,
            solve,
        }
    }

    fn model(&self, scheme: PlateScheme, solve: LinearSolve) -> PlateModel<DenseCoupling> {
        let mut rng = Rng(self.seed ^ 0x5555);
        PlateModel::new(
            &self.params(scheme, solve),
            self.coupling(),
            rng.vec(self.n_phi),
            vec![PickupWeights::new(rng.vec(self.n_phi), PickupKind::Displacement).unwrap()],
        )
        .unwrap()
    }

    /// Sets a random initial state scaled until the in-plane energy `u` is at least
    /// `share` of the total; returns the share reached.
    fn excite(&self, model: &mut PlateModel<DenseCoupling>, share: f64) -> f64 {
        let mut rng = Rng(self.seed ^ 0x7777);
        let dir = rng.vec(self.n_phi);
        let vdir = rng.vec(self.n_phi);
        let mut a = 1e-9;
        for _ in 0..400 {
            let q0: Vec<f64> = dir.iter().map(|d| a * d).collect();
            let v0: Vec<f64> = vdir.iter().map(|d| 300.0 * a * d).collect();
            model.set_state(&q0, &v0).unwrap();
            let e = model.energy();
            if e.nonlinear / e.total() >= share {
                return e.nonlinear / e.total();
            }
            a *= 1.2;
        }
        panic!("no amplitude reached u share {share}");
    }
}

fn name(s: PlateScheme) -> &'static str {
    match s {
        PlateScheme::ConservativeTheta1 => "conservative θ=1",
        PlateScheme::ConservativeExact => "conservative exact",
        PlateScheme::StormerVerletExact => "Störmer-Verlet exact",
        PlateScheme::SavExact => "SAV exact",
    }
}

const SIZES: [(usize, usize); 2] = [(12, 6), (8, 14)];

// ---------------------------------------------------------------- tests

/// Woodbury and direct routes solve the same system: trajectories agree to 1e-12 (relative
/// to max |q|) over 30 strongly nonlinear steps (measured ~1e-14). The two routes round
/// differently (~1e-16 per solve) and strongly nonlinear dynamics amplify such differences over
/// long runs, so the comparison is kept short enough to see the solves, not the dynamics.
#[test]
fn woodbury_and_direct_routes_agree() {
    for &(n_phi, n_psi) in &SIZES {
        let case = Case {
            n_phi,
            n_psi,
            seed: 5,
            damped: true,
        };
        for scheme in CONSERVATIVE {
            let mut w = case.model(scheme, LinearSolve::Woodbury);
            let mut d = case.model(scheme, LinearSolve::Direct);
            assert_eq!(w.solve_route(), Some(LinearSolve::Woodbury));
            assert_eq!(d.solve_route(), Some(LinearSolve::Direct));
            case.excite(&mut w, 0.5);
            case.excite(&mut d, 0.5);
            let (mut diff, mut scale) = (0.0f64, 0.0f64);
            for _ in 0..30 {
                w.step(0.0).unwrap();
                d.step(0.0).unwrap();
                for (a, b) in w.q().iter().zip(d.q()) {
                    diff = diff.max((a - b).abs());
                    scale = scale.max(a.abs());
                }
            }
            eprintln!(
                "[{}] N_Φ={n_phi} N_Ψ={n_psi}: Woodbury vs direct max |Δq|/max|q| = {:.2e}",
                name(scheme),
                diff / scale
            );
            assert!(diff / scale < 1e-12);
        }
    }
}

/// Without coupling (`coupling_scale = 0`), the exact-linear schemes reproduce the damped and
/// undamped modal solution at every sample for any h, including ωh > π (SEED 1.2 shows
/// h = 0.31, 1.25, 10 for ω = 1). Tolerance 1e-12 · n_steps relative: the two-step recursion
/// accumulates round-off linearly in the number of steps.
#[test]
fn exact_linear_part_reproduces_the_modal_solution_at_any_h() {
    let coupling = Arc::new(DenseCoupling::from_fn(1, 1, |_, _, _| 1.0).unwrap());
    for scheme in [
        PlateScheme::ConservativeExact,
        PlateScheme::StormerVerletExact,
        PlateScheme::SavExact,
    ] {
        for &(h, c) in &[
            (0.31, 0.0),
            (1.25, 0.0),
            (10.0, 0.0),
            (0.01, 0.0),
            (2.0, 0.2),
            (0.3, 3.0),
        ] {
            let omega = 1.0;
            let params = PlateParams {
                omega: vec![omega],
                zeta4: vec![1.0],
                rho_h: 1.0,
                e_h: 1.0,
                coupling_scale: 0.0,
                fs: 1.0 / h,
                damping: vec![c],
                scheme,
                solve: LinearSolve::Auto,
            };
            let mut m = PlateModel::new(&params, coupling.clone(), vec![0.0], vec![]).unwrap();
            m.set_state(&[1.0], &[0.0]).unwrap();
            let steps = 2000;
            let sigma: f64 = c / 2.0;
            let exact = |t: f64| {
                if omega > sigma {
                    let wd = (omega * omega - sigma * sigma).sqrt();
                    (-sigma * t).exp() * ((wd * t).cos() + sigma / wd * (wd * t).sin())
                } else {
                    let l = (sigma * sigma - omega * omega).sqrt();
                    (-sigma * t).exp() * ((l * t).cosh() + sigma / l * (l * t).sinh())
                }
            };
            let mut err = 0.0f64;
            for n in 1..=steps {
                m.step(0.0).unwrap();
                err = err.max((m.q()[0] - exact(n as f64 * h)).abs());
            }
            eprintln!(
                "[{}] h={h} c={c}: max |q - q_exact| over {steps} steps = {err:.2e}",
                name(scheme)
            );
            assert!(err < 1e-12 * steps as f64, "h={h} c={c}: {err}");
        }
    }
}

/// θ = 1 refuses h ω_max ≥ 2 with an error naming `fs` and the limit; just below is accepted,
/// and the exact-linear schemes accept the unstable rate.
#[test]
fn theta1_refuses_unstable_sampling_rates() {
    let case = Case {
        n_phi: 4,
        n_psi: 2,
        seed: 1,
        damped: false,
    };
    let mut p = case.params(PlateScheme::ConservativeTheta1, LinearSolve::Auto);
    let wmax = p.omega.iter().copied().fold(0.0, f64::max);
    for fs in [wmax / 2.0, wmax / 4.0] {
        p.fs = fs;
        let e = PlateModel::new(&p, case.coupling(), vec![0.0; 4], vec![])
            .err()
            .expect("refused");
        let msg = e.to_string();
        assert_eq!(e.field, "fs");
        assert!(msg.contains(&format!("{}", wmax / 2.0)), "{msg}");
    }
    p.fs = wmax / 2.0 * (1.0 + 1e-9);
    assert!(PlateModel::new(&p, case.coupling(), vec![0.0; 4], vec![]).is_ok());
    p.fs = wmax / 4.0;
    for scheme in [
        PlateScheme::ConservativeExact,
        PlateScheme::StormerVerletExact,
        PlateScheme::SavExact,
    ] {
        p.scheme = scheme;
        assert!(PlateModel::new(&p, case.coupling(), vec![0.0; 4], vec![]).is_ok());
    }
}

/// A one-step impulse gives the velocity jump Φ_s I / ρh (no damping, at rest, no coupling):
/// exact to round-off (1e-12 relative).
#[test]
fn impulse_gives_the_velocity_jump() {
    for scheme in ALL {
        let case = Case {
            n_phi: 5,
            n_psi: 3,
            seed: 9,
            damped: false,
        };
        let mut m = case.model(scheme, LinearSolve::Auto);
        let phi = Rng(9 ^ 0x5555).vec(5);
        let fs = 10_000.0;
        m.step(impulse_force(0.01, fs)).unwrap();
        for (s, &p) in phi.iter().enumerate() {
            let v = (m.q()[s] - m.q_prev()[s]) * fs;
            let want = p * 0.01 / 7.86;
            assert!((v - want).abs() < 1e-12 * want.abs(), "{v} vs {want}");
        }
    }
}

/// `process` writes the same samples as `step` + `outputs`, for f32 and f64, interleaving the
/// pickups; backward-velocity pickups equal the difference quotient of displacement pickups.
/// Neither `step` nor `process` allocates (counted by the binary's global allocator,
/// `noether_testkit::alloc::Guard`).
#[test]
fn process_matches_step_and_does_not_allocate() {
    let case = Case {
        n_phi: 10,
        n_psi: 4,
        seed: 21,
        damped: true,
    };
    for scheme in ALL {
        let coupling: Arc<dyn ModalCoupling> = case.coupling();
        let weights = Rng(77).vec(10);
        let pickups = vec![
            PickupWeights::new(weights.clone(), PickupKind::Displacement).unwrap(),
            PickupWeights::new(weights.clone(), PickupKind::VelocityBackward).unwrap(),
        ];
        let params = case.params(scheme, LinearSolve::Auto);
        let mut a: PlateModel =
            PlateModel::new(&params, coupling.clone(), weights.clone(), pickups.clone()).unwrap();
        let mut b: PlateModel = PlateModel::new(&params, coupling, weights, pickups).unwrap();
        let strike = RaisedCosine::new(1e-3, 50.0).unwrap();
        let force: Vec<f64> = (0..256).map(|n| strike.force(n as f64 * 1e-4)).collect();
        let mut out64 = vec![0.0f64; 512];
        let mut out32 = vec![0.0f32; 512];
        let before = allocations();
        let frames = a.process(&force, &mut out64).unwrap();
        let mut prev_disp = 0.0;
        for (n, &f) in force.iter().enumerate() {
            b.step(f).unwrap();
            assert_eq!(b.outputs()[0], out64[2 * n]);
            assert_eq!(b.outputs()[1], out64[2 * n + 1]);
            let fd = (b.outputs()[0] - prev_disp) * 1e4;
            assert!((fd - b.outputs()[1]).abs() <= 1e-9 * fd.abs().max(1e-12));
            prev_disp = b.outputs()[0];
        }
        a.reset();
        a.process(&force, &mut out32).unwrap();
        assert_eq!(
            allocations(),
            before,
            "{scheme:?} allocated on the audio path"
        );
        assert_eq!(frames, 256);
        assert_eq!(out32[100], out64[100] as f32);
    }
}

/// Backbone: one transverse mode coupled to one in-plane mode is the Duffing oscillator
/// `q̈ + ω² q + Γ q³ = 0`, `Γ = κ² Eh Ĥ² / (2 ρh ζ⁴)`; from `q(0) = a`, `q̇(0) = 0` its angular
/// frequency is `2π / T`, `T = 4 K(m) / Ω`, `Ω² = ω² + Γ a²`, `m = Γ a² / (2 Ω²)`.
/// At fs = 100 kHz (ω h = 6.3e-3) every scheme is second order. θ = 1 on a linear oscillator
/// of frequency ω errs by `(ωh)²/24` relative; along the Duffing orbit the linearised frequency
/// reaches `ω_max² = ω² + 3Γa²`, so the tolerance is `(ω_max h)² / 12` (a factor 2 over the
/// linear bound at the stiffest point of the orbit). Frequency measured on ~100
/// periods by `measure()` (crossing error ~1e-12).
#[test]
fn single_mode_backbone_matches_duffing() {
    let (omega, rho_h, e_h, zeta4, kappa, hh) = (2.0 * PI * 100.0, 7.86, 2e8, 3e4, 2.0, 0.7);
    let gamma = kappa * kappa * e_h * hh * hh / (2.0 * rho_h * zeta4);
    let coupling = Arc::new(DenseCoupling::new(1, 1, vec![hh]).unwrap());
    let fs = 100_000.0;
    let h = 1.0 / fs;
    for scheme in ALL {
        for ratio in [0.0, 0.1, 1.0, 4.0] {
            // ratio = Γ a² / ω²: from linear to strongly hardening (frequency ×2.4).
            let a = (ratio * omega * omega / gamma).sqrt();
            let params = PlateParams {
                omega: vec![omega],
                zeta4: vec![zeta4],
                rho_h,
                e_h,
                coupling_scale: kappa,
                fs,
                damping: vec![0.0],
                scheme,
                solve: LinearSolve::Auto,
            };
            let mut m = PlateModel::new(&params, coupling.clone(), vec![0.0], vec![]).unwrap();
            m.set_state(&[a.max(1e-9)], &[0.0]).unwrap();
            let big_omega = (omega * omega + gamma * a * a).sqrt();
            let mpar = gamma * a * a / (2.0 * big_omega * big_omega);
            let want = 2.0 * PI / (4.0 * ellip::ellipk(mpar).unwrap() / big_omega);
            let steps = (100.5 * 2.0 * PI / want / h) as usize;
            let mut x = Vec::with_capacity(steps);
            for _ in 0..steps {
                m.step(0.0).unwrap();
                x.push(m.q()[0]);
            }
            let got = measure(&x, h).unwrap().omega;
            let err = (got / want - 1.0).abs();
            let tol = (omega * omega + 3.0 * gamma * a * a) * h * h / 12.0;
            eprintln!(
                "[{}] Γa²/ω² = {ratio}: ω_NL/ω = {:.6}, measured/exact - 1 = {err:.2e} (tol {tol:.1e})",
                name(scheme),
                want / omega
            );
            assert!(err < tol, "{scheme:?} ratio {ratio}: {err} >= {tol}");
        }
    }
}
