//! Relaxation of a quadratised (scalar auxiliary variable, SAV) state toward its definition,
//! with the energy it exchanges counted: the drift correction of every SAV-type scheme of the
//! models (the plate's in-plane `ψ`, [`crate::models::plate`]'s `sav.rs`; the string's contact
//! `z_i`, [`crate::models::string`]'s `contact_sav.rs`).
//!
//! # Why
//! A SAV scheme writes a non-negative potential as `U = ψ²/2` and advances `ψ` as a state of
//! its own, `ψ(n+½) = ψ(n-½) + g(q(n))·(q(n+1) - q(n-1))/2`. The exact flow keeps
//! `ψ = √(2U(q))`; the scheme keeps it only up to its consistency error, and nothing pulls it
//! back: the error accumulates over every strike a voice receives. When the plate comes to
//! rest `ψ` stays wherever the drift left it, and the force `-μ_{t.}ψ g(q)` (with `g` of degree
//! 1 in `q`) acts as an extra linear stiffness on a plate at rest: a soft strike after a
//! minute of rolls sounds like another instrument (measured: the 80 N gong's soft strike moved
//! from 72 Hz to a 2.5 kHz centroid after 240 strikes).
//!
//! # The relaxation (after Jiang, Zhang, Zhao, "Improving the accuracy and consistency of the
//! scalar auxiliary variable (SAV) method with relaxation", J. Comput. Phys. 456, 2022)
//! Before each step, with `ψ̃` the scheme's value and `ψ*` a second-order estimate of
//! `√(2U)` at the same half step (each model says which), the state is moved toward it:
//!
//! ```text
//! ψ = ψ̃ + ξ (ψ* - ψ̃),   ξ = min(κ, ξ_max),
//! ```
//!
//! `κ ∈ [0, 1]` the fraction of the gap closed per step (`κ = 1 - e^{-h/τ}` for a time
//! constant `τ`; `κ = 1` is the paper's full relaxation), and `ξ_max` the largest `ξ` for
//! which the auxiliary energy does not grow by more than the allowance `β ≥ 0`:
//! `(ψ² - ψ̃²)/2 ≤ β`. The allowance is a share `η ∈ [0, 1]` of the physical dissipation of
//! the previous step (the paper's `η` times its dissipation term) plus the **bank**: the
//! energy the relaxation itself removed earlier and has not yet given back
//! ([`RelaxationLedger`]). So the relaxation returns at most what it took plus `η` of the
//! losses, and the modified energy `𝔥 = t + v + ψ²/2` obeys, at every step `n`,
//! `𝔥(n) ≤ 𝔥(0) + W(n) - (1 - η) D(n)` (`W` the external work, `D` the physical
//! dissipation): the bound on which the scheme's stability rests is kept, and without losses
//! and forcing `𝔥` never exceeds its initial value. The models' default is `η = 0`
//! ([`DEFAULT_BUDGET_SHARE`]): the bound is then the physical one,
//! `𝔥(n) ≤ 𝔥(0) + W(n) - D(n)`, and a damped note decays at least as fast as its damping says.
//! The bank is what makes the correction symmetric: with an allowance of the losses alone, a
//! lossless run could only ever lower `ψ` (the scheme's oscillating consistency error then
//! biases `ψ` low: measured as a 0.3 % frequency error of a curved plate's linear mode,
//! `tests/plates/plate_shell.rs`). With `d = ψ* - ψ̃`,
//! `f(ξ) = (ψ̃ + ξd)² - ψ̃² - 2β = ξ²d² + 2ξψ̃d - 2β` is convex with `f(0) = -2β ≤ 0`, so the
//! feasible `ξ ≥ 0` form the interval `[0, ξ_max]` with the positive root
//! `ξ_max = (|d| √(ψ̃² + 2β) - ψ̃ d) / d²` (no root when `d = 0`: nothing to do).
//!
//! # Energy
//! The energy removed, `R = (ψ̃² - ψ²)/2` (J, times the model's scale; negative when the
//! budget returns some), is added to the model's dissipated energy, so the power balance
//! `𝔥 + dissipated - work` still closes to round-off: the relaxation is a (signed, bounded)
//! dissipation term of the discrete energy identity, not a change of the conserved quantity.
//! The models report it apart as well (`relaxed`).
//!
//! Threads: the coefficients are plain `Copy` data chosen on a worker thread; [`relax`] runs on
//! the audio thread, O(1), no allocation.

