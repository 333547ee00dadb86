//! The backbone of the curved plate's fundamental axisymmetric mode (a free-edge shallow
//! spherical cap, `core/src/models/plate/model/rest_shape.rs`): hardening or softening against
//! the curvature `κ = a²/(Rh)`, single-mode theory against the normal form with every
//! quadratic coupling and against the simulated model.
//!
//! Units as `plate_shell.rs`: radius 1, `D = ρh = 1`, thickness `TH`, `Eh = 12(1-ν²)/TH²`, the
//! cap `a = TH ã`. The model's potential is `U = Σ_l u_l (Ĥ(r,r)_l - c_l)²`, `r = q + a`,
//! `c_l = Ĥ(a,a)_l`, `u_l = Eh/(8ζ_l⁴)` (`rest_shape.rs`; the force is `-∇U`).
//!
//! **Single mode.** On `q = x v` (`v` the unit shell eigenvector of the lowest axisymmetric
//! mode), `Ĥ(r,r)_l - c_l = x² A_l + 2x B_l` with `A_l = Ĥ(v,v)_l`, `B_l = Ĥ(a,v)_l`, so
//! `U = Σ_l u_l (x⁴ A_l² + 4x³ A_l B_l + 4x² B_l²)` and `ẍ + ω²x + αx² + Γx³ = 0` with
//! `ω² = vᵀ diag(ω_s²) v + 8 Σ_l u_l B_l²` (the shell's stiffness), `α = 12 Σ_l u_l A_l B_l`,
//! `Γ = 4 Σ_l u_l A_l²`. Second-order backbone (Nayfeh & Mook, Nonlinear Oscillations, 1979,
//! eq. 4.1.32; Touzé, Thomas & Chaigne, J. Sound Vib. 273, 2004): `ω_NL = ω(1 + T A²)`,
//! `T = 3Γ/(8ω²) - 5α²/(12ω⁴)`, `A` the first harmonic's amplitude (= half the peak-to-peak
//! excursion to `O(A³)`: the quadratic term's offset and second harmonic shift the maximum and
//! the minimum by the same `-αA²/(3ω²)`).
//!
//! **Normal form.** In the shell's linear modes `y_m` (unit eigenvectors `V_m`, pulsations
//! `ω_m`), the cubic part of `U`, `4 Σ_l u_l Ĥ(q,q)_l Ĥ(a,q)_l`, puts `g_m y_p²` in mode `m`'s
//! equation and `2 g_m y_p y_m` in mode `p`'s, `g_m = 4 Σ_l u_l (A_l Ĥ(a,V_m)_l
//! + 2 Ĥ(v,V_m)_l B_l)` (`g_p = α`). The invariant manifold `y_m = a_m R² + b_m Ṙ²`,
//! `b_m = 2g_m/(ω_m²(ω_m² - 4ω²))`, `a_m = -(ω_m² - 2ω²) b_m/2`, leaves
//! `R̈ + ω²R + (Γ + 2Σ_m g_m a_m) R³ + 2Σ_m g_m b_m R Ṙ² = 0`, whence
//! `T = [3Γ + Σ_m 2g_m² (8ω² - 3ω_m²)/(ω_m²(ω_m² - 4ω²))]/(8ω²)` (the normal-form
//! reduction of Touzé, Thomas & Chaigne 2004, derived here for this potential; the `m = p`
//! term is the single mode's `-5α²/(12ω⁴)`). Only axisymmetric modes have `g_m ≠ 0`.
//!
//! **Full model.** An axisymmetric start stays axisymmetric (the selection rules zero every
//! coupling from `n = 0` modes into the others), so the model runs on the `n = 0` modes of the
//! mirror basis (checked against the whole basis below). Figures print with `--nocapture`.

use std::sync::Arc;

use crate::plate_shell::pulsation;
use faer::{Mat, Side};
use noether::modal::circular::{CircularEdge, Parity, PlateModes};
use noether::modal::shell::{shell_stiffness, CapCoupling, Imperfection};
use noether::modal::CircularPlateSpec;
use noether::models::plate::{DenseCoupling, LinearSolve, PlateModel, PlateParams, PlateScheme};

/// Plate thickness in units of the radius.
const TH: f64 = 0.01;
const NU: f64 = 0.3;

