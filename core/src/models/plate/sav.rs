//! The explicit energy-quadratised ("scalar auxiliary variable", SAV) step of the plate
//! ([`super::PlateScheme::SavExact`]): no linear system beyond a rank-one update.
//!
//! # Scheme
//!
//! After S. Bilbao, M. Ducceschi, F. Zama, "Explicit exactly energy-conserving methods for
//! Hamiltonian systems", J. Comput. Phys. (2023) (energy quadratisation of a non-negative
//! potential), as M. Ducceschi, S. Bilbao use it for the geometrically exact string ("Simulation
//! of the geometrically exact nonlinear string via energy quadratisation", J. Sound Vib., 2022); here
//! applied to the modal von Kármán potential.
//! The in-plane potential of [`super`] is `U(q) = Σ_l u_l Ĥ(q, q)_l²` with
//! `u_l = Eh κ² / (8 ζ_l⁴)` (J per unit `Ĥ²`), `U ≥ 0`. Write it as `U = ψ²/2`,
//! `ψ = √(2U)`, and carry `ψ` as a state at half steps, with
//! `g(q) = ∇U(q) / √(2U(q))` (so `ψ̇ = g · q̇` on solutions and `∇U = ψ g`):
//!
//! ```text
//! ρh [δ_tt q_s + ω̃_s² q_s + c̃_s δ_{t.} q_s] = -μ_{t.}ψ(n) g_s(q(n)) + Φ_s F(n),
//! ψ(n+½) - ψ(n-½) = g(q(n)) · (q(n+1) - q(n-1)) / 2,
//! ```
//!
//! `μ_{t.}ψ(n) = (ψ(n+½) + ψ(n-½))/2`, linear part exact (`ω̃`, `c̃` of [`super::params`]).
//! `∇U_s = Σ_l 4 u_l Ĥ(q,q)_l Σ_k Ĥ^l_{s,k} q_k`: one fused pass over the tensor per step
//! (`ModalCoupling::quartic_gradient`; else `contract_eta` then `apply_force`), no coupling
//! matrix. The regularisation `ε` of the paper (`ψ = √(2U + ε)`) is taken as
//! 0: by Cauchy-Schwarz `|∇U| ≤ √(2U) · (2 Σ_l u_l |∇Ĥ(q,q)_l|²)^{1/2}`, so `g` is bounded by
//! `O(|q|)` and tends to 0 with `q`; it is set to 0 where `U(q) = 0` exactly (then `∇U = 0`).
//!
//! # Update (rank one)
//!
//! With `μ_{t.}ψ = ψ(n-½) + g·(q(n+1) - q(n-1))/4`, multiplying by `h²/ρh`:
//! `(A + β g gᵀ) q(n+1) = r`, `β = h²/(4ρh)`, `A = diag(1 + c̃h/2)`,
//! `r = (2 - h²ω̃²) q(n) - (1 - c̃h/2) q(n-1) + h² p(n) - (h²/ρh) g (ψ(n-½) - g·q(n-1)/4)`,
//! solved in increment form for `q(n+1) - q(n-1)` (see [`SavStep::step`]).
//! Sherman-Morrison: `q(n+1) = A⁻¹r - A⁻¹g · β gᵀA⁻¹r / (1 + β gᵀA⁻¹g)`; the denominator is
//! ≥ 1, so the update always exists. `O(N_Φ)` besides the two tensor passes.
//!
//! # Energy and stability
//!
//! Multiply by `δ_{t.} q(n)` and sum: the nonlinear term gives
//! `-μ_{t.}ψ · (ψ(n+½) - ψ(n-½))/h = -δ_{t+}(ψ²/2)`, so with
//! `𝔥(n) = t(n) + v(n) + ψ(n-½)²/2` (the `t`, `v` of [`super`])
//! `δ_{t+}𝔥 = -ρh Σ c̃ (δ_{t.}q)² + F Σ Φ δ_{t.}q` exactly, for any `q`: the modified energy
//! is conserved to round-off without losses and forcing. `ψ²/2 ≥ 0` holds unconditionally
//! (whatever the nonlinearity's size or the step), so stability rests only on `t + v` being
//! positive definite, which the exact linear part gives for every `h` with `ω_s h` away from
//! multiples of `π` (refused by validation, as for the other exact schemes). What is *not*
//! unconditional is accuracy: `ψ(n-½)` drifts from `√(2U(q))` by `O(h²)`, and the drift grows
//! with the nonlinearity's stiffness relative to `fs` (measured in `tests/plates/plate_sav.rs`).
//!
//! # Relaxation
//! Before each step `ψ(n-½)` is relaxed toward a second-order estimate `ψ*` of `√(2U)` at the
//! same half step ([`crate::models::sav_relaxation`]: the energy-constrained relaxation, its
//! allowance and its accounting). The estimate costs two `N_Φ` dot products and no tensor
//! pass. With `e_l(x, y) = Ĥ(x + a, y + a)_l - c_l` (`a` the rest shape, 0 flat; `U(q) =
//! Σ_l u_l e_l(q, q)²`), the gradient the step computes anyway gives the *mixed* energies
//!
//! ```text
//! U_→(n) = Σ_l u_l e_l(q(n), q(n)) e_l(q(n), q(n-1))         = ∇U(q(n))·r(n-1)/4 - Σ_l u_l e_l(n,n) c_l,
//! U_←(n) = Σ_l u_l e_l(q(n-1), q(n-1)) e_l(q(n-1), q(n))     = ∇U(q(n-1))·r(n)/4 - Σ_l u_l e_l(n-1,n-1) c_l,
//! ```
//!
//! (`r = q + a`; `∇U(q)·r = 4 Σ_l u_l e_l(q,q) Ĥ(r, ·)`), and `ψ* = √2 (U_→ U_←)^{1/4}`: the
//! geometric mean of the two, a symmetric `O(h²)` estimate of `U(q(n-½))`. Why this form and
//! not the mean of `√(2U(q(n-1)))` and `√(2U(q(n)))`: for one mode (`U = Γq⁴/4`) the scheme's
//! own `ψ` telescopes to `√(Γ/2) q(n) q(n-1)` exactly (`g = √(2Γ) q`, so
//! `ψ(n+½) - ψ(n-½) = √(Γ/2)(q(n)q(n+1) - q(n)q(n-1))`), and `ψ*` is exactly that: the
//! relaxation leaves a drift-free `ψ` alone, and moves only what drifts (the cross-mode
//! terms). The arithmetic mean differs from the scheme's `ψ` by its own `O(h²)` and was
//! measured to pull the single-mode Duffing backbone 4× off (`tests/plates/plate_scheme.rs`).
//! Where either mixed energy is negative, `q(n)` and `q(n-1)` lie on opposite sides of rest
//! (in the in-plane products that matter): the midpoint's energy is then 0 to the same order,
//! and so is the target. That case is not rare: the SAV scheme has a parasitic undamped orbit
//! at the Nyquist rate, `q(n) = -q(n-1)`, in which `ψ` does not change (`q(n+1) - q(n-1) = 0`),
//! the centred damping `c̃ δ_{t.}q` vanishes, and `ψ g` is the stiffness that puts the pattern
//! at `ωh = π`; a 16 s performance left a gong voice in it, silent (above the heard band) but
//! never ending. With the target 0 there `ψ` decays and the orbit with it. No relaxation on the
//! first step after a new state or a retune (the previous gradient is unknown or stale). The
//! energy the relaxation removes is reported per step ([`SavStep::take_relaxed`]) and counted
//! as dissipation by the model, so the power balance still closes to round-off.
//!
//! Threads: built with the model on a worker thread; [`SavStep::step`] runs on the audio thread
//! without allocating.

