//! N-degree-of-freedom Hamiltonian systems and one-step integrators (SEED.md section 2).
//!
//! State layout: `y = [q_1..q_n, p_1..p_n]` (length `2n`), `ẏ = J⁻¹ ∇H(y)` with
//! `J = [[0, I], [-I, 0]]`, i.e. `q̇ = ∂H/∂p`, `ṗ = -∂H/∂q`.
//!
//! Methods are objects built for one state dimension (scratch allocated at build time), then
//! stepped in place: `method.step(&system, h, &mut y)` never allocates.
//!
//! Modules: [`butcher`] (tableaus as data, order and symplecticity conditions),
//! [`runge_kutta`] (explicit RK), [`gauss`] (implicit RK with simplified Newton),
//! [`verlet`] (Störmer-Verlet), [`systems`] (FPU chain, linear chain, pendulum, Kepler and
//! [`SystemSpec`]), [`methods`] ([`METHOD_NAMES`], [`build_method`]).

use super::StepperStats;

pub mod butcher;
pub mod gauss;
pub mod methods;
pub mod runge_kutta;
pub mod systems;
pub mod verlet;

pub use methods::{build_method, build_method_for_system, METHOD_NAMES};
pub use systems::{build_system, SystemSpec};

/// A Hamiltonian system `ẏ = J⁻¹ ∇H(y)`, `y = [q; p]`.
///
/// Implementations are immutable parameter holders; any thread may evaluate them.
pub trait HamiltonianSystem: Send + Sync {
    /// Short identifier (for reports), for example `fpu`.
    fn name(&self) -> &'static str;
    /// Number of positions `n` (the state has `2n` entries).
    fn degrees_of_freedom(&self) -> usize;
    /// The Hamiltonian `H(y)`.
    fn hamiltonian(&self, y: &[f64]) -> f64;
    /// Writes `ẏ = J⁻¹ ∇H(y)` into `dy` (length `2n`).
    fn vector_field(&self, y: &[f64], dy: &mut [f64]);
    /// Writes the Jacobian of [`Self::vector_field`] at `y` into `jac`, row-major `2n × 2n`.
    fn vector_field_jacobian(&self, y: &[f64], jac: &mut [f64]);
    /// For separable systems `H = ½|p|² + V(q)` (unit masses), writes the force
    /// `f(q) = -∇V(q)` into `force` (length `n`) and returns `true`; otherwise returns `false`
    /// and leaves `force` untouched. Störmer-Verlet requires a separable system.
    fn separable_force(&self, _q: &[f64], _force: &mut [f64]) -> bool {
        false
    }
}

/// A one-step integrator `y_{n+1} = Φ_h(y_n)` built for one state dimension.
///
/// Owned and stepped by one thread; `step` does not allocate.
pub trait OneStepMethod: Send {
    /// Identifier used on the command line (for example `rk4`, `gauss2`).
    fn name(&self) -> &'static str;
    /// Classical order of accuracy.
    fn order(&self) -> u32;
    /// Whether the map `Φ_h` is symplectic (`Φ'ᵀ J Φ' = J`).
    fn is_symplectic(&self) -> bool;
    /// Advances `y` (length `2n`) by one step `h` in place.
    fn step(&mut self, system: &dyn HamiltonianSystem, h: f64, y: &mut [f64]);
    /// Solver counters since build (implicit methods; zeros otherwise).
    fn stats(&self) -> StepperStats {
        StepperStats::default()
    }
}