/// The free plate's mirror basis of `n_phi × n_psi` modes, ν = 0.3.
fn basis(n_phi: usize, n_psi: usize) -> PlateModes {
    let spec = CircularPlateSpec::new(CircularEdge::Free, NU, n_phi, n_psi, None)
        .unwrap()
        .mirror_symmetric();
    PlateModes::build(&spec).unwrap()
}

/// The axisymmetric subsystem of a basis with a cap of curvature `kappa`, and the shell's
/// linear modes in it.
struct Axi {
    /// Indices of the `n = 0` transverse modes in the basis.
    phi: Vec<usize>,
    /// Flat pulsations `λ²` of those modes (rad/s).
    omega: Vec<f64>,
    /// `ζ⁴` of the `n = 0` in-plane modes.
    zeta4: Vec<f64>,
    /// Dense `Ĥ^l_{ij}` on the subset, `[(l n + i) n + j]`.
    h: Vec<f64>,
    /// The cap (units of `q`).
    a: Vec<f64>,
    /// `Eh` (units of `D/a²`).
    eh: f64,
    /// Shell pulsations, ascending (rad/s).
    omega_shell: Vec<f64>,
    /// Unit shell eigenvectors, same order.
    v: Vec<Vec<f64>>,
}

impl Axi {
    fn new(modes: &PlateModes, kappa: f64) -> Self {
        let phi: Vec<usize> = (0..modes.phi.len())
            .filter(|&s| modes.phi[s].n == 0 && modes.phi[s].parity == Parity::Cos)
            .collect();
        let psi: Vec<usize> = (0..modes.psi.len())
            .filter(|&l| modes.psi[l].n == 0 && modes.psi[l].parity == Parity::Cos)
            .collect();
        let n = phi.len();
        let mut h = vec![0.0; psi.len() * n * n];
        for (l, &lp) in psi.iter().enumerate() {
            for (i, &ip) in phi.iter().enumerate() {
                for (j, &jp) in phi.iter().enumerate() {
                    h[(l * n + i) * n + j] = modes.coupling.get(lp, ip, jp).unwrap_or(0.0);
                }
            }
        }
        let full = Imperfection::spherical_cap(kappa).unwrap().project(modes);
        let mut s = Self {
            omega: phi.iter().map(|&i| modes.lambda2[i]).collect(),
            zeta4: psi.iter().map(|&l| modes.zeta4[l]).collect(),
            a: phi.iter().map(|&i| TH * full[i]).collect(),
            phi,
            h,
            eh: 12.0 * (1.0 - NU * NU) / (TH * TH),
            omega_shell: vec![],
            v: vec![],
        };
        let k = s.stiffness();
        let evd = Mat::<f64>::from_fn(n, n, |r, c| k[r * n + c])
            .self_adjoint_eigen(Side::Lower)
            .unwrap();
        let (ev, u) = (evd.S().column_vector(), evd.U());
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&x, &y| ev[x].total_cmp(&ev[y]));
        for m in order {
            s.omega_shell.push(ev[m].sqrt());
            s.v.push((0..n).map(|r| u[(r, m)]).collect());
        }
        s
    }

    fn n(&self) -> usize {
        self.omega.len()
    }

    /// `u_l = Eh/(8ζ_l⁴)`.
    fn u(&self, l: usize) -> f64 {
        self.eh / (8.0 * self.zeta4[l])
    }

    /// `Ĥ(x, y)_l = Σ_ij Ĥ^l_{ij} x_i y_j` for every `l`.
    fn contract(&self, x: &[f64], y: &[f64]) -> Vec<f64> {
        let n = self.n();
        let dot = |row: &[f64], z: &[f64]| row.iter().zip(z).map(|(a, b)| a * b).sum::<f64>();
        self.h
            .chunks_exact(n * n)
            .map(|hl| {
                hl.chunks_exact(n)
                    .zip(x)
                    .map(|(r, &xi)| xi * dot(r, y))
                    .sum()
            })
            .collect()
    }

    /// The model's linear stiffness `diag(ω_s²) + Σ_l 8u_l g_l g_lᵀ`, `g_l = Ĥ^l a`
    /// (row-major `n × n`).
    fn stiffness(&self) -> Vec<f64> {
        let n = self.n();
        let mut k = vec![0.0; n * n];
        for s in 0..n {
            k[s * n + s] = self.omega[s] * self.omega[s];
        }
        for l in 0..self.zeta4.len() {
            let g: Vec<f64> = (0..n)
                .map(|s| {
                    (0..n)
                        .map(|t| self.h[(l * n + s) * n + t] * self.a[t])
                        .sum()
                })
                .collect();
            let w = 8.0 * self.u(l);
            for s in 0..n {
                for t in 0..n {
                    k[s * n + t] += w * g[s] * g[t];
                }
            }
        }
        k
    }

    /// Single-mode coefficients of the fundamental axisymmetric mode: `(ω, α, Γ)`.
    fn single_mode(&self) -> (f64, f64, f64) {
        let v = &self.v[0];
        let (a, b) = (self.contract(v, v), self.contract(&self.a, v));
        let alpha = (0..a.len()).map(|l| 12.0 * self.u(l) * a[l] * b[l]).sum();
        let gamma = (0..a.len()).map(|l| 4.0 * self.u(l) * a[l] * a[l]).sum();
        (self.omega_shell[0], alpha, gamma)
    }

    /// `g_m` of every shell mode (the coefficient of `y_p²` in mode `m`'s equation).
    fn quadratic_couplings(&self) -> Vec<f64> {
        let v = &self.v[0];
        let (a, b) = (self.contract(v, v), self.contract(&self.a, v));
        self.v
            .iter()
            .map(|vm| {
                let (bm, c) = (self.contract(&self.a, vm), self.contract(v, vm));
                (0..a.len())
                    .map(|l| 4.0 * self.u(l) * (a[l] * bm[l] + 2.0 * c[l] * b[l]))
                    .sum()
            })
            .collect()
    }

    /// Normal-form `T` with every quadratic coupling (module docs).
    fn t_normal_form(&self) -> f64 {
        let (w, _, gamma) = self.single_mode();
        let w2 = w * w;
        let sum: f64 = self
            .quadratic_couplings()
            .iter()
            .zip(&self.omega_shell)
            .map(|(&g, &wm)| {
                let m2 = wm * wm;
                2.0 * g * g * (8.0 * w2 - 3.0 * m2) / (m2 * (m2 - 4.0 * w2))
            })
            .sum();
        (3.0 * gamma + sum) / (8.0 * w2)
    }

    /// The lossless conservative-exact model on the subset at `fs` (Hz), on its rest shape.
    fn model(&self, fs: f64) -> PlateModel<DenseCoupling> {
        let n = self.n();
        let np = self.zeta4.len();
        let coupling = DenseCoupling::new(n, np, self.h.clone()).unwrap();
        let params = PlateParams {
            omega: self.omega.clone(),
            zeta4: self.zeta4.clone(),
            rho_h: 1.0,
            e_h: self.eh,
            coupling_scale: 1.0,
            fs,
            damping: vec![0.0; n],
            scheme: PlateScheme::ConservativeExact,
            solve: LinearSolve::Auto,
        };
        let mut p = PlateModel::new(&params, Arc::new(coupling), vec![1.0; n], vec![]).unwrap();
        p.set_rest_shape(&self.a).unwrap();
        p
    }

    /// Free vibration started at rest on `x0 v` (units of `q`), or on the second-order
    /// invariant manifold through it, for `periods` linear periods at `steps` steps per
    /// period: `(pulsation, amplitude)` of `y = vᵀq`, the amplitude half its peak-to-peak
    /// excursion.
    fn free_vibration(&self, x0: f64, periods: f64, steps: f64, start: Start) -> (f64, f64) {
        let w = self.omega_shell[0];
        let fs = steps * w / std::f64::consts::TAU;
        let mut p = self.model(fs);
        let v = &self.v[0];
        let mut q0: Vec<f64> = v.iter().map(|x| x0 * x).collect();
        if start == Start::Manifold {
            let modes = self.quadratic_couplings();
            for ((&g, &wm), vm) in modes.iter().zip(&self.omega_shell).zip(&self.v) {
                let m2 = wm * wm;
                let am = -(m2 - 2.0 * w * w) * g / (m2 * (m2 - 4.0 * w * w));
                for (q, x) in q0.iter_mut().zip(vm) {
                    *q += am * x0 * x0 * x;
                }
            }
        }
        p.set_state(&q0, &vec![0.0; q0.len()]).unwrap();
        let count = (periods * steps) as usize;
        let mut y = Vec::with_capacity(count);
        for _ in 0..count {
            p.step(0.0).unwrap();
            y.push(p.q().iter().zip(v).map(|(q, v)| q * v).sum::<f64>());
        }
        let hi = y.iter().fold(f64::MIN, |m, &x| m.max(x));
        let lo = y.iter().fold(f64::MAX, |m, &x| m.min(x));
        (pulsation(&y, 1.0 / fs), 0.5 * (hi - lo))
    }
}

