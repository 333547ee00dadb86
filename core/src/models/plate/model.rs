//! [`PlateModel`]: state, lifecycle and the per-step update of the four plate schemes
//! (equations and energy proofs in [`super`]).
//!
//! Lifecycle: [`PlateModel::new`] validates and allocates everything (worker thread);
//! [`PlateModel::set_state`] / [`PlateModel::reset`] set initial conditions (no allocation on
//! success); [`PlateModel::step`] / [`PlateModel::process`] run on the audio thread: no
//! allocation, no lock, bounded work (a fixed number of passes over the modes plus one Cholesky
//! factorisation of fixed size).

use std::fmt;
use std::sync::Arc;

use super::closure::{
    TruncationClosure, DEFAULT_LAYER, DEFAULT_STRENGTH, DEFAULT_TIME_CONSTANT, MAX_STRENGTH,
};
use super::contact_residual::ContactResidual;
use super::coupling::ModalCoupling;
use super::energy::PlateEnergy;
use super::excitation::{PickupKind, PickupWeights};
use super::hand_damper::Hand;
use super::linalg::{Route, SpdSolver};
use super::params::{LinearSolve, PlateParams, PlateScheme};
use super::partial_sums::{all_finite, lane_sum};
use super::sav::SavStep;
use super::step_board::StepBoard;
use super::step_join::StepJoin;
use crate::error::{check_finite, ParamError};
use crate::models::sav_relaxation::SavRelaxation;
use free_response::free_response_backward;

/// The state became non-finite (or the linear system lost positive definiteness, which only
/// non-finite values can cause): the model outputs zeros until [`PlateModel::reset`] or
/// [`PlateModel::set_state`].
///
/// Returned on the audio thread; plain `Copy` data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Diverged {
    /// Step index `n` at which the update failed.
    pub step: u64,
}

impl fmt::Display for Diverged {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "plate state became non-finite at step {}", self.step)
    }
}

impl std::error::Error for Diverged {}

/// Sample types [`PlateModel::process`] can write (conversion runs on the audio thread).
pub trait OutputSample: Copy {
    /// Converts one output value (rounding for `f32`).
    fn from_f64(x: f64) -> Self;
}

impl OutputSample for f32 {
    fn from_f64(x: f64) -> Self {
        x as f32
    }
}

impl OutputSample for f64 {
    fn from_f64(x: f64) -> Self {
        x
    }
}

/// A modal von Kármán plate advanced by one of the [`PlateScheme`]s.
///
/// Struct-of-arrays state `q(n-1)`, `q(n)` (and the buffer for `q(n+1)`), scratch for the
/// coupling matrix and the solve, all allocated by [`Self::new`]. Built on a worker thread, then
/// moved to (and owned by) the audio thread, which calls [`Self::step`] / [`Self::process`]; the
/// coupling is shared read-only through the `Arc`. Generic over the coupling type (`C` may be
/// `dyn ModalCoupling`, the default, or a concrete type for static dispatch).
pub struct PlateModel<C: ModalCoupling + ?Sized = dyn ModalCoupling> {
    coupling: Arc<C>,
    scheme: PlateScheme,
    h: f64,
    rho_h: f64,
    /// Physical `ω_s` (rad/s) and `c_s` (1/s), for initial conditions.
    omega: Vec<f64>,
    damping: Vec<f64>,
    /// `ω̃_s²` and `c̃_s` of the linear part (θ = 1 or exact).
    omega_sq: Vec<f64>,
    c_eff: Vec<f64>,
    /// `a_s = 1 + c̃_s h/2`, its inverse, `b_s = 2 - h²ω̃_s²`, `d_s = 1 - c̃_s h/2`.
    a: Vec<f64>,
    inv_a: Vec<f64>,
    b: Vec<f64>,
    d: Vec<f64>,
    /// `h² D_l`, `h √D_l`, `Eh κ² / (8 ζ_l⁴)` with `D_l = κ² Eh / (4 ρh ζ_l⁴)`.
    dh2: Vec<f64>,
    e_sqrt: Vec<f64>,
    u_coef: Vec<f64>,
    force_weights: Vec<f64>,
    pickups: Vec<PickupWeights>,
    outputs: Vec<f64>,
    q_prev: Vec<f64>,
    q: Vec<f64>,
    q_next: Vec<f64>,
    /// `Ĥ(q(n), q(n-1))` and its successor `Ĥ(q(n+1), q(n))` (length `N_Ψ`).
    b_half: Vec<f64>,
    b_next: Vec<f64>,
    g: Vec<f64>,
    r: Vec<f64>,
    /// Scratch: `set_state`'s nonlinear force, and `step_with_mallet`'s unit-force response.
    f: Vec<f64>,
    w: Vec<f64>,
    /// Scratch of the coupling's `_with_scratch` kernels (`kernel_scratch_len` values,
    /// allocated in [`Self::new`]; audio thread).
    kscratch: Vec<f64>,
    solver: Option<SpdSolver>,
    /// Auxiliary state and scratch of the SAV scheme (`None` for the other schemes).
    sav: Option<SavStep>,
    /// The player's hand (a point damper, [`super::hand_damper`]); `c = 0` without one.
    hand: Hand,
    /// The modes above the truncation at the mallet's contact ([`super::contact_residual`];
    /// off unless [`Self::set_contact_residual`] set it).
    residual: ContactResidual,
    /// The static rest shape (flat unless [`Self::set_rest_shape`] set one).
    rest: RestShape,
    /// The damping of the top modes that takes a loud strike's pile-up ([`super::closure`];
    /// off unless [`Self::set_closure`] turned it on).
    closure: TruncationClosure,
    /// Energy the closure absorbed since the last [`Self::take_absorbed`] (J): what the band
    /// above the simulation ([`super::extension`]) receives.
    absorbed: f64,
    energy: PlateEnergy,
    /// Physical energy dissipated in the last step (J; damping and hand): the SAV
    /// relaxation's budget ([`crate::models::sav_relaxation`]).
    step_dissipated: f64,
    track_energy: bool,
    diverged: bool,
}