use super::coupling::ModalCoupling;
use super::linalg::dot;
use super::partial_sums::{lane_sum, lane_sums};
use super::step_board::{HalfJob, StepBoard};
use super::step_join::StepJoin;
use crate::models::sav_relaxation::{relax, RelaxationLedger, SavRelaxation};
use std::sync::Arc;
use std::time::Instant;

/// Scratch and auxiliary state of the SAV scheme (owned by the model, audio thread).
#[derive(Debug)]
pub(crate) struct SavStep {
    /// `ψ(n-½)` (√J).
    pub psi: f64,
    /// How `ψ` is pulled back to `√(2U)` before each step (module doc, "Relaxation").
    pub relaxation: SavRelaxation,
    /// `√(2U(q(n-1)))` from the previous step's gradient pass (√J); NaN when unknown (after
    /// a reset, a new state or a retune: `g` then does not hold the previous step's gradient
    /// and the step is not relaxed).
    psi_q_prev: f64,
    /// `Σ_l u_l e_l c_l` of the previous step (J; `e_l = Ĥ(r,r)_l - c_l` of a curved plate,
    /// 0 flat): the constant part of its mixed energy (module doc, "Relaxation").
    shift_prev: f64,
    /// Energy removed by the relaxation in the last step (J; negative when the budget returned
    /// some), until [`Self::take_relaxed`].
    relaxed: f64,
    /// What the relaxation may give back ([`crate::models::sav_relaxation`]).
    ledger: RelaxationLedger,
    /// `Ĥ(q(n), q(n))` then `4 u_l Ĥ_l / √(2U)` (length `N_Ψ`).
    w: Vec<f64>,
    /// The last step's in-plane stress coordinates `e_l = Ĥ(r,r)_l - c_l` at `q(n)` (flat:
    /// `Ĥ(q,q)_l`; length `N_Ψ`): what [`super::closure`]'s nonlinearity gate reads.
    stress: Vec<f64>,
    /// `g(q(n))` (√J per unit `q`, length `N_Φ`).
    g: Vec<f64>,
    /// `A⁻¹ r` (first `N_Φ` entries; length `3 N_Φ + 8`); first the fused kernel's scratch.
    y: Vec<f64>,
    /// The fused kernel split in two halves of the in-plane rows (`None`: one pass).
    split: Option<SavSplit>,
}