/// How strongly a SAV auxiliary variable is pulled back to its definition each step.
///
/// Plain `Copy` data: set on a worker or control thread, read by the audio thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SavRelaxation {
    /// `κ`: fraction of the gap `ψ* - ψ̃` closed per step, in `[0, 1]` (0: the plain SAV
    /// scheme, bit for bit).
    pub per_step: f64,
    /// `η`: share of the previous step's physical dissipation that the relaxation may return
    /// to the auxiliary energy when `ψ̃` lies below `ψ*`, in `[0, 1]` (0: it only removes).
    pub budget_share: f64,
}

impl SavRelaxation {
    /// The plain SAV scheme: no relaxation.
    pub const OFF: SavRelaxation = SavRelaxation {
        per_step: 0.0,
        budget_share: 0.0,
    };

    /// The models' default: `τ =` [`DEFAULT_TIME_CONSTANT`] and `η =`
    /// [`DEFAULT_BUDGET_SHARE`] at the time step `h` (s).
    pub fn default_at(h: f64) -> Self {
        Self::with_time_constant(DEFAULT_TIME_CONSTANT, DEFAULT_BUDGET_SHARE, h)
    }

    /// The string contact's default: `τ =` [`DEFAULT_CONTACT_TIME_CONSTANT`] at the time step
    /// `h` (s).
    pub fn contact_default_at(h: f64) -> Self {
        Self::from_scene(DEFAULT_CONTACT_TIME_CONSTANT, h)
    }

    /// `κ = 1 - e^{-h/τ}` for the time constant `tau` (s, > 0; `0` or less gives `κ = 1`,
    /// `∞` gives 0) at the time step `h` (s), with the budget share `share` (clamped to
    /// `[0, 1]`: callers pass constants).
    pub fn with_time_constant(tau: f64, share: f64, h: f64) -> Self {
        let per_step = if tau > 0.0 { -(-h / tau).exp_m1() } else { 1.0 };
        Self {
            per_step: per_step.clamp(0.0, 1.0),
            budget_share: share.clamp(0.0, 1.0),
        }
    }

    /// A scene's setting: the time constant `tau` (s; 0 or less: [`Self::OFF`]) with
    /// [`DEFAULT_BUDGET_SHARE`], at the time step `h` (s).
    pub fn from_scene(tau: f64, h: f64) -> Self {
        if tau > 0.0 {
            Self::with_time_constant(tau, DEFAULT_BUDGET_SHARE, h)
        } else {
            Self::OFF
        }
    }

    /// Whether the relaxation does anything.
    pub fn is_on(&self) -> bool {
        self.per_step > 0.0
    }

    /// The budget `β = η D` (J, ≥ 0) the relaxation may return to the auxiliary energy after
    /// a step that dissipated `dissipated` (J) by the model's physical losses.
    #[inline]
    pub fn allowance(&self, dissipated: f64) -> f64 {
        (self.budget_share * dissipated).max(0.0)
    }

    /// The relaxed value of `psi` (`ψ̃`) toward `target` (`ψ*`), the auxiliary energy
    /// `ψ²/2` growing by at most `allowance` (`β`, in units of `ψ²/2`, ≥ 0; module doc).
    /// Returns `psi` unchanged when the relaxation is off or nothing is to be gained. Audio
    /// thread, O(1).
    #[inline]
    pub fn relax(&self, psi: f64, target: f64, allowance: f64) -> f64 {
        let d = target - psi;
        if self.per_step <= 0.0 || d == 0.0 || !d.is_finite() {
            return psi;
        }
        let b = allowance.max(0.0);
        // The positive root of ξ²d² + 2ξψd - 2β; written to avoid the cancellation of
        // `|d|√(ψ² + 2β)` against `ψd` when both are large (multiply by the conjugate).
        let s = (psi * psi + 2.0 * b).sqrt();
        let pd = psi * d;
        let ad = d.abs();
        let xi_max = if pd <= 0.0 {
            (ad * s - pd) / (d * d)
        } else {
            // (|d|s - ψd)/d² = 2β / (|d|s + ψd) / ... : (ad s)² - (pd)² = d²(s² - ψ²) = 2βd².
            2.0 * b / (ad * s + pd)
        };
        let xi = self.per_step.min(xi_max.max(0.0));
        psi + xi * d
    }
}