impl<C: ModalCoupling + 'static> PlateModel<C> {
    /// Shares each SAV step's coupling kernel with real-time helpers: the second half of the
    /// in-plane rows is offered on `board` and taken back after a bounded wait
    /// ([`super::step_board`]), or the kernel runs in one pass (`None`, the default). Returns
    /// whether the split is in use (as [`Self::set_step_join`]). Worker thread: allocates
    /// the job.
    pub fn set_step_board(&mut self, board: Option<Arc<StepBoard>>) -> bool {
        match self.sav.as_mut() {
            Some(sav) => sav.set_board(&self.coupling, board),
            None => false,
        }
    }
}

impl<C: ModalCoupling + ?Sized> PlateModel<C> {
    /// Validates `params` against the coupling's sizes and allocates the model, at rest.
    ///
    /// `force_weights[s] = Φ_s(x₀)` (1/m): the transverse modes at the excitation point, length
    /// `N_Φ`; the modal forcing is `p_s = Φ_s(x₀) F / ρh` for the force `F` (N) passed to
    /// [`Self::step`]. `pickups`: any number of outputs, each with `N_Φ` weights.
    /// Errors ([`ParamError`] naming field, value and allowed range): see
    /// [`PlateParams`]; also the θ = 1 stability limit `fs > ω_max / 2` and, for the exact linear
    /// part, `ω_s h` not at a multiple of `π`. Runs on a worker thread.
    pub fn new(
        params: &PlateParams,
        coupling: Arc<C>,
        force_weights: Vec<f64>,
        pickups: Vec<PickupWeights>,
    ) -> Result<Self, ParamError> {
        let (nf, np) = (coupling.n_phi(), coupling.n_psi());
        let v = params.validate(nf, np)?;
        check_weights("force_weights", &force_weights, nf)?;
        for (i, p) in pickups.iter().enumerate() {
            check_weights(&format!("pickups[{i}].weights"), &p.weights, nf)?;
        }
        let h = v.h;
        let (rho_h, kappa) = (params.rho_h, params.coupling_scale);
        let omega_sq: Vec<f64> = v.linear.iter().map(|c| c.omega_sq).collect();
        let c_eff: Vec<f64> = v.linear.iter().map(|c| c.damping).collect();
        let a: Vec<f64> = c_eff.iter().map(|c| 1.0 + 0.5 * c * h).collect();
        let dl: Vec<f64> = params
            .zeta4
            .iter()
            .map(|z| kappa * kappa * params.e_h / (4.0 * rho_h * z))
            .collect();
        let solver = match params.scheme {
            PlateScheme::StormerVerletExact | PlateScheme::SavExact => None,
            PlateScheme::ConservativeTheta1 | PlateScheme::ConservativeExact => {
                let route = match params.solve {
                    LinearSolve::Woodbury => Route::Woodbury,
                    LinearSolve::Direct => Route::Direct,
                    LinearSolve::Auto if np < nf => Route::Woodbury,
                    LinearSolve::Auto => Route::Direct,
                };
                Some(SpdSolver::new(route, nf, np))
            }
        };
        Ok(Self {
            scheme: params.scheme,
            h,
            rho_h,
            omega: params.omega.clone(),
            damping: params.damping.clone(),
            inv_a: a.iter().map(|x| 1.0 / x).collect(),
            b: omega_sq.iter().map(|w2| 2.0 - h * h * w2).collect(),
            d: c_eff.iter().map(|c| 1.0 - 0.5 * c * h).collect(),
            a,
            omega_sq,
            c_eff,
            dh2: dl.iter().map(|d| h * h * d).collect(),
            e_sqrt: dl.iter().map(|d| h * d.sqrt()).collect(),
            u_coef: params
                .zeta4
                .iter()
                .map(|z| params.e_h * kappa * kappa / (8.0 * z))
                .collect(),
            force_weights,
            outputs: vec![0.0; pickups.len()],
            pickups,
            q_prev: vec![0.0; nf],
            q: vec![0.0; nf],
            q_next: vec![0.0; nf],
            b_half: vec![0.0; np],
            b_next: vec![0.0; np],
            g: if params.scheme == PlateScheme::SavExact {
                Vec::new()
            } else {
                vec![0.0; nf * np]
            },
            r: vec![0.0; nf],
            f: vec![0.0; nf],
            w: vec![0.0; np],
            kscratch: vec![0.0; coupling.kernel_scratch_len()],
            solver,
            sav: (params.scheme == PlateScheme::SavExact).then(|| {
                let mut sav = SavStep::new(nf, np);
                sav.relaxation = SavRelaxation::default_at(h);
                sav
            }),
            hand: Hand::new(nf),
            residual: ContactResidual::default(),
            rest: RestShape::flat(nf, np),
            closure: TruncationClosure::new(nf),
            absorbed: 0.0,
            energy: PlateEnergy::default(),
            step_dissipated: 0.0,
            track_energy: true,
            diverged: false,
            coupling,
        })
    }

