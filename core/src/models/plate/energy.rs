//! The discrete energy of the plate schemes and its power balance (derivation in [`super`]).

/// Discrete energy terms and power-balance accumulators at the current step `n` (the terms are
/// those of the half-step energy `𝔥^{n-1/2}` built from `q(n)` and `q(n-1)`).
///
/// Energies are in the units of `ρh q̇²`: joules when the modes are normalised to
/// `∫_S Φ_s² dS = 1` (then `q` is in m², `Φ` in 1/m). Written by the audio thread at every
/// step; copied out by value ([`super::PlateModel::energy`]) by any reader.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct PlateEnergy {
    /// Steps taken since the initial state was set (`n`).
    pub step: u64,
    /// Kinetic energy `t = (ρh/2) Σ_s (δ_{t-} q_s(n))²` (J).
    pub kinetic: f64,
    /// Linear potential energy `v = (ρh/2) Σ_s ω̃_s² q_s(n) q_s(n-1)` (J), with `ω̃_s = ω_s`
    /// for θ = 1 and the exact-scheme value otherwise (a modified energy, see [`super`]).
    pub linear: f64,
    /// Nonlinear (in-plane) energy `u = (1/2Eh) Σ_l ζ_l⁴ (μ_{t-}η_l(n))²` (J), with
    /// `μ_{t-}η_l(n) = -(Eh/2ζ_l⁴) Σ H^l_{ij} q_i(n) q_j(n-1)`; for the SAV scheme the
    /// quadratised `ψ(n-½)²/2` instead.
    pub nonlinear: f64,
    /// Cumulative energy removed by damping since the initial state,
    /// `Σ_m h ρh Σ_s c̃_s (δ_{t.} q_s(m))²` (J), exactly as the discrete identity gives, plus
    /// the hand's [`Self::hand_dissipated`].
    pub dissipated: f64,
    /// The part of [`Self::dissipated`] removed by the player's hand (a point damper),
    /// `Σ_m -h F_h(m) δ_{t.} w_h(m) = Σ_m h c (δ_{t.} w_h(m))²` (J, ≥ 0; 0 without a hand).
    pub hand_dissipated: f64,
    /// The part of [`Self::dissipated`] removed by the SAV scheme's relaxation of `ψ` toward
    /// `√(2U(q))` ([`crate::models::sav_relaxation`]; J, negative where its budget returned some
    /// of the step's losses; 0 for the other schemes).
    pub relaxed: f64,
    /// The part of [`Self::dissipated`] removed by the truncation closure, the damping of the
    /// top modes that takes a loud strike's pile-up ([`super::closure`]; J, ≥ 0; 0 when it is off).
    pub closure: f64,
    /// Cumulative work done by the external force since the initial state,
    /// `Σ_m h F(m) Σ_s Φ_s δ_{t.} q_s(m)` (J).
    pub work: f64,
}

impl PlateEnergy {
    /// Stored energy `t + v + u` (J).
    pub fn total(&self) -> f64 {
        self.kinetic + self.linear + self.nonlinear
    }

    /// Power-balance invariant `t + v + u + dissipated - work` (J): constant to round-off for
    /// the conservative schemes, with or without losses and forcing.
    pub fn balance(&self) -> f64 {
        self.total() + self.dissipated - self.work
    }
}

impl From<PlateEnergy> for crate::models::source::EnergyTerms {
    /// The render and engine view of the plate's energy terms (J), same values.
    fn from(e: PlateEnergy) -> Self {
        Self {
            kinetic: e.kinetic,
            linear: e.linear,
            nonlinear: e.nonlinear,
            above: 0.0,
            dissipated: e.dissipated,
            work: e.work,
        }
    }
}
