//! Strings coupled through a moving bridge: the tanpura's and the sitar's network (strings,
//! jawari, bridge, and through it every other string, both ways).
//!
//! # Model
//! String `s` ([`crate::models::string`]: `μ_s u_tt - T u_xx + EI u_xxxx = f`) is seated on
//! the bridge at node `t_s` by a stiff spring (`V_s = (K_s/2) w_s²`, `w_s = u_s(x_t) - λ_s`),
//! and its jawari obstacle `g_s(x)` rides on the bridge: `η_{s,i} = g_{s,i} + λ_s - u_{s,i}`.
//! `λ_s = Σ_k Φ_{k,s} y_k` is the bridge's displacement under the string, `y_k` the bridge's
//! modes ([`bridge`]: `M_k(ÿ_k + 2σ_k ẏ_k + ω_k² y_k) = G_k`). The bridge receives the
//! reactions: `G_k = -Σ_s Φ_{k,s} F_s`, `F_s = Δx Σ_i f_{s,i} + P_s` the string's total force
//! from its jawari and its seat. Energy flows from a plucked string into the bridge and from
//! the bridge into every other string, so a string whose partials match the bridge's motion
//! rings (sympathy). This is the coupling of van Walstijn, Bridges & Mehes (DAFx-16,
//! "A real-time synthesis oriented tanpura model") and Issanchou et al. (JASA 2018) with a
//! modal bridge; its discretisation here is this crate's own.
//!
//! # Scheme
//! Every string keeps its exact modal scheme; the bridge uses the same exact scheme per mode.
//! All coupling forces are discrete gradients between `n+1` and `n-1`:
//! `f_{s,i} = (ψ(η^{n+1}) - ψ(η^{n-1}))/(η^{n+1} - η^{n-1})`,
//! `P_s = -(K_s/2)(w_s^{n+1} + w_s^{n-1})`. One step:
//! 1. each string's free update and free grid values (`StiffString::free_step`);
//!    the bridge's free increment ([`bridge::BridgeBody::free`]);
//! 2. Newton's iteration on the bridge's `y^{n+1}` ([`solve`]): for a trial `y`, each string
//!    solves its nodes' scalar equations (the same per-node solve as on a fixed bridge, with
//!    the obstacle lifted by `λ_s`, and the seat in closed form) and returns `F_s` and
//!    `dF_s/dλ_s`;
//! 3. each string commits its forces at the converged `y` (`StiffString::solve_contacts`),
//!    the bridge takes `G` ([`bridge::BridgeBody::finish`]), each string finishes its step.
//!
//! # Energy
//! Multiply string `s`'s scheme by `δ_t. q_s`, the bridge's by `δ_t. y`, and add. The coupling
//! terms are `Σ_s [Δx Σ_i f_{s,i}(δ_t. u_{s,i} - δ_t. λ_s) + P_s(δ_t. u_s(x_t) - δ_t. λ_s)]`
//! (the string's force times its velocity plus the reaction times the bridge's velocity,
//! `Σ_k G_k δ_t. y_k = -Σ_s F_s δ_t. λ_s`), and `δ_t. λ - δ_t. u = δ_t. η` makes each a
//! discrete time difference:
//! `Δx Σ f δ_t.(u - λ) = -δ_t. Σ_i Δx ψ(η_i)` and `P δ_t. w = -(K/4h)(w^{n+1}² - w^{n-1}²)`.
//! So `H = Σ_s (H_s + Δx Σ_i (ψ(η^{n+1}) + ψ(η^n))/2 + (K_s/4)(w^{n+1}² + w^n²)) + E_bridge`
//! obeys `δ_{t-}H = -(string and bridge damping) + (work of the plucks and strikes)`: without
//! losses it is conserved exactly, up to the Newton solves' tolerance and round-off. Every
//! term is non-negative (the strings' and the bridge's by their exact schemes, SEED.md 3.2), so
//! the coupled scheme is stable for any seat stiffness, bridge mass and contact stiffness.
//! A one-way coupling (the bridge driven by the strings, not acting back) breaks the
//! cancellation and the energy is not conserved (`tests/strings/network.rs` shows both).

pub mod bridge;
pub mod config;
pub mod model;
pub mod solve;
mod source;

pub use bridge::{BridgeBody, BridgeMode, MAX_BRIDGE_MODES};
pub use config::{NetworkConfig, NetworkOutput, SeatedString};
pub use model::StringNetwork;
pub use solve::{NetworkStats, NETWORK_NEWTON_CAP, NETWORK_STOP, NETWORK_TOL};
pub use source::BridgeInstrument;