    /// Puts the plate at rest (`q(0) = q(-1) = 0`), clears energy accumulators and divergence.
    /// No allocation; any thread that owns the model.
    pub fn reset(&mut self) {
        for v in [&mut self.q_prev, &mut self.q, &mut self.q_next, &mut self.f] {
            v.fill(0.0);
        }
        self.b_half.fill(0.0);
        if let Some(sav) = self.sav.as_mut() {
            sav.restart(0.0);
        }
        self.outputs.fill(0.0);
        self.hand.force = 0.0;
        self.residual.reset();
        self.closure.reset();
        self.write_closure_coefficients();
        self.absorbed = 0.0;
        self.energy = PlateEnergy::default();
        self.step_dissipated = 0.0;
        self.diverged = false;
    }

    /// Sets the initial modal displacements `q(0) = q0` and velocities `q̇(0) = v0` (units of
    /// `q` and `q`/s) and rewinds to step 0.
    ///
    /// The second starting value is `q_s(-1) = q_s^{lin}(-h) + (h²/2) f_s(q0)`: the exact free
    /// response of the damped linear mode (`ω_s`, `c_s`) evaluated at `t = -h`, plus the Taylor
    /// term of the nonlinear acceleration `f_s = (κ/ρh) Σ E^s_{k,l} q0_k η_l(q0)`. Without
    /// coupling the exact-linear schemes then reproduce the exact solution at every sample.
    /// Errors: lengths `N_Φ`, finite values. No allocation on success.
    pub fn set_state(&mut self, q0: &[f64], v0: &[f64]) -> Result<(), ParamError> {
        let nf = self.q.len();
        check_weights("q0", q0, nf)?;
        check_weights("v0", v0, nf)?;
        self.reset();
        self.q.copy_from_slice(q0);
        // Nonlinear acceleration at q0 (Störmer-Verlet form): f = Σ_l G_{s,l} (-2 D_l) Ĥ(q0,q0)_l.
        self.nonlinear_force(1.0 / (self.h * self.h));
        let h = self.h;
        for s in 0..nf {
            let lin = free_response_backward(self.omega[s], self.damping[s], h, q0[s], v0[s]);
            self.q_prev[s] = lin + 0.5 * h * h * self.f[s];
        }
        self.refresh_b_half();
        if let Some(sav) = self.sav.as_mut() {
            // ψ(-½) = √(2u) with the conservative schemes' half-step u = Σ u_l Ĥ(q0, q(-1))_l²
            // (an O(h²)-consistent start; the same initial energy as those schemes).
            sav.restart(SavStep::psi_from(&self.u_coef, &self.b_half));
        }
        if self.track_energy {
            self.update_stored_energy(true);
        }
        Ok(())
    }