/// The default relaxation time constant `τ` (s): long against a step (the scheme's own
/// consistency error oscillates at the modes' periods and is left alone) and short against a
/// note's decay (the drift left after a strike is gone before the next one). Measured choice:
/// docs/models.md, "SAV relaxation".
pub const DEFAULT_TIME_CONSTANT: f64 = 2e-3;

/// The default time constant (s) of the string contact's relaxation: 0, off. The `z` a
/// release leaves at a node is given back at its next contact a few periods later, part of the
/// contact's dynamics rather than a drift. Removing it (τ = 2 ms) brings the lecture's sitar
/// at K = 1e13 far closer to the Newton contact at 192 kHz (relative L2 distance 5.0e-4
/// against 1.7e-2 plain) but stops the convergence as the rate grows (3.6e-4 at 6.1 MHz
/// against 2.6e-4 plain; `tests/strings/string_sav.rs`): kept off by default, so the scheme
/// converges; a scene sets it (`string.sav_relaxation`) for drones whose released nodes
/// should come back to rest.
pub const DEFAULT_CONTACT_TIME_CONSTANT: f64 = 0.0;

/// The default share `η` of the previous step's dissipation that the relaxation may return to
/// a `ψ` that fell below its definition: none. The relaxation gives back only what it removed
/// (its bank), so every loss leaves the instrument. A share of 0.5 (the former default) let a
/// strongly damped note have half its losses returned to `ψ`: the crash cymbal's release at
/// 31.2 kHz decayed 21 dB in 0.9 s against the 27 its 2 s release asks for, its spectrum
/// rising (docs/models.md, "Long performances: the SAV relaxation").
pub const DEFAULT_BUDGET_SHARE: f64 = 0.0;

/// The energy account of one model's relaxation: what it may give back this step.
///
/// Owned by the model, audio thread; plain data, no allocation.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RelaxationLedger {
    /// Energy the relaxation removed and has not given back (J, ≥ 0).
    pub bank: f64,
    /// What is left this step of `η` times the last step's physical dissipation (J, ≥ 0).
    loss_share: f64,
}

impl RelaxationLedger {
    /// Starts a step after one that dissipated `dissipated` (J) by the model's losses.
    #[inline]
    pub fn begin_step(&mut self, r: &SavRelaxation, dissipated: f64) {
        self.loss_share = r.allowance(dissipated);
    }

    /// The energy (J) the relaxation may still give back this step.
    #[inline]
    pub fn allowance(&self) -> f64 {
        self.loss_share + self.bank
    }

    /// Books a relaxation that removed `removed` J (negative: gave back), spending the share
    /// of the losses before the bank.
    #[inline]
    pub fn book(&mut self, removed: f64) {
        if removed >= 0.0 {
            self.bank += removed;
        } else {
            let back = -removed;
            let from_losses = back.min(self.loss_share);
            self.loss_share -= from_losses;
            // Not clamped at 0: a binding allowance is met to the round-off of `ψ²`, and the
            // bank then holds that round-off (a few ulps below 0), so the cumulative removed
            // energy is exactly the bank plus what the losses' share gave.
            self.bank -= back - from_losses;
        }
    }
}

