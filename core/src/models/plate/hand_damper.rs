//! The player's hand on the plate: a viscous point damper at the hand point `x_h`, solved
//! implicitly with the step (closed form, no iteration) and counted in the energy.
//!
//! # Model
//!
//! A hand resting on the plate (a percussionist muting a gong) is a dashpot of coefficient `c`
//! (N·s/m, ≥ 0) at `x_h`: the force `F_h = -c ẇ_h`, `w_h = Σ_s Φ_s(x_h) q_s`, enters every mode
//! as the strike force does, `ρh (q̈_s + …) = … + Φ_s(x_h) F_h`. Mode `s` alone gets the extra
//! decay rate `σ_s = c Φ_s(x_h)² / (2ρh) = c / (2 m_s)`, `m_s = ρh / Φ_s(x_h)²` its modal mass
//! at the hand point (Morse & Ingard, *Theoretical Acoustics*, 1968, §5.1 for the mass seen at
//! a point of a modal system); the hand also couples the modes (through `Φ_s Φ_k`), which the
//! scheme keeps.
//!
//! # Discrete form
//!
//! `F_h(n) = -c δ_{t.}w_h(n) = -c (w_h(n+1) - w_h(n-1)) / 2h`. Every plate scheme's `q(n+1)` is
//! affine in a force at a point (`q(n+1) = q*(n+1) + F z`, see
//! [`crate::models::plate::mallet`]), so with `z_h` the response to a unit force at `x_h`,
//! `c_hh = Φ(x_h)·z_h ≥ 0` and `γ = c/2h`:
//!
//! ```text
//! F_h = -γ (w_h* - w_h(n-1)) / (1 + γ c_hh),   q(n+1) = q*(n+1) + F_h z_h.
//! ```
//!
//! With a mallet in contact (force `F_m` at the strike point, response `z_f`) the hand force is
//! affine in `F_m`: `F_h = F_h0 + k F_m`, `k = -γ Φ(x_h)·z_f / (1 + γ c_hh)`, so the mallet sees
//! the plate's `q* + F_h0 z_h` and the response `z_f + k z_h` (its compliance
//! `Φ(x₀)·z_f + k Φ(x₀)·z_h ≥ 0`, a Schur complement of the positive semi-definite `[Φ·z]`
//! matrix) and keeps its scalar Newton solve. `c = 0` skips all of this: the step is the one
//! without the hand bit for bit.
//!
//! # Energy
//!
//! The hand's force enters the discrete identity of [`crate::models::plate`] as any force does:
//! `δ_{t+}𝔥 = … + F_h δ_{t.}w_h`, and `F_h δ_{t.}w_h = -c (δ_{t.}w_h)² ≤ 0`. Each step adds
//! `-h F_h δ_{t.}w_h` to [`super::PlateEnergy::dissipated`] (and to
//! [`super::PlateEnergy::hand_dissipated`]): the balance closes to round-off and the hand only removes energy, whatever `c` and `h`.
//!
//! Threads: the model's; no allocation (the weights and the scratch are allocated in
//! [`super::PlateModel::new`]).

/// The hand's state on a plate model: coefficient, weights, scratch and last force.
/// Owned by the model (the thread that steps it).
#[derive(Debug, Clone)]
pub(crate) struct Hand {
    /// Damper coefficient `c` (N·s/m, ≥ 0); 0: no hand.
    pub(crate) c: f64,
    /// `Φ_s(x_h)` (1/m), length `N_Φ`.
    pub(crate) weights: Vec<f64>,
    /// Scratch: `z_h = ∂q(n+1)/∂F_h` (units of `q` per N), length `N_Φ`.
    pub(crate) z: Vec<f64>,
    /// The hand force `F_h(n)` of the last step (N).
    pub(crate) force: f64,
}

impl Hand {
    /// No hand (`c = 0`), zero weights, for `n` modes (allocates; worker thread).
    pub(crate) fn new(n: usize) -> Self {
        Self {
            c: 0.0,
            weights: vec![0.0; n],
            z: vec![0.0; n],
            force: 0.0,
        }
    }
}

/// The damper coefficient `c` (N·s/m) under which a mode with value `phi` = `Φ_s(x_h)` (1/m)
/// at the hand point decays by 60 dB in `t60` (s) on a plate of surface density `rho_h`
/// (kg/m²): `σ = ln(1000)/T60 = c Φ_s² / (2ρh)`, so `c = 2 ρh ln(1000) / (T60 Φ_s²)` (the
/// modal mass at the hand point `m_s = ρh/Φ_s²` times `2σ`; module docs). Valid while `σ` is
/// small against the mode's distance to its neighbours (the hand then barely couples them).
/// `phi = 0` (a node) gives infinity. Any thread.
pub fn hand_damping_for_t60(rho_h: f64, phi: f64, t60: f64) -> f64 {
    2.0 * rho_h * 1000f64.ln() / (t60 * phi * phi)
}