    /// Replaces the excitation weights `Φ_s(x₀)` (1/m), for example to move the strike point.
    /// No allocation. Errors: length `N_Φ`, finite values.
    pub fn set_force_weights(&mut self, weights: &[f64]) -> Result<(), ParamError> {
        check_weights("force_weights", weights, self.q.len())?;
        self.force_weights.copy_from_slice(weights);
        Ok(())
    }

    /// Shares each SAV step's coupling kernel between two jobs run by `join` (two halves of the
    /// in-plane rows; [`super::step_join`]), or runs it in one pass (`None`, the default).
    /// Returns whether the split is in use (the `sav` scheme, a coupling with a row-split
    /// kernel, at least two in-plane modes). Worker thread: allocates the second half's
    /// scratch.
    pub fn set_step_join(&mut self, join: Option<Arc<dyn StepJoin>>) -> bool {
        match self.sav.as_mut() {
            Some(sav) => sav.set_join(&*self.coupling, join),
            None => false,
        }
    }

    /// Whether each SAV step's second half is offered to real-time helpers
    /// ([`Self::set_step_board`]): the engine asks its workers to help only then. Any thread
    /// that owns the model.
    pub fn offers_step_halves(&self) -> bool {
        self.sav.as_ref().is_some_and(|s| s.offers_halves())
    }

    /// Sets how the SAV scheme's `ψ` is relaxed toward `√(2U(q))` each step
    /// ([`crate::models::sav_relaxation`]; default [`SavRelaxation::default_at`] the model's
    /// step; [`SavRelaxation::OFF`] gives the plain scheme). No effect on the other schemes.
    /// The relaxation's budget is the last step's dissipation, known only while the energy is
    /// tracked (otherwise it only removes energy). Any thread that owns the model.
    pub fn set_sav_relaxation(&mut self, relaxation: SavRelaxation) {
        if let Some(sav) = self.sav.as_mut() {
            sav.relaxation = relaxation;
        }
    }

    /// The SAV relaxation in use (`None` for the other schemes).
    pub fn sav_relaxation(&self) -> Option<SavRelaxation> {
        self.sav.as_ref().map(|s| s.relaxation)
    }

    /// Sets the strength of the truncation closure ([`super::closure`]: the top half-octave of
    /// modes is damped when a loud strike's cascade piles energy up there) as a multiple of the
    /// calibrated `β` ([`DEFAULT_STRENGTH`]): 1 is calibrated; 0, the default, turns it off and
    /// the model is the plain truncation, bit for bit. Its averages are forgotten. Errors:
    /// `strength` outside 0 to [`MAX_STRENGTH`] (the model is unchanged). Any thread that owns
    /// the model; no allocation on success, `O(N_Φ)`.
    pub fn set_closure(&mut self, strength: f64) -> Result<(), ParamError> {
        if !(0.0..=MAX_STRENGTH).contains(&strength) {
            return Err(ParamError::new(
                "closure",
                strength,
                format!("0 to {MAX_STRENGTH} (0 = off)"),
            ));
        }
        self.closure.configure(
            strength * DEFAULT_STRENGTH,
            DEFAULT_LAYER,
            DEFAULT_TIME_CONSTANT,
        );
        self.closure
            .retune(&self.omega, &self.omega_sq, &self.damping, self.h);
        self.write_closure_coefficients();
        Ok(())
    }

