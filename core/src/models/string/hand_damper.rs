//! The player's hand on the string: a viscous point damper at a grid node, solved implicitly
//! with the step (closed form) and counted in the energy.
//!
//! # Model
//!
//! A finger resting on the string (muting it, as a player's touch) is a dashpot of coefficient
//! `c` (N·s/m, ≥ 0) at `x_h`: the point force `F_h = -c u_t(x_h)` enters mode `j` as
//! `F_h φ_j(x_h)`, so mode `j` alone gets the extra decay rate
//! `σ_j = c φ_j(x_h)² / (2μ)` (`μ/φ_j(x_h)²` is its modal mass at the hand point).
//!
//! # Discrete form
//!
//! `F_h = -c δ_{t.}w_h`, `w_h = Σ_j φ_j(x_h) q_j`. The exact modal scheme adds `k F φ_j(x)` to
//! each mode's increment for a point force `F` at `x` (`k = h²/μ`, the same for every mode), so
//! with the force-free `w_h*` and `c_h = k Σ_j φ_j(x_h)²`, `γ = c/2h`:
//!
//! ```text
//! F_h = -γ (w_h* - w_h(n-1)) / (1 + γ c_h),   Δ_j += k F_h φ_j(x_h),
//! ```
//!
//! solved right after the free update, before the grid synthesis and the contact solve, so the
//! contact sees the hand's motion. The hand sits at a grid node `x_p` that is not an obstacle
//! node: there `Σ_j φ_j(x_i) φ_j(x_p) Δx = δ_ip` (`S S⁻¹ = I`, module docs of
//! [`crate::models::string`]), so the hand's force moves no obstacle node and the contact
//! forces do not move `w_h`: both solves stay exact and decoupled. `c = 0` skips all of this
//! (the step is the one without the hand bit for bit).
//!
//! # Energy
//!
//! Multiplying by `δ_{t.}q_j` as in the module docs, the hand adds
//! `F_h δ_{t.}w_h = -c (δ_{t.}w_h)² ≤ 0` to the balance: each step adds `-h F_h δ_{t.}w_h`
//! (J) to the dissipated energy (and to [`super::StiffString::hand_dissipated`]).
//!
//! Threads: the model's; no allocation (the mode shapes' buffer is allocated at build).

/// The hand's state on a string: coefficient, node, mode shapes there and accounts.
#[derive(Debug, Clone)]
pub(crate) struct StringHand {
    /// Damper coefficient `c` (N·s/m, ≥ 0); 0: no hand.
    pub(crate) c: f64,
    /// Grid node of the hand (1..N-1; 0 before [`super::StiffString::set_hand`]).
    pub(crate) node: usize,
    /// `φ_j(x_h)` (m^-1/2), length `N - 1`.
    pub(crate) shape: Vec<f64>,
    /// `Σ_j φ_j(x_h)²` (1/m).
    pub(crate) shape_sq: f64,
    /// The hand force `F_h` of the last step (N).
    pub(crate) force: f64,
    /// Energy taken by the hand since the initial condition (J, part of the dissipated energy).
    pub(crate) dissipated: f64,
}

impl StringHand {
    /// No hand, for `modes` modes (allocates; build thread).
    pub(crate) fn new(modes: usize) -> Self {
        Self {
            c: 0.0,
            node: 0,
            shape: vec![0.0; modes],
            shape_sq: 0.0,
            force: 0.0,
            dissipated: 0.0,
        }
    }
}