/// The relaxation of one auxiliary variable `psi` toward `target` with the energy scale
/// `scale` (J per unit `ψ²/2`, > 0: 1 for the plate, `Δx` for a string's contact node),
/// within `ledger`'s allowance, booked in it. Returns the new value and the energy it removed
/// (J, negative when it gave some back). Audio thread, O(1).
#[inline]
pub fn relax(
    r: &SavRelaxation,
    psi: f64,
    target: f64,
    scale: f64,
    ledger: &mut RelaxationLedger,
) -> (f64, f64) {
    let new = r.relax(psi, target, ledger.allowance() / scale);
    // Where the allowance binds, `ψ²` lands on its bound up to the round-off of `ψ²` (a few
    // ulps of the auxiliary energy): the bound of the module doc holds to that round-off.
    let removed = 0.5 * scale * (psi * psi - new * new);
    ledger.book(removed);
    (new, removed)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Off, or a zero gap, leaves the value bit-identical.
    #[test]
    fn off_and_zero_gap_do_nothing() {
        assert_eq!(SavRelaxation::OFF.relax(0.3, 0.1, 1.0), 0.3);
        let r = SavRelaxation::with_time_constant(1e-3, 1.0, 1.0 / 48e3);
        assert_eq!(r.relax(0.3, 0.3, 1.0), 0.3);
        assert_eq!(r.relax(0.3, f64::NAN, 1.0), 0.3);
    }

    /// `κ = 1 - e^{-h/τ}` (the closed form, to 1e-15), and `τ = 0` snaps.
    #[test]
    fn per_step_from_time_constant() {
        let h = 1.0 / 44_100.0;
        let r = SavRelaxation::with_time_constant(2e-3, 0.5, h);
        assert!((r.per_step - (1.0 - (-h / 2e-3f64).exp())).abs() < 1e-15);
        assert_eq!(SavRelaxation::with_time_constant(0.0, 0.5, h).per_step, 1.0);
    }

    /// Above its target the value moves down by exactly κ of the gap (removing energy, no
    /// budget needed); below its target with no budget it does not move (no energy may be
    /// added without losses); with a budget it rises until `(ψ² - ψ̃²)/2` equals the budget
    /// (to 1e-14 relative), never past `κ` of the gap.
    #[test]
    fn energy_constraint_is_exact() {
        let r = SavRelaxation {
            per_step: 0.25,
            budget_share: 1.0,
        };
        let down = r.relax(2.0, 1.0, 0.0);
        assert!((down - 1.75).abs() < 1e-15);
        assert_eq!(r.relax(1.0, 2.0, 0.0), 1.0);
        // Budget too small for κ: the energy rises by exactly the budget.
        let budget = 0.01;
        let up = r.relax(1.0, 2.0, budget);
        assert!(up > 1.0 && up < 1.25);
        assert!(((up * up - 1.0) / 2.0 - budget).abs() < 1e-14 * budget.max(1.0));
        // Budget large: κ of the gap.
        assert!((r.relax(1.0, 2.0, 10.0) - 1.25).abs() < 1e-15);
        // A negative value (drifted through zero) is pulled toward the positive target only
        // as far as its energy does not grow: |ψ| shrinks.
        let neg = r.relax(-1.0, 0.5, 0.0);
        assert!(neg > -1.0 && neg.abs() <= 1.0);
        // η = 0.5: the allowance is half the dissipation.
        let half = SavRelaxation {
            per_step: 1.0,
            budget_share: 0.5,
        };
        assert_eq!(half.allowance(2.0 * budget), budget);
        assert_eq!(half.allowance(-1.0), 0.0);
    }

    /// The removed energy of [`relax`] is `scale (ψ̃² - ψ²)/2`, its sign follows the move;
    /// what is removed goes to the bank and may be given back, no more (to 1e-14), and the
    /// share of the losses is spent before the bank.
    #[test]
    fn removed_energy_is_counted_and_banked() {
        let r = SavRelaxation {
            per_step: 1.0,
            budget_share: 1.0,
        };
        let mut ledger = RelaxationLedger::default();
        ledger.begin_step(&r, 0.0);
        let (new, removed) = relax(&r, 3.0, 1.0, 0.5, &mut ledger);
        assert_eq!(new, 1.0);
        assert!((removed - 0.5 * 0.5 * 8.0).abs() < 1e-15);
        assert_eq!(ledger.bank, removed);
        // Give back: at most the bank (2 J), though the target asks for more.
        ledger.begin_step(&r, 0.0);
        let (new, given) = relax(&r, 1.0, 10.0, 0.5, &mut ledger);
        assert!((given + 2.0).abs() < 1e-14, "{given}");
        assert!((0.25 * (new * new - 1.0) - 2.0).abs() < 1e-14);
        assert!(ledger.bank.abs() < 1e-14);
        // The share of the losses goes first: 0.25 J of losses, 0.1 J given back.
        ledger.bank = 1.0;
        ledger.begin_step(&r, 0.25);
        ledger.book(-0.1);
        assert_eq!(ledger.bank, 1.0);
        assert!((ledger.allowance() - 1.15).abs() < 1e-15);
        ledger.book(-0.5);
        assert!((ledger.bank - 0.65).abs() < 1e-15);
    }
}