    /// Writes the closure's damping of the coming step into the layer's `a`, `1/a`, `d`.
    fn write_closure_coefficients(&mut self) {
        self.closure.write_coefficients(
            &self.c_eff,
            self.h,
            &mut self.a,
            &mut self.inv_a,
            &mut self.d,
        );
    }

    /// Returns the energy the truncation closure absorbed since the last call (J, ≥ 0; counted
    /// whether or not the energy is tracked) and starts the count again: the band above the
    /// simulation receives it ([`super::extension`]). Any thread that owns the model; O(1).
    pub fn take_absorbed(&mut self) -> f64 {
        std::mem::take(&mut self.absorbed)
    }

    /// Turns the per-step energy bookkeeping on (default) or off (saves `O(N_Φ)` work per step;
    /// [`Self::energy`] is then stale). Audio thread.
    pub fn set_energy_tracking(&mut self, on: bool) {
        self.track_energy = on;
    }

    /// Advances one step `n → n + 1` under the external force `force` = `F(n)` (N) applied
    /// through the force weights and the player's hand (if any, [`Self::set_hand`]; solved in
    /// closed form with the step), then updates the pickups and the energy.
    /// Audio thread: no allocation, bounded work.
    pub fn step(&mut self, force: f64) -> Result<(), Diverged> {
        if self.diverged {
            return Err(Diverged {
                step: self.energy.step,
            });
        }
        let fscale = self.h * self.h * force / self.rho_h;
        if self.scheme_step(fscale).is_err() {
            return Err(self.fail());
        }
        if self.hand.c > 0.0 {
            self.apply_hand(false);
            self.refresh_b_next();
        }
        self.finish_step(force)
    }

    /// The common end of a step once `q(n+1)` (and `Ĥ(q(n+1), q(n))` or `ψ(n+½)`) is in place
    /// under the force `force` = `F(n)`: divergence check, power, pickups, shift, energy.
    #[inline]
    fn finish_step(&mut self, force: f64) -> Result<(), Diverged> {
        if !all_finite(&self.q_next) || !force.is_finite() {
            return Err(self.fail());
        }
        let closure = if self.closure.is_on() {
            let n = self.q.len();
            let in_plane = self.closure.samples_gate().then(|| self.in_plane_split());
            let absorbed = self.closure.observe(
                (&self.q_next[..n], &self.q[..n], &self.q_prev[..n]),
                &self.omega_sq,
                in_plane,
                self.rho_h,
                self.h,
            );
            self.write_closure_coefficients();
            self.absorbed += absorbed;
            absorbed
        } else {
            0.0
        };
        if self.track_energy {
            self.update_power(force, closure);
        }
        let n = self.q.len();
        let (qn, qc, qp) = (&self.q_next[..n], &self.q[..n], &self.q_prev[..n]);
        for (out, p) in self.outputs.iter_mut().zip(&self.pickups) {
            let phi = &p.weights[..n];
            *out = match p.kind {
                PickupKind::Displacement => lane_sum(n, |s| phi[s] * qn[s]),
                PickupKind::VelocityCentred => {
                    lane_sum(n, |s| phi[s] * (qn[s] - qp[s])) * (0.5 / self.h)
                }
                PickupKind::VelocityBackward => lane_sum(n, |s| phi[s] * (qn[s] - qc[s])) / self.h,
            };
        }
        std::mem::swap(&mut self.q_prev, &mut self.q);
        std::mem::swap(&mut self.q, &mut self.q_next);
        std::mem::swap(&mut self.b_half, &mut self.b_next);
        self.energy.step += 1;
        if self.track_energy {
            self.update_stored_energy(false);
        }
        Ok(())
    }

    /// `b_next = Ĥ(q⁺, q) = Gᵀ q⁺` (H symmetric; curved: `Ĥ(r⁺, r) - c = Gᵀ q⁺ + σ`):
    /// `u(n+1)`, and the next step's `b(n)`.
    #[inline]
    fn update_b_next(&mut self) {
        let np = self.b_next.len();
        if self.rest.on {
            self.b_next.copy_from_slice(&self.rest.shift);
        } else {
            self.b_next.fill(0.0);
        }
        for (grow, &x) in self.g.chunks_exact(np.max(1)).zip(&self.q_next) {
            for (bn, &gv) in self.b_next.iter_mut().zip(grow) {
                *bn += gv * x;
            }
        }
    }