/// How a free vibration starts (at rest in both cases).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Start {
    /// `q = x0 v`: the other modes start at zero and then ring at their own frequencies
    /// (amplitude `O(x0²)`); near a 2:1 internal resonance they beat with mode `p` for many
    /// periods and bias a measurement of finite length.
    Plain,
    /// On the normal form's invariant manifold: `y_p = x0 + a_p x0²`, `y_m = a_m x0²` (the
    /// velocity term `b_m Ṙ²` vanishes at rest), so the other modes only follow `p`.
    Manifold,
}

/// Single-mode `T = 3Γ/(8ω²) - 5α²/(12ω⁴)`.
fn t_single(w: f64, alpha: f64, gamma: f64) -> f64 {
    3.0 * gamma / (8.0 * w * w) - 5.0 * alpha * alpha / (12.0 * w.powi(4))
}

/// The measured `T` of the simulated model in units of `1/TH²` (amplitudes in thicknesses):
/// free vibrations at `a1` and `a1/2` thicknesses against one at `10⁻⁶` (the scheme's own
/// linear pulsation `ω0`), fitted as `ω/ω0 - 1 = T A² + c A⁴` (the `A⁴` term is the next
/// order of the backbone; two amplitudes remove it).
fn measured_t(axi: &Axi, a1: f64, periods: f64, steps: f64, start: Start) -> f64 {
    let (w0, _) = axi.free_vibration(1e-6 * TH, periods, steps, Start::Plain);
    let (w1, m1) = axi.free_vibration(a1 * TH, periods, steps, start);
    let (w2, m2) = axi.free_vibration(0.5 * a1 * TH, periods, steps, start);
    let (e1, e2) = (w1 / w0 - 1.0, w2 / w0 - 1.0);
    let (s1, s2) = ((m1 / TH).powi(2), (m2 / TH).powi(2));
    let c = (e1 / s1 - e2 / s2) / (s1 - s2);
    e1 / s1 - c * s1
}