/// The second half of a split fused kernel: its rows, gradient and scratch, and who runs it
/// (built on a worker thread; the step runs it, allocation-free).
struct SavSplit {
    /// First in-plane row of the second half.
    row: usize,
    /// The second half's part of `∇U` (length `N_Φ`).
    g: Vec<f64>,
    /// The second half's kernel scratch (length `3 N_Φ + 8`).
    y: Vec<f64>,
    /// Whether the coupling also has the shifted (curved plate) row kernel; a curved step
    /// without it runs in one pass (or two passes) instead.
    shifted: bool,
    runner: HalfRunner,
}

/// Who runs the second half.
enum HalfRunner {
    /// A join that returns when both halves are done (offline helpers, [`super::StepJoin`]).
    Join(Arc<dyn StepJoin>),
    /// A real-time helper through a board, with a bounded wait ([`super::step_board`]).
    Board {
        board: Arc<StepBoard>,
        job: Box<HalfJob>,
    },
}

impl std::fmt::Debug for SavSplit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SavSplit").field("row", &self.row).finish()
    }
}

/// Per-mode coefficients of the linear part (`inv_a = 1/(1 + c̃h/2)`, `b = 2 - h²ω̃²`; the
/// increment form needs no `1 - c̃h/2`), the force weights `Φ_s(x₀)` and the in-plane energy weights `u_l`.
pub(crate) struct SavCoefficients<'a> {
    /// `1/(1 + c̃_s h/2)` (dimensionless), length `N_Φ`.
    pub inv_a: &'a [f64],
    /// `2 - h²ω̃_s²` (dimensionless), length `N_Φ`.
    pub b: &'a [f64],
    /// `Φ_s(x₀)` (1/m), length `N_Φ`.
    pub force_weights: &'a [f64],
    /// `u_l = Eh κ²/(8 ζ_l⁴)` (J per unit `Ĥ²`), length `N_Ψ`.
    pub u_coef: &'a [f64],
    /// `h²/ρh` (s² m²/kg).
    pub h2_over_rho_h: f64,
}

impl SavStep {
    /// Allocates the scratch for `n_phi` transverse and `n_psi` in-plane modes (worker thread).
    pub(crate) fn new(n_phi: usize, n_psi: usize) -> Self {
        Self {
            psi: 0.0,
            relaxation: SavRelaxation::OFF,
            psi_q_prev: f64::NAN,
            shift_prev: 0.0,
            relaxed: 0.0,
            ledger: RelaxationLedger::default(),
            w: vec![0.0; n_psi],
            stress: vec![0.0; n_psi],
            g: vec![0.0; n_phi],
            // The block kernel's scratch: permuted q, H^l q and gradient, + 8 padding.
            y: vec![0.0; 3 * n_phi + 8],
            split: None,
        }
    }

