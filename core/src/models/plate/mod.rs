//! Modal von Kármán plate (gongs, cymbals) with energy-conserving time schemes.
//!
//! # Model (SEED.md section 3.1)
//!
//! Projected von Kármán equations (Ducceschi & Touzé, JSV 344, 2015, eqs. (13)-(14)), with
//! `H = κ Ĥ` (`κ` = [`PlateParams::coupling_scale`], `Ĥ` the tensor of the [`ModalCoupling`]),
//! `E^s_{k,l} = H^l_{s,k}`:
//!
//! ```text
//! q̈_s + ω_s² q_s + c_s q̇_s = (1/ρh) Σ_{k,l} E^s_{k,l} q_k η_l + p_s(t),
//! η_l = -(Eh / 2ζ_l⁴) Σ_{i,j} H^l_{i,j} q_i q_j,     p_s = Φ_s(x₀) F(t) / ρh,
//! ```
//!
//! energy `T + V + U = (ρh/2) Σ q̇_s² + (ρh/2) Σ ω_s² q_s² + (1/2Eh) Σ ζ_l⁴ η_l²`, with
//! `d(T+V+U)/dt = -ρh Σ c_s q̇_s² + F Σ Φ_s q̇_s`. Units: with modes normalised to
//! `∫ Φ² dS = ∫ Ψ² dS = 1`, `q` is in m², `Φ` in 1/m, energies in J.
//!
//! Single transverse mode and single in-plane mode: `η = -(Eh κ Ĥ / 2ζ⁴) q²`, so
//! `q̈ + ω² q + Γ q³ = 0` with `Γ = κ² Eh Ĥ² / (2 ρh ζ⁴)` (a hardening Duffing oscillator).
//!
//! # Conservative schemes ([`PlateScheme::ConservativeTheta1`], [`PlateScheme::ConservativeExact`])
//!
//! After Bilbao, Thomas, Touzé, Ducceschi (NMPDE 31(6), 2015, section 4) and SEED 3.1, in the
//! notation of SEED section 0. Write `b_l(n) = Ĥ(q(n), q(n-1)) = Σ_{i,j} Ĥ^l_{i,j} q_i(n) q_j(n-1)`
//! and define the in-plane amplitudes at half steps
//!
//! ```text
//! μ_{t-}η_l(n) := -(Eh κ / 2ζ_l⁴) b_l(n)            (SEED 3.1, second equation)
//! δ_tt q_s + ω̃_s² q_s + c̃_s δ_{t.} q_s = (κ/ρh) Σ_{k,l} Ĥ^l_{s,k} q_k(n) · μ_{t+}(μ_{t-}η_l)(n) + p_s(n)
//! ```
//!
//! i.e. the `μ_{t.}η_l(n)` of SEED 3.1 is taken as the average of the two half-step values
//! `½(μ_{t-}η_l(n+1) + μ_{t-}η_l(n))`. (Carrying `η_l(n)` itself as a state, defined by the
//! two-term recursion `μ_{t-}η = …`, conserves the variant `(1/2Eh)Σζ⁴ μ_{t-}(η²)` instead, but
//! `μ_{t-}` has the null space `(-1)^n`: any inconsistency in `η(0)` leaves an undamped
//! Nyquist-rate component in `μ_{t.}η` forever. The choice here needs no extra state and its
//! `u` differs from that one by `(h²/8Eh) Σ ζ⁴ (δ_{t-}η)²`, i.e. `O(h²)`.)
//!
//! **Energy identity.** Multiply mode `s` by `ρh δ_{t.} q_s(n)` and sum over `s`.
//! With the identities of SEED section 0,
//! `ρh δ_tt q δ_{t.} q = δ_{t+}((ρh/2)(δ_{t-}q)²)`, `ρh ω̃² q δ_{t.} q = δ_{t+}((ρh/2) ω̃² q e_{t-}q)`.
//! For the coupling, symmetry of `Ĥ^l` gives
//! `b_l(n+1) - b_l(n) = Ĥ(q(n), q(n+1) - q(n-1)) = 2h Σ_{s,k} Ĥ^l_{s,k} q_k(n) δ_{t.} q_s(n)`,
//! so the coupling power is
//! `κ Σ_l μ_{t+}(μ_{t-}η_l)(n) · δ_{t+} b_l(n) / 2 = -Σ_l (ζ_l⁴/Eh) μ_{t+}(μ_{t-}η_l) δ_{t+}(μ_{t-}η_l)
//!  = -δ_{t+} u(n)` with `u(n) = (1/2Eh) Σ_l ζ_l⁴ (μ_{t-}η_l(n))²` (using `μ_{t+}a · δ_{t+}a = δ_{t+}(a²/2)`).
//! Hence, with `𝔥(n) = t(n) + v(n) + u(n)`,
//!
//! ```text
//! t(n) = (ρh/2) Σ_s (δ_{t-} q_s(n))²,   v(n) = (ρh/2) Σ_s ω̃_s² q_s(n) q_s(n-1),
//! δ_{t+} 𝔥(n) = -ρh Σ_s c̃_s (δ_{t.} q_s(n))² + F(n) Σ_s Φ_s δ_{t.} q_s(n),
//! ```
//!
//! an exact identity: `𝔥(n) + Σ_{m<n} h ρh Σ c̃ (δ_{t.}q(m))² - Σ_{m<n} h F(m) Σ Φ δ_{t.}q(m)` is
//! constant up to round-off ([`PlateEnergy::balance`]). `u ≥ 0` always; `t + v` is positive
//! definite iff `h² ω̃_s² < 4` for every mode, so the energy bounds the solution (stability).
//!
//! **Linear system.** With `G_{s,l} = Σ_k Ĥ^l_{s,k} q_k(n)`, `Ĥ(q(n+1), q(n)) = (Gᵀ q(n+1))_l`
//! and `b(n) = Gᵀ q(n-1)`; with `D_l = κ² Eh / (4 ρh ζ_l⁴)` the update is, after multiplying by
//! `h²`,
//! `(A + h² G D Gᵀ) q(n+1) = (2 - h²ω̃²) q(n) - (1 - c̃h/2) q(n-1) - h² G D b(n) + h² p(n)`,
//! `A = diag(1 + c̃_s h/2)`: SPD, solved by Woodbury (`N_Ψ < N_Φ`) or directly (see `linalg`).
//! `Gᵀ q(n+1)` is the next step's `b`, so each step costs one `coupling_matrix` call.
//!
//! **Linear parts.** θ = 1: `ω̃_s = ω_s`, `c̃_s = c_s`; stable iff `h ω_max < 2`
//! ([`PlateModel::new`] refuses other settings). Exact: the damped exact two-step scheme
//! `q(n+1) - C_s q(n) + C̃_s q(n-1) = 0` (SEED 1.2, 3.2, `σ_s = c_s/2`) *is* the θ = 1 scheme
//! with `c̃_s h/2 = tanh(σ_s h)` and `h²ω̃_s² = 2 - 2C_s/(1 + C̃_s)`
//! (`= 4 sin²(ω_s h/2)` undamped); so the same proof gives the conserved modified energy with
//! `ω̃_s`, `c̃_s`, and `0 < h²ω̃_s² < 4` holds for every `h` except when `ω_s h` sits on a multiple of
//! `π` (refused). This is the modal-exact approach of Ducceschi & Touzé (JSV 2015, section 3.2)
//! and of the string scheme of SEED 3.2 (Issanchou et al. 2017), combined with the conservative
//! nonlinear term. Without coupling it reproduces the damped modal solution at every sample.
//!
//! # Störmer-Verlet ([`PlateScheme::StormerVerletExact`])
//!
//! Same exact linear part, nonlinear force explicit from `q(n)` alone:
//! `… = (κ/ρh) Σ Ĥ^l_{s,k} q_k(n) η_l(n)`, `η_l(n) = -(Eh κ/2ζ_l⁴) Ĥ(q(n), q(n))` (the lecture's
//! gong code). No energy identity holds (SEED 1.3: Störmer-Verlet on Duffing is not
//! conservative); [`PlateEnergy`] reports the same `t + v + u` so the drift can be measured.
//!
//! # Energy-quadratised explicit scheme ([`PlateScheme::SavExact`])
//!
//! The potential `u` written as `ψ²/2` with `ψ` a state; exact linear part; one rank-one
//! update per step; conserves `t + v + ψ²/2` (derivation, stability and references in `sav.rs`).
//!
//! # Curved plates
//!
//! A static rest shape `w0 = Σ a_k Φ_k` ([`PlateModel::set_rest_shape`]) makes the plate a
//! shallow shell (gongs with a dome or boss, cymbals): every scheme above carries over with
//! `q + a` inside the coupling and the rest shape's own Airy source removed; the energy
//! identities hold as they stand (derivation in `model/rest_shape.rs`).
//!
//! Threads: everything is built on a worker thread; [`PlateModel::step`] and
//! [`PlateModel::process`] run on the audio thread without allocating.