/// `κ` in `[lo, hi]` where `t(κ)` changes sign, by bisection to `tol` relative.
fn sign_change(mut lo: f64, mut hi: f64, tol: f64, t: impl Fn(f64) -> f64) -> f64 {
    let t_lo = t(lo);
    assert!(t_lo * t(hi) < 0.0, "no sign change in [{lo}, {hi}]");
    while hi - lo > tol * lo {
        let mid = 0.5 * (lo + hi);
        if t(mid) * t_lo > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The 1-DOF oscillator `ẍ + ω²x + αx² + Γx³ = 0` started at rest at `x0`, by classical
/// Runge-Kutta at `steps` steps per linear period for `periods` periods: `(pulsation,
/// amplitude)` with the amplitude half the peak-to-peak excursion.
fn oscillator(w: f64, alpha: f64, gamma: f64, x0: f64, periods: f64, steps: f64) -> (f64, f64) {
    let h = std::f64::consts::TAU / (w * steps);
    let acc = |x: f64| -(w * w * x + alpha * x * x + gamma * x * x * x);
    let (mut x, mut v) = (x0, 0.0);
    let count = (periods * steps) as usize;
    let mut xs = Vec::with_capacity(count);
    for _ in 0..count {
        let (k1x, k1v) = (v, acc(x));
        let (k2x, k2v) = (v + 0.5 * h * k1v, acc(x + 0.5 * h * k1x));
        let (k3x, k3v) = (v + 0.5 * h * k2v, acc(x + 0.5 * h * k2x));
        let (k4x, k4v) = (v + h * k3v, acc(x + h * k3x));
        x += h / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        xs.push(x);
    }
    let hi = xs.iter().fold(f64::MIN, |m, &x| m.max(x));
    let lo = xs.iter().fold(f64::MAX, |m, &x| m.min(x));
    (pulsation(&xs, h), 0.5 * (hi - lo))
}

/// The `x²` term of the single-mode potential, `8 Σ_l u_l Ĥ(a,V_m)_l²`, is the shell's linear
/// stiffness minus the flat part, `V_mᵀ (K - diag(λ⁴)) V_m` with `K` from `shell_stiffness`
/// (the whole mirror basis, the same projection), for every axisymmetric shell mode at
/// κ = 5 and 20. Tolerance 1e-12 of `ω_m²`: two evaluations of the same sums in a different
/// order, the flat part `λ⁴` (up to 1e8 for the highest modes) cancelled (measured 1.4e-13 at
/// κ = 5, 2.2e-14 at κ = 20). A potential with `u_l = Eh/(4ζ_l⁴)` (a factor 2 off) fails by
/// 0.44.
#[test]
fn quadratic_term_is_the_shells_linear_stiffness() {
    let modes = basis(160, 80);
    let n_all = modes.phi.len();
    for kappa in [5.0, 20.0] {
        let axi = Axi::new(&modes, kappa);
        let imp = Imperfection::spherical_cap(kappa).unwrap();
        let k = shell_stiffness(&modes, &imp, CapCoupling::ModalProjection).unwrap();
        let mut worst = 0.0f64;
        for (vm, &wm) in axi.v.iter().zip(&axi.omega_shell) {
            let b = axi.contract(&axi.a, vm);
            let ours: f64 = (0..b.len()).map(|l| 8.0 * axi.u(l) * b[l] * b[l]).sum();
            let mut theirs = 0.0;
            for (r, &i) in axi.phi.iter().enumerate() {
                for (c, &j) in axi.phi.iter().enumerate() {
                    let flat = if i == j {
                        axi.omega[r] * axi.omega[r]
                    } else {
                        0.0
                    };
                    theirs += vm[r] * (k[i * n_all + j] - flat) * vm[c];
                }
            }
            worst = worst.max((ours - theirs).abs() / (wm * wm));
            // And the flat part plus the x² term is the shell's ω².
            let flat: f64 = (0..vm.len()).map(|r| (axi.omega[r] * vm[r]).powi(2)).sum();
            worst = worst.max(((flat + ours) / (wm * wm) - 1.0).abs());
        }
        println!("κ = {kappa}: x² term against shell_stiffness, worst {worst:.2e}");
        assert!(worst < 1e-12, "κ = {kappa}: {worst}");
    }
}

/// The second-order backbone `T = 3Γ/(8ω²) - 5α²/(12ω⁴)` (Nayfeh & Mook eq. 4.1.32) against
/// the 1-DOF oscillator integrated by Runge-Kutta (400 steps per period, frequency error
/// `O(h⁴)` ≈ 1e-10), for a pure cubic, a pure quadratic and the shell's κ = 5 coefficients
/// (units of thicknesses). `T` measured from `ω(A)/ω - 1` at two amplitudes with `|T| A² ≈
/// 1e-3`, the `A⁴` term fitted out; tolerance 1e-3 relative (the next order is `(T A²)²`,
/// 1e-3 of `T A²` before the fit and far less after; measured below 5e-6). The quadratic's
/// coefficient with the wrong sign (`+5/12`) fails by 200 %.
#[test]
fn second_order_backbone_of_the_one_dof_oscillator() {
    let axi = Axi::new(&basis(160, 80), 5.0);
    let (w, alpha, gamma) = axi.single_mode();
    for (w, alpha, gamma) in [
        (1.0, 0.0, 1.0),
        (1.0, 1.0, 0.0),
        (w, alpha * TH, gamma * TH * TH),
    ] {
        let t = t_single(w, alpha, gamma);
        let a1 = (1e-3 / t.abs()).sqrt();
        let (w1, m1) = oscillator(w, alpha, gamma, a1, 40.0, 400.0);
        let (w2, m2) = oscillator(w, alpha, gamma, 0.5 * a1, 40.0, 400.0);
        let (e1, e2) = (w1 / w - 1.0, w2 / w - 1.0);
        let (s1, s2) = (m1 * m1, m2 * m2);
        let c = (e1 / s1 - e2 / s2) / (s1 - s2);
        let measured = e1 / s1 - c * s1;
        println!("ω {w:.4}, α {alpha:.4}, Γ {gamma:.4}: T {t:.6}, measured {measured:.6}");
        assert!((measured / t - 1.0).abs() < 1e-3, "{measured} vs {t}");
    }
}

/// The axisymmetric subspace is invariant: the model on the whole mirror basis (160 × 80)
/// started on `x0 v` at one thickness (strongly nonlinear: `|T̃| A² ≈ 0.1`) and the model on
/// its `n = 0` modes only give the same `vᵀq` over 4000 steps at κ = 10, and the other modes
/// stay at zero. Tolerance 1e-9 thicknesses: round-off of two different linear solves
/// (Woodbury on 80 in-plane modes against 8) over 4000 nonlinear steps (measured 3.7e-13; the
/// other modes stay exactly 0). Dropping the last `n = 0` in-plane mode from the subset gives
/// 1.4e-4.
#[test]
fn axisymmetric_subspace_is_invariant() {
    let modes = basis(160, 80);
    let kappa = 10.0;
    let axi = Axi::new(&modes, kappa);
    let n_all = modes.phi.len();
    let fs = 200.0 * axi.omega_shell[0] / std::f64::consts::TAU;
    let mut sub = axi.model(fs);
    let params = PlateParams {
        omega: modes.lambda2.clone(),
        zeta4: modes.zeta4.clone(),
        rho_h: 1.0,
        e_h: axi.eh,
        coupling_scale: 1.0,
        fs,
        damping: vec![0.0; n_all],
        scheme: PlateScheme::ConservativeExact,
        solve: LinearSolve::Auto,
    };
    let coupling = Arc::new(modes.coupling.clone());
    let mut whole = PlateModel::new(&params, coupling, vec![1.0; n_all], vec![]).unwrap();
    let cap = Imperfection::spherical_cap(kappa).unwrap().project(&modes);
    let cap: Vec<f64> = cap.iter().map(|x| TH * x).collect();
    whole.set_rest_shape(&cap).unwrap();
    let v = &axi.v[0];
    let mut q0 = vec![0.0; n_all];
    for (&i, &x) in axi.phi.iter().zip(v) {
        q0[i] = TH * x;
    }
    let q0_sub: Vec<f64> = v.iter().map(|x| TH * x).collect();
    whole.set_state(&q0, &vec![0.0; n_all]).unwrap();
    sub.set_state(&q0_sub, &vec![0.0; q0_sub.len()]).unwrap();
    let (mut diff, mut other) = (0.0f64, 0.0f64);
    for _ in 0..4000 {
        whole.step(0.0).unwrap();
        sub.step(0.0).unwrap();
        let y_sub: f64 = sub.q().iter().zip(v).map(|(q, v)| q * v).sum();
        let y_whole: f64 = axi.phi.iter().zip(v).map(|(&i, v)| whole.q()[i] * v).sum();
        diff = diff.max((y_sub - y_whole).abs() / TH);
        for (s, &q) in whole.q().iter().enumerate() {
            if !axi.phi.contains(&s) {
                other = other.max(q.abs() / TH);
            }
        }
    }
    println!("vᵀq difference {diff:.2e}, largest other mode {other:.2e} (thicknesses)");
    assert!(diff < 1e-9 && other < 1e-9, "{diff} {other}");
}

/// The simulated backbone (conservative-exact, 400 steps per period, lossless) follows the
/// normal form with every quadratic coupling, not the single mode: measured `T` against the
/// normal form's to 2e-3 relative at κ = 0, 5, 15 and 20, started on the invariant manifold
/// (amplitudes with `|T̃| A² = 1e-4` and half that, `A⁴` fitted out; next to an internal
/// resonance the second-order backbone only holds for amplitudes small against the detuning).
/// Error budget: the scheme's `O((ωh)²)` warping of the nonlinear frequency (`(2π/400)²` =
/// 2.5e-4), the fit's remainder, and none from the basis (theory and model share it);
/// measured 7.6e-5, 1.1e-4, 3.7e-4, 8.2e-5. The normal form without the other modes (the
/// single mode) fails by 8.4 % at κ = 5. The single mode is off by 8 % at κ = 5 and 29 % at
/// κ = 15 (next to the 2:1 internal
/// resonance with the (0,3) mode, `ω_(0,3) = 2.001 ω`), where the plain start `x0 v` (the
/// (0,3) mode then rings freely and beats with the fundamental for thousands of periods)
/// measures -0.0544 instead of -0.0734 over 60 periods: checked to differ by more than 10 %.
#[test]
fn simulated_backbone_follows_the_normal_form() {
    let modes = basis(160, 80);
    for kappa in [0.0, 5.0, 15.0, 20.0] {
        let axi = Axi::new(&modes, kappa);
        let (w, alpha, gamma) = axi.single_mode();
        let t1 = t_single(w, alpha, gamma) * TH * TH;
        let tn = axi.t_normal_form() * TH * TH;
        let a1 = (1e-4 / tn.abs()).sqrt();
        let tm = measured_t(&axi, a1, 40.0, 400.0, Start::Manifold);
        println!(
            "κ = {kappa}: T̃ single {t1:.5}, normal form {tn:.5}, model {tm:.5} (error {:.1e})",
            tm / tn - 1.0
        );
        assert!((tm / tn - 1.0).abs() < 2e-3, "κ = {kappa}: {tm} vs {tn}");
        if kappa == 15.0 {
            let plain = measured_t(&axi, a1, 60.0, 400.0, Start::Plain);
            println!("κ = {kappa}: plain start {plain:.5}");
            assert!((plain / tn - 1.0).abs() > 0.1, "{plain} vs {tn}");
        }
        if kappa > 0.0 {
            assert!((t1 / tn - 1.0).abs() > 0.01, "κ = {kappa}: {t1} vs {tn}");
        }
    }
}

/// The `κ` in `[lo, hi]` of the 2:1 internal resonance `ω_m = 2ω` of the `m`-th shell mode
/// (axisymmetric, `m = 1` the (0,2) mode) and the end of the hardening window just past it
/// (the normal form's `T` comes down from `+∞` and crosses zero).
fn resonance_window(modes: &PlateModes, m: usize, lo: f64, hi: f64) -> (f64, f64) {
    let ratio = |k: f64| {
        let axi = Axi::new(modes, k);
        axi.omega_shell[m] / axi.omega_shell[0] - 2.0
    };
    let k_res = sign_change(lo, hi, 1e-9, ratio);
    let k_end = sign_change(k_res * (1.0 + 1e-7), hi, 1e-7, |k| {
        Axi::new(modes, k).t_normal_form()
    });
    (k_res, k_end)
}

/// Where the type changes. The main transition from hardening (flat plate) to softening:
/// single mode κ = 1.3733, normal form 1.3651 (bisection to 1e-4; checked within 1 % of each
/// other), and the simulated `T̃` has the normal form's sign 2 % on either side (measured
/// +0.0112 and -0.0108, far above the measurement's resolution, about 1e-5). Then a narrow
/// hardening window just past the 2:1 internal resonance with the (0,2) mode (κ = 5.9343 to
/// 6.0001) that the single mode misses: in its middle `T̃` is +0.2324 (normal form) and
/// +0.2330 (simulated, hardening) while the single mode's is -0.2285. A normal form without
/// the other modes (the single mode) finds no window and fails.
#[test]
fn type_changes_where_the_normal_form_says() {
    let modes = basis(160, 80);
    let single = |k: f64| {
        let (w, a, g) = Axi::new(&modes, k).single_mode();
        t_single(w, a, g)
    };
    let normal = |k: f64| Axi::new(&modes, k).t_normal_form();
    let k1 = sign_change(0.5, 3.0, 1e-4, single);
    let kn = sign_change(0.5, 3.0, 1e-4, normal);
    let below = measured_t(
        &Axi::new(&modes, 0.98 * kn),
        0.2,
        40.0,
        400.0,
        Start::Manifold,
    );
    let above = measured_t(
        &Axi::new(&modes, 1.02 * kn),
        0.2,
        40.0,
        400.0,
        Start::Manifold,
    );
    println!(
        "main transition: single mode κ = {k1:.4}, normal form {kn:.4}; model T̃ {:.4} at \
         0.98 κ, {:.4} at 1.02 κ",
        below, above
    );
    assert!((k1 / kn - 1.0).abs() < 0.01 && below > 0.0 && above < 0.0);
    let (k_res, k_end) = resonance_window(&modes, 1, 5.0, 7.0);
    let mid = 0.5 * (k_res + k_end);
    let axi = Axi::new(&modes, mid);
    let tm = measured_t(&axi, 0.002, 60.0, 400.0, Start::Manifold);
    let tn = axi.t_normal_form() * TH * TH;
    let t1 = single(mid) * TH * TH;
    println!(
        "(0,2) 2:1 resonance at κ = {k_res:.4}, hardening up to {k_end:.4}; at {mid:.4}: \
         T̃ single {t1:.4}, normal form {tn:.4}, model {tm:.4}"
    );
    assert!(tn > 0.0 && tm > 0.0 && t1 < 0.0, "{t1} {tn} {tm}");
}

/// The table and figure of `docs/models.md` (ignored tests).
#[path = "plate_shell_backbone_table.rs"]
mod table;