    /// Runs the fused kernel as two halves of the in-plane rows through `join` (or in one
    /// pass with `None`). Returns whether the split is in use: it needs a coupling with
    /// [`ModalCoupling::quartic_gradient_rows`] and at least two in-plane modes. A split
    /// changes the summation order of `∇U` (round-off), not the scheme; its result does not
    /// depend on how `join` schedules the halves. Worker thread (allocates).
    pub(crate) fn set_join<C: ModalCoupling + ?Sized>(
        &mut self,
        coupling: &C,
        join: Option<Arc<dyn StepJoin>>,
    ) -> bool {
        self.split = None;
        let Some(join) = join else { return false };
        let Some((row, shifted)) = self.probe_split(coupling) else {
            return false;
        };
        self.split = Some(self.new_split(row, shifted, HalfRunner::Join(join)));
        true
    }

    /// Runs the fused kernel as two halves, the second offered to real-time helpers through
    /// `board` with a bounded wait ([`super::step_board`]; `None`: one pass). The same
    /// conditions and summation order as [`Self::set_join`], so the bits do not depend on who
    /// ran the second half. Worker thread (allocates).
    pub(crate) fn set_board<C: ModalCoupling + 'static>(
        &mut self,
        coupling: &Arc<C>,
        board: Option<Arc<StepBoard>>,
    ) -> bool {
        self.split = None;
        let Some(board) = board else { return false };
        let Some((row, shifted)) = self.probe_split(&**coupling) else {
            return false;
        };
        let (nf, np) = (self.g.len(), self.w.len());
        let job = HalfJob::new(coupling, row..np, nf, np, self.y.len());
        self.split = Some(self.new_split(row, shifted, HalfRunner::Board { board, job }));
        true
    }

    /// The split row, if `coupling` has a row-range kernel and there are two in-plane modes,
    /// and whether it has the shifted one too.
    fn probe_split<C: ModalCoupling + ?Sized>(&self, coupling: &C) -> Option<(usize, bool)> {
        let (nf, np) = (self.g.len(), self.w.len());
        if np < 2 {
            return None;
        }
        let row = coupling.split_row().clamp(1, np - 1);
        let (q, mut g, mut y) = (vec![0.0; nf], vec![0.0; nf], vec![0.0; self.y.len()]);
        let (mut eta, zeros) = (vec![0.0; np - row], vec![0.0; np]);
        if !coupling.quartic_gradient_rows(row..np, &q, &zeros, &mut eta, &mut g, &mut y) {
            return None;
        }
        let shifted = coupling.quartic_gradient_shifted_rows(
            row..np,
            &q,
            &zeros,
            &zeros,
            &mut eta,
            &mut g,
            &mut y,
        );
        Some((row, shifted))
    }

    fn new_split(&self, row: usize, shifted: bool, runner: HalfRunner) -> SavSplit {
        SavSplit {
            row,
            g: vec![0.0; self.g.len()],
            y: vec![0.0; self.y.len()],
            shifted,
            runner,
        }
    }

    /// Whether the second half of each step is offered to real-time helpers
    /// ([`Self::set_board`]).
    pub(crate) fn offers_halves(&self) -> bool {
        matches!(
            &self.split,
            Some(SavSplit {
                runner: HalfRunner::Board { .. },
                ..
            })
        )
    }

    /// The fused kernel `w = Ĥ(q,q)`, `g = 4 Σ_l u_l (w_l - c_l) Ĥ^l q` (`c = shift`, a curved
    /// plate's offsets at `q = r`; `None`: 0) as one pass or two halves (see
    /// [`Self::set_join`]); `false` when the coupling has no fused kernel.
    fn fused_gradient<C: ModalCoupling + ?Sized>(
        &mut self,
        coupling: &C,
        q: &[f64],
        u_coef: &[f64],
        shift: Option<&[f64]>,
    ) -> bool {
        let rows =
            |c: &C, r: std::ops::Range<usize>, w: &mut [f64], g: &mut [f64], y: &mut [f64]| {
                match shift {
                    None => c.quartic_gradient_rows(r, q, u_coef, w, g, y),
                    Some(s) => c.quartic_gradient_shifted_rows(r, q, u_coef, s, w, g, y),
                }
            };
        let split = match self.split.as_mut() {
            Some(split) if shift.is_none() || split.shifted => split,
            _ => {
                let np = self.w.len();
                return rows(coupling, 0..np, &mut self.w, &mut self.g, &mut self.y);
            }
        };
        let np = self.w.len();
        let row = split.row;
        let (w_a, w_b) = self.w.split_at_mut(row);
        let (g_a, y_a) = (&mut self.g, &mut self.y);
        let (g_b, y_b) = (&mut split.g, &mut split.y);
        let (mut ok_a, mut ok_b) = (false, false);
        match &split.runner {
            HalfRunner::Join(join) => join.join(
                &mut || ok_a = rows(coupling, 0..row, w_a, g_a, y_a),
                &mut || ok_b = rows(coupling, row..np, w_b, g_b, y_b),
            ),
            HalfRunner::Board { board, job } => {
                let offered = job.offer(board, q, u_coef, shift);
                let start = Instant::now();
                ok_a = rows(coupling, 0..row, w_a, g_a, y_a);
                if offered {
                    job.finish(board, start.elapsed(), q, u_coef, shift, w_b, g_b, y_b);
                } else {
                    job.run_here(q, u_coef, shift, w_b, g_b, y_b);
                }
                ok_b = true;
            }
        }
        debug_assert!(ok_a && ok_b, "set_join probed the split kernel");
        for (g, &gb) in self.g.iter_mut().zip(&split.g) {
            *g += gb;
        }
        ok_a && ok_b
    }

    /// The last step's in-plane stress coordinates `e_l` at `q(n)` (see the field; zeros
    /// before the first step). Audio thread.
    pub(crate) fn stress(&self) -> &[f64] {
        &self.stress
    }

    /// Sets `ψ(n-½) = psi` (√J) for a new state, forgets the previous step's gradient (the
    /// next step is not relaxed) and empties the relaxation's account. No allocation.
    pub(crate) fn restart(&mut self, psi: f64) {
        self.psi = psi;
        self.psi_q_prev = f64::NAN;
        self.stress.fill(0.0);
        self.relaxed = 0.0;
        self.ledger = RelaxationLedger::default();
    }

    /// Forgets the previous step's gradient (after the coefficients of `U` changed, a retune):
    /// the next step is not relaxed. No allocation.
    pub(crate) fn forget_target(&mut self) {
        self.psi_q_prev = f64::NAN;
    }

    /// The energy the relaxation removed in the steps since the last call (J; negative when
    /// its budget returned some), and clears it. Audio thread.
    pub(crate) fn take_relaxed(&mut self) -> f64 {
        std::mem::take(&mut self.relaxed)
    }

    /// Relaxes `ψ(n-½)` toward `ψ* = √2 (U_→ U_←)^{1/4}` from the two mixed energies
    /// `back` (`U_←`, of the previous step's gradient) and `fwd` (`U_→`, of this step's) (J;
    /// module doc), the energy growing by at most the relaxation's allowance (its bank and its
    /// share of the last step's physical dissipation `dissipated`, J). The target is 0 when
    /// either is negative (module doc). Audio thread, O(1).
    fn relax_toward(&mut self, back: f64, fwd: f64, dissipated: f64) {
        if back.is_nan() || fwd.is_nan() {
            return;
        }
        let target = if back < 0.0 || fwd < 0.0 {
            0.0
        } else {
            (2.0 * (back * fwd).sqrt()).sqrt()
        };
        self.ledger.begin_step(&self.relaxation, dissipated);
        let (psi, removed) = relax(&self.relaxation, self.psi, target, 1.0, &mut self.ledger);
        self.psi = psi;
        self.relaxed += removed;
    }

    /// `ψ = √(2U)` from the in-plane products `bl = Ĥ(·,·)_l`: `2U = 2 Σ u_l bl²`.
    pub(crate) fn psi_from(u_coef: &[f64], bl: &[f64]) -> f64 {
        (2.0 * u_coef.iter().zip(bl).map(|(u, b)| u * b * b).sum::<f64>()).sqrt()
    }

    /// One step: writes `q(n+1)` into `q_next` and advances `ψ` to `ψ(n+½)`.
    /// `fscale = h² F(n) / ρh`. `rest`: for a plate with a rest shape `a`
    /// (`super::model::rest_shape`), `(r, c)` with `r = q(n) + a` and `c_l = Ĥ(a, a)_l`, so
    /// that `U = Σ_l u_l (Ĥ(r,r)_l - c_l)²`; `None` for a flat plate. `dissipated`: the last
    /// step's physical dissipation (J), of which the relaxation may return a share to `ψ`
    /// (module doc, "Relaxation").
    /// Audio thread: no allocation, `O(nnz + N_Φ)` work.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn step<C: ModalCoupling + ?Sized>(
        &mut self,
        coupling: &C,
        k: &SavCoefficients<'_>,
        q: &[f64],
        q_prev: &[f64],
        rest: Option<(&[f64], &[f64])>,
        fscale: f64,
        dissipated: f64,
        q_next: &mut [f64],
    ) {
        // The relaxation's backward mixed energy U_← = ψ_q(n-1) g(n-1)·r(n)/4 - shift(n-1),
        // from the previous step's g, before this step overwrites it (module doc).
        let n = q.len();
        let relaxing = self.relaxation.is_on() && !self.w.is_empty() && !self.psi_q_prev.is_nan();
        let back = if relaxing {
            let r_now = rest.map_or(q, |(r, _)| r);
            0.25 * self.psi_q_prev * dot(&self.g[..n], &r_now[..n]) - self.shift_prev
        } else {
            f64::NAN
        };
        let mut shift = 0.0;
        // g = ∇U / √(2U), ∇U_s = Σ_l 4 u_l Ĥ(q,q)_l Σ_k Ĥ^l_{s,k} q_k (fused kernel when the
        // coupling has one, else two passes; a curved plate's at r with Ĥ(r,r) - c, the fused
        // kernel shifting each row by its c_l).
        let psi_q = if self.w.is_empty() {
            self.g.fill(0.0);
            0.0
        } else if let Some((r, c)) = rest {
            // A curved plate: w = Ĥ(r,r) - c. The fused kernel gives Ĥ(r,r) and
            // g = 4 Σ u (Ĥ(r,r) - c) Ĥ r in one pass; else two passes.
            let fused = self.fused_gradient(coupling, r, k.u_coef, Some(c));
            if !fused {
                coupling.contract_eta(r, r, &mut self.w);
            }
            for (w, &c) in self.w.iter_mut().zip(c) {
                *w -= c;
            }
            self.stress.copy_from_slice(&self.w);
            shift = self
                .w
                .iter()
                .zip(c)
                .zip(k.u_coef)
                .map(|((e, c), u)| u * e * c)
                .sum();
            let psi_q = Self::psi_from(k.u_coef, &self.w);
            if fused {
                let inv = if psi_q > 0.0 { 1.0 / psi_q } else { 0.0 };
                for g in self.g.iter_mut() {
                    *g *= inv;
                }
            } else if psi_q > 0.0 {
                let inv = 4.0 / psi_q;
                for (w, &u) in self.w.iter_mut().zip(k.u_coef) {
                    *w *= u * inv;
                }
                coupling.apply_force(r, &self.w, &mut self.g);
            } else {
                self.g.fill(0.0);
            }
            psi_q
        } else if self.fused_gradient(coupling, q, k.u_coef, None) {
            self.stress.copy_from_slice(&self.w);
            let psi_q = Self::psi_from(k.u_coef, &self.w);
            let inv = if psi_q > 0.0 { 1.0 / psi_q } else { 0.0 };
            for g in self.g.iter_mut() {
                *g *= inv;
            }
            psi_q
        } else {
            coupling.contract_eta(q, q, &mut self.w);
            self.stress.copy_from_slice(&self.w);
            let psi_q = Self::psi_from(k.u_coef, &self.w);
            if psi_q > 0.0 {
                let inv = 4.0 / psi_q;
                for (w, &u) in self.w.iter_mut().zip(k.u_coef) {
                    *w *= u * inv;
                }
                coupling.apply_force(q, &self.w, &mut self.g);
            } else {
                self.g.fill(0.0);
            }
            psi_q
        };
        if relaxing {
            // The forward mixed energy U_→ = ψ_q(n) g(n)·r(n-1)/4 - shift(n), with
            // r(n-1) = q(n-1) + a = q(n-1) + (r(n) - q(n)) on a curved plate.
            let g = &self.g[..n];
            let g_r_prev = match rest {
                Some((r, _)) => (0..n).map(|s| g[s] * (q_prev[s] + (r[s] - q[s]))).sum(),
                None => dot(g, &q_prev[..n]),
            };
            let fwd = 0.25 * psi_q * g_r_prev - shift;
            self.relax_toward(back, fwd, dissipated);
        }
        self.psi_q_prev = psi_q;
        self.shift_prev = shift;
        // Solve for the increment δ = q(n+1) - q(n-1) rather than q(n+1): the rank-one
        // correction cancels most of `A⁻¹r` along `g` when `β gᵀA⁻¹g ≫ 1` (stiff nonlinearity),
        // and that cancellation costs round-off relative to the size of the solved vector; `δ`
        // is `O(h q̇)` where `q(n+1)` is `O(q)`. Substituting `q(n+1) = q(n-1) + δ` (the
        // `β g gᵀ q(n-1)` terms cancel, `a + d = 2`):
        // `(A + β g gᵀ) δ = 2(q(n) - q(n-1)) - h²ω̃² q(n) + h² p(n) - (h²/ρh) ψ(n-½) g`.
        let c = k.h2_over_rho_h * self.psi;
        // y = A⁻¹ r; gᵀy and gᵀA⁻¹g for Sherman-Morrison.
        let n = q.len();
        let (qc, qp, g, y) = (&q[..n], &q_prev[..n], &self.g[..n], &mut self.y[..n]);
        let (b, fw, inv_a) = (&k.b[..n], &k.force_weights[..n], &k.inv_a[..n]);
        let [gy, gag] = lane_sums(n, |s| {
            let gs = g[s];
            let r = 2.0 * (qc[s] - qp[s]) + (b[s] - 2.0) * qc[s] + fscale * fw[s] - c * gs;
            let ys = r * inv_a[s];
            y[s] = ys;
            [gs * ys, gs * gs * inv_a[s]]
        });
        let beta = 0.25 * k.h2_over_rho_h;
        let coef = beta * gy / (1.0 + beta * gag);
        let q_next = &mut q_next[..n];
        let dpsi = lane_sum(n, |s| {
            let delta = y[s] - coef * g[s] * inv_a[s];
            q_next[s] = qp[s] + delta;
            g[s] * delta
        });
        self.psi += 0.5 * dpsi;
    }

    /// The change of `q(n+1)` per unit force `F(n)` (1 N) of the step just taken, into `z`
    /// (units of `q` per N), and `g·z`. The step is affine in the force (the rank-one system
    /// does not depend on it), so `z = (h²/ρh)(A⁻¹Φ - A⁻¹g · β gᵀA⁻¹Φ / (1 + β gᵀA⁻¹g))` with
    /// the `g` of that step; adding `F z` to `q(n+1)` and `F g·z / 2` to `ψ` gives exactly the
    /// step under the force `F`. Audio thread: no allocation, `O(N_Φ)`.
    pub(crate) fn unit_response(&self, k: &SavCoefficients<'_>, z: &mut [f64]) -> f64 {
        let (mut g_phi, mut gag) = (0.0, 0.0);
        for ((&gs, &ia), &phi) in self.g.iter().zip(k.inv_a).zip(k.force_weights) {
            g_phi += gs * ia * phi;
            gag += gs * gs * ia;
        }
        let beta = 0.25 * k.h2_over_rho_h;
        let coef = beta * g_phi / (1.0 + beta * gag);
        let mut gz = 0.0;
        for (((zs, &gs), &ia), &phi) in z.iter_mut().zip(&self.g).zip(k.inv_a).zip(k.force_weights)
        {
            *zs = k.h2_over_rho_h * ia * (phi - coef * gs);
            gz += gs * *zs;
        }
        gz
    }
}