    /// Runs `force.len()` steps (or as many as `out` has room for), writing the pickups'
    /// outputs interleaved frame by frame (`out[frame * n_pickups + i]`). Returns the number of
    /// frames processed; on divergence the rest of `out` is zeroed and the error returned.
    /// Audio thread: no allocation.
    pub fn process<S: OutputSample>(
        &mut self,
        force: &[f64],
        out: &mut [S],
    ) -> Result<usize, Diverged> {
        let np = self.pickups.len();
        let frames = out
            .len()
            .checked_div(np)
            .map_or(force.len(), |room| force.len().min(room));
        for (n, &f) in force.iter().take(frames).enumerate() {
            if let Err(e) = self.step(f) {
                out[n * np..].fill(S::from_f64(0.0));
                return Err(e);
            }
            for (o, &v) in out[n * np..(n + 1) * np].iter_mut().zip(&self.outputs) {
                *o = S::from_f64(v);
            }
        }
        Ok(frames)
    }

    /// The pickups' outputs after the last step (see [`PickupKind`] for timing and units).
    pub fn outputs(&self) -> &[f64] {
        &self.outputs
    }

    /// Discrete energy terms and balance accumulators at the current step.
    pub fn energy(&self) -> PlateEnergy {
        let mut e = self.energy;
        if self.residual.is_on() {
            // The contact residual's spring with the linear potential, its dashpot with the
            // losses, and the mallet's work on it with the work (`contact_residual.rs`).
            let (stored, dissipated, work) = self.residual.energy();
            e.linear += stored;
            e.dissipated += dissipated;
            e.work += work;
        }
        e
    }

    /// Modal displacements `q(n)` at the current step.
    pub fn q(&self) -> &[f64] {
        &self.q
    }

    /// Modal displacements `q(n-1)`.
    pub fn q_prev(&self) -> &[f64] {
        &self.q_prev
    }

    /// Time step `h = 1/fs` (s).
    pub fn h(&self) -> f64 {
        self.h
    }

    /// The scheme this model runs.
    pub fn scheme(&self) -> PlateScheme {
        self.scheme
    }

    /// The linear-solver route in use (`Woodbury` or `Direct`), `None` for Störmer-Verlet.
    pub fn solve_route(&self) -> Option<LinearSolve> {
        self.solver.as_ref().map(|s| match s.route() {
            Route::Woodbury => LinearSolve::Woodbury,
            Route::Direct => LinearSolve::Direct,
        })
    }

    /// The SAV scheme's auxiliary variable `ψ(n-½)` (√J; `ψ²/2` is its in-plane energy, an
    /// `O(h²)` approximation of `U(q)`), `None` for the other schemes. Any thread owning the model.
    pub fn sav_psi(&self) -> Option<f64> {
        self.sav.as_ref().map(|s| s.psi)
    }

    /// The shared coupling.
    pub fn coupling(&self) -> &Arc<C> {
        &self.coupling
    }

    /// Whether the state became non-finite (see [`Diverged`]); the model then outputs zeros
    /// until [`Self::reset`] or [`Self::set_state`]. Any thread that owns the model.
    pub fn is_diverged(&self) -> bool {
        self.diverged
    }

    /// Marks the model diverged and zeroes its outputs.
    fn fail(&mut self) -> Diverged {
        self.diverged = true;
        self.outputs.fill(0.0);
        Diverged {
            step: self.energy.step,
        }
    }
}

/// Checks a per-mode vector: length `n`, finite entries.
fn check_weights(field: &str, w: &[f64], n: usize) -> Result<(), ParamError> {
    if w.len() != n {
        return Err(ParamError::new(
            format!("{field}.len"),
            w.len(),
            format!("n_phi = {n}"),
        ));
    }
    for (s, &x) in w.iter().enumerate() {
        check_finite(&format!("{field}[{s}]"), x)?;
    }
    Ok(())
}

mod energy_terms;
mod free_response;
mod hand_solve;
mod in_plane_split;
mod mallet_step;
mod rest_shape;
mod rest_state;
mod retune;
mod scheme_step;
use rest_state::RestShape;
pub use retune::Unstable;