pub mod basis;
pub mod blueprint;
pub mod closure;
pub mod contact_residual;
pub mod coupling;
pub mod energy;
pub mod excitation;
pub mod extension;
pub mod geometry;
pub mod hand_damper;
mod linalg;
pub mod mallet;
pub mod mallet_heads;
pub mod mode_list;
pub mod model;
pub mod params;
mod partial_sums;
pub mod rest_projection;
pub mod rest_shape;
mod sav;
mod shared;
mod sparse;
pub mod spec;
pub mod step_board;
pub mod step_join;
pub mod voice;

pub use coupling::{DenseCoupling, ModalCoupling};
pub use energy::PlateEnergy;
pub use excitation::{
    damping_law, damping_to_t60, impulse_force, t60_to_damping, PickupKind, PickupWeights,
    RaisedCosine,
};
pub use extension::{BandExtension, ExtensionEnergy};
pub use hand_damper::hand_damping_for_t60;
pub use mallet::{Mallet, MalletEnergy};
pub use mallet_heads::{HeadLaw, MalletHead};
pub use model::{Diverged, OutputSample, PlateModel};
pub use params::{LinearSolve, PlateParams, PlateScheme};
pub use rest_shape::ShapePart;
pub use step_board::{StepBoard, SPLIT_MIN_ENTRIES};
pub use step_join::{Sequential, StepJoin};
