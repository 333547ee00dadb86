//! Time steppers.
//!
//! - One degree of freedom (`ü + ...`): every scheme of SEED.md sections 1.1-1.4 implements
//!   [`OscillatorStepper`]; [`OscillatorSpec`] names them and [`build_oscillator`] builds one.
//! - N degrees of freedom: [`ndof`] (Hamiltonian systems, Störmer-Verlet, Runge-Kutta from
//!   Butcher tableaus, Gauss methods).
//! - [`two_step`]: the exact damped two-step coefficients (SEED.md 1.2 / 3.2), one kernel for
//!   the lab's [`exact`] scheme and the plate and string models' exact linear parts.
//!
//! Lifecycle of every stepper: build (validates parameters, allocates), `reset` (sets initial
//! conditions, no allocation), `step` (no allocation, bounded work).

pub mod closed_form;
pub mod duffing;
pub mod exact;
pub mod impact;
pub mod linear;
pub mod ndof;
pub mod spec;
pub mod two_step;

pub use spec::{build_oscillator, OscillatorSpec};

/// Counters a stepper keeps about its own work (Newton iterations and the like).
///
/// Updated by the thread that calls `step`; read by the same thread or after the run.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct StepperStats {
    /// Total nonlinear-solver iterations over all steps so far (0 for explicit schemes).
    pub solver_iterations: u64,
    /// Largest number of iterations any single step needed.
    pub max_iterations_per_step: u32,
    /// Steps where the solver hit its iteration cap and the documented fallback was used.
    pub solver_failures: u64,
    /// Number of steps during which a contact force was active (impact schemes; else 0).
    pub contact_steps: u64,
    /// Number of distinct contact episodes (impacts) so far (impact schemes; else 0).
    pub impacts: u64,
}

/// A time stepper for one oscillator with a two-step (or one-step) recurrence.
///
/// Conventions: time step `h` (s), state at step `n` is `u_n` at `t_n = n h`. `reset` puts the
/// stepper at `n = 0` with initial displacement `u0` and velocity `v0`; how the second starting
/// value is chosen is documented by each scheme. `step` advances `n -> n + 1` without allocating.
/// All methods are called from the one thread that owns the stepper.
pub trait OscillatorStepper: Send {
    /// Short identifier of the scheme (for reports), for example `theta` or `duffing-verlet`.
    fn name(&self) -> &'static str;
    /// Time step `h` in seconds (or the problem's time unit).
    fn step_size(&self) -> f64;
    /// Sets the initial conditions `u(0) = u0`, `u̇(0) = v0` and rewinds to `n = 0`.
    fn reset(&mut self, u0: f64, v0: f64);
    /// Advances one step.
    fn step(&mut self);
    /// Number of steps taken since the last `reset`.
    fn steps_taken(&self) -> u64;
    /// Displacement `u_n` at the current step.
    fn displacement(&self) -> f64;
    /// Velocity estimate at the current step: the backward difference `δ_{t-} u_n` for two-step
    /// schemes (it is the velocity the discrete energy uses), the state velocity for one-step ones.
    fn velocity(&self) -> f64;
    /// The scheme's own discrete energy at the current step, as defined in SEED.md for that
    /// scheme (exactly conserved by conservative schemes without damping).
    fn discrete_energy(&self) -> f64;
    /// The continuous Hamiltonian `H(u, u̇)` evaluated at `(u_n, velocity())`, for comparison.
    fn physical_energy(&self) -> f64;
    /// Energy removed by damping since `reset` (0 for undamped schemes), in the same units as
    /// `discrete_energy`, so that `discrete_energy + dissipated_energy` is conserved.
    fn dissipated_energy(&self) -> f64 {
        0.0
    }
    /// Solver and contact counters since `reset`.
    fn stats(&self) -> StepperStats {
        StepperStats::default()
    }
}
