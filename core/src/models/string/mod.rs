//! Stiff string against a unilateral obstacle: sitar and tanpura (SEED.md section 3.2; Issanchou,
//! Bilbao, Le Carrou, Touzé, Doaré, "A modal-based approach to the nonlinear vibration of
//! strings against a unilateral obstacle", JSV 393, 2017; Bilbao, Numerical Sound Synthesis,
//! Wiley 2009).
//!
//! # Model
//! `μ u_tt - T u_xx + EI u_xxxx = f`, simply supported ends, obstacle height `g(x)`,
//! penetration `η = g - u`, force density `f = ψ'(η) = K[η]_+^α` pushing the string towards
//! `+u` ([`obstacle`], [`contact`]). Modes `φ_j = √(2/L) sin(jπx/L)`, `u = Σ_j q_j φ_j`,
//! `μ(q̈_j + 2σ_j q̇_j + ω_j² q_j) = F_j = ∫ f φ_j dx` ([`params`], [`losses`]).
//!
//! # Scheme
//! Grid `x_i = iΔx`, `i = 1..N-1`, `N_m = N - 1` modes, `u = S q`, `S⁻¹ = Δx S` ([`transform`]).
//! Each mode uses the exact two-step scheme ([`exact`])
//! `(μ/h²)(q^{n+1} - C q^n + C̃ q^{n-1}) = F^n`, with the nodal contact force entering as
//! `F^n = S⁻¹ f^n` (`F_j = Δx Σ_i f_i φ_j(x_i)`, the rectangle rule of `∫ f φ_j dx`). Multiplying
//! by `S` gives the grid form of SEED.md 3.2:
//! `(μ/h²)(u^{n+1} - D u^n + D̃ u^{n-1}) = f^n`, `D = S C S⁻¹`, `D̃ = S C̃ S⁻¹`,
//! `f_i^n = (ψ(η_i^{n+1}) - ψ(η_i^{n-1})) / (η_i^{n+1} - η_i^{n-1})`.
//!
//! **The contact solve decouples exactly into one scalar equation per obstacle node.**
//! `u^{n+1} = u_free + (h²/μ) f^n` with `u_free = D u^n - D̃ u^{n-1} = S(C q^n - C̃ q^{n-1})`
//! built from known data only: the force enters `u^{n+1}` through the identity (`S S⁻¹ = I`),
//! not through `D` or `D̃`, and `f_i^n` depends only on node i's own `η_i^{n+1}` (and known
//! `η_i^{n-1}`). So node i solves `r_i + (h²/μ) Φ_i(r_i) = b_i`, `r_i = η_i^{n+1} - η_i^{n-1}`,
//! `b_i = (g_i - u_free_i) - η_i^{n-1}` (safeguarded Newton, [`contact`]); nodes without
//! obstacle are not visited. This holds because the force factor of every mode is the same
//! `h²/μ`; a per-mode factor (for example the `1/(1 + σ_j h)` of a centred damping term with
//! unit mass) would give `u^{n+1} = u_free + S Λ S⁻¹ f`, a coupled system. The price is a
//! consistency error `O(σ_j h)` in the force scaling (`σ_j h < 1e-3` for strings at audio rates).
//!
//! The same per-node structure admits a second, non-iterative contact force: the
//! energy-quadratised scheme of Ducceschi et al. (JASA 2021), linear in `r_i` with a closed-form
//! solution, which conserves a modified energy ([`contact_sav`], selected by
//! [`StiffString::set_contact_scheme`]; Newton stays the default).
//!
//! One step ([`StiffString::step`]): free modal update (O(N)), the grid values the step needs
//! (obstacle nodes and grid-pickup nodes) from stored rows of `S` ([`rows`], default for at
//! most `ROW_LIMIT` nodes) or one DST of the whole grid ([`GridSynthesis`]), the scalar solves
//! at obstacle nodes, and, only if some force is non-zero, the modal force from the same rows
//! (few active nodes) or one DST of the nodal forces. Outputs read the grid or the modes
//! ([`output`]).
//!
//! # Energy
//! Per mode the forced exact scheme is `μ(a δ_tt q + b q + 2s δ_t. q) = F` with `a = (1+c̃)/2`,
//! `b = (1+c̃-c)/h²`, `s = (1-c̃)/(2h)` ([`exact`]); multiplying by `δ_t. q_j`, summing over modes
//! and using `Σ_j F_j δ_t. q_j = Δx Σ_i f_i δ_t. u_i = -Δx Σ_i δ_t. ψ(η_i)` (discrete gradient,
//! `δ_t. u = -δ_t. η`) gives `δ_{t-} H^{n+1/2} = -Σ_j 2μ s_j (δ_t. q_j^n)²` for
//! `H^{n+1/2} = (μ/2)(⟨δ_{t+}u^n, Ď1 δ_{t+}u^n⟩ + ⟨u^{n+1}, Ď2 u^n⟩) + ⟨ψ^{n+1/2}, 1⟩`,
//! `⟨v, w⟩ = Δx Σ_i v_i w_i`, `Ď1 = S diag(a_j) S⁻¹`, `Ď2 = S diag(b_j) S⁻¹`,
//! `ψ^{n+1/2} = (ψ(η^{n+1}) + ψ(η^n))/2`. It is evaluated modally
//! (`⟨Sv, S Λ S⁻¹ Sw⟩ = Σ_j λ_j v_j w_j`) and split into non-negative kinetic and potential parts
//! ([`StiffString::energy_terms`]). Without damping it is exactly conserved; with damping,
//! `H + dissipated` is, and with a force excitation `H + dissipated - work`.

pub mod band_limit;
pub mod contact;
pub mod contact_sav;
pub mod exact;
pub mod excitation;
pub mod hand_damper;
pub mod losses;
pub mod model;
pub mod obstacle;
pub mod output;
pub mod params;
pub mod rows;
pub mod seat;
pub mod spec;
pub mod transform;

pub use contact::{ContactLaw, ContactStats, NEWTON_CAP, NEWTON_TOL};
pub use contact_sav::ContactScheme;
pub use excitation::{StrikeForce, TrianglePluck};
pub use losses::{Losses, ValetteLosses};
pub use model::{GridSynthesis, StiffString, StringConfig, ROW_ACTIVE_LIMIT, ROW_LIMIT};
pub use obstacle::{Obstacle, SitarBridge};
pub use output::{OutputChannel, Quantity, Readout};
pub use params::{Stiffness, StringParams};
pub use rows::NodeRows;
pub use seat::SeatSpec;
pub use transform::ModalMap;
