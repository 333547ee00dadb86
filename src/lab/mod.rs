//! The lecture's integrator experiments as runnable configurations (SEED.md sections 1-2).
//!
//! A [`OscillatorExperiment`] runs one scalar scheme, records `u`, the velocity and the energies
//! at every step, compares with the closed-form solution where one exists (or a reference run
//! at a 16× finer step where none does), and summarises the run in a [`Summary`] (measured
//! frequency, cents, energy error). [`NdofExperiment`] does the same for N-degree-of-freedom
//! systems. [`report`] writes CSV and PNG figures; [`table`] prints the θ-family table.
//!
//! Everything here runs offline on the calling thread and allocates freely.

pub mod figures;
pub mod ndof;
pub mod oscillator;
pub mod report;
pub mod table;

pub use ndof::NdofExperiment;
pub use oscillator::OscillatorExperiment;

use crate::error::{check_positive, ParamError};
use serde::Serialize;

/// Largest number of steps one lab run may take (memory: four f64 series of this length).
pub const MAX_STEPS: u64 = 20_000_000;

/// How long to simulate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Duration {
    /// A number of periods of the linear natural frequency (`2π/ω0`).
    Periods(f64),
    /// A time span in the problem's time unit.
    Seconds(f64),
}

impl Duration {
    /// Number of steps of size `h` covering this duration, for natural angular frequency
    /// `omega0`; errors if it is not positive or exceeds [`MAX_STEPS`].
    pub fn steps(self, h: f64, omega0: f64) -> Result<u64, ParamError> {
        let (field, value, span) = match self {
            Duration::Periods(p) => (
                "periods",
                p,
                check_positive("periods", p)? * std::f64::consts::TAU / omega0,
            ),
            Duration::Seconds(s) => ("seconds", s, check_positive("seconds", s)?),
        };
        let steps = (span / h).round();
        if !(1.0..=MAX_STEPS as f64).contains(&steps) {
            return Err(ParamError::new(
                field,
                value,
                format!("a duration of 1 to {MAX_STEPS} steps of h = {h}"),
            ));
        }
        Ok(steps as u64)
    }
}

/// Time series recorded by a lab run, one entry per step `n = 0..=steps`.
#[derive(Debug, Clone, Default)]
pub struct Trace {
    /// Times `t_n = n h`.
    pub t: Vec<f64>,
    /// Displacement `u_n` (first coordinate `q_1` for N-DOF systems).
    pub u: Vec<f64>,
    /// Velocity estimate (`δ_{t-}u_n` for two-step schemes; `p_1` for N-DOF systems).
    pub v: Vec<f64>,
    /// The scheme's discrete energy (the Hamiltonian for N-DOF systems).
    pub energy: Vec<f64>,
    /// Energy removed by damping since the start (zeros for undamped schemes), so that
    /// `energy + dissipated` is the conserved quantity.
    pub dissipated: Vec<f64>,
    /// Reference solution at `t_n` (closed form or fine-step run), when available.
    pub reference: Option<Vec<f64>>,
    /// What the reference is (`"exact solution"`, `"same scheme, h/16"`, ...).
    pub reference_label: String,
}

/// Summary of a lab run, printed as text or as one JSON object (`--json`).
#[derive(Debug, Clone, Serialize)]
pub struct Summary {
    /// System simulated (`linear`, `duffing`, `impact`, `fpu`, ...).
    pub system: String,
    /// Scheme or method identifier.
    pub scheme: String,
    /// Time step h.
    pub h: f64,
    /// Steps taken.
    pub steps: u64,
    /// Angular frequency measured from the simulated signal (upward crossings); `null` when
    /// the signal does not oscillate.
    pub omega_d: Option<f64>,
    /// Period `2π/omega_d`.
    pub period: Option<f64>,
    /// Reference angular frequency the cents are measured against.
    pub omega_ref: f64,
    /// What `omega_ref` is (`"omega0"`, `"exact nonlinear frequency"`, ...).
    pub omega_ref_kind: String,
    /// `1200 log2(omega_d / omega_ref)`.
    pub cents: Option<f64>,
    /// Closed-form numerical frequency of the scheme, where one exists (θ-family, exact).
    pub omega_d_closed_form: Option<f64>,
    /// Largest `|E_n - E_0| / |E_0|` of the conserved quantity over the run (discrete energy
    /// plus dissipated energy for damped schemes).
    pub max_rel_energy_error: f64,
    /// Largest absolute deviation between the numerical and reference solutions, if any.
    pub max_abs_error_vs_reference: Option<f64>,
    /// Nonlinear solver iterations, total.
    pub solver_iterations: u64,
    /// Largest number of solver iterations in one step.
    pub max_iterations_per_step: u32,
    /// Steps where the solver hit its cap and used its fallback.
    pub solver_failures: u64,
    /// Number of impacts (impact oscillator only).
    pub impacts: u64,
    /// Whether every recorded value is finite.
    pub finite: bool,
}

impl Summary {
    /// Multi-line human-readable rendering.
    pub fn to_text(&self) -> String {
        let opt = |v: Option<f64>, prec: usize| {
            v.map_or("n/a (no oscillation)".to_string(), |x| {
                format!("{x:.prec$}")
            })
        };
        let mut s = String::new();
        s += &format!(
            "system {}, scheme {}, h = {}, {} steps\n",
            self.system, self.scheme, self.h, self.steps
        );
        s += &format!("  omega_d (measured)     {}\n", opt(self.omega_d, 12));
        if let Some(w) = self.omega_d_closed_form {
            s += &format!("  omega_d (closed form)  {w:.12}\n");
        }
        s += &format!("  period                 {}\n", opt(self.period, 12));
        s += &format!(
            "  reference              {} = {:.12}\n",
            self.omega_ref_kind, self.omega_ref
        );
        s += &format!("  deviation              {} cents\n", opt(self.cents, 6));
        s += &format!(
            "  max rel energy error   {:.3e}\n",
            self.max_rel_energy_error
        );
        if let Some(e) = self.max_abs_error_vs_reference {
            s += &format!("  max |u - reference|    {e:.3e}\n");
        }
        if self.solver_iterations > 0 {
            s += &format!(
                "  solver                 {} iterations, max {} per step, {} capped\n",
                self.solver_iterations, self.max_iterations_per_step, self.solver_failures
            );
        }
        if self.impacts > 0 {
            s += &format!("  impacts                {}\n", self.impacts);
        }
        if !self.finite {
            s += "  WARNING: non-finite values (the scheme is unstable at this step)\n";
        }
        s
    }
}

impl Trace {
    /// An empty trace with room for `n` samples in every series.
    pub fn with_capacity(n: usize) -> Self {
        Self {
            t: Vec::with_capacity(n),
            u: Vec::with_capacity(n),
            v: Vec::with_capacity(n),
            energy: Vec::with_capacity(n),
            dissipated: Vec::with_capacity(n),
            ..Self::default()
        }
    }

    /// Appends one sample: time, displacement, velocity, energy, dissipated energy.
    pub fn push(&mut self, t: f64, u: f64, v: f64, energy: f64, dissipated: f64) {
        self.t.push(t);
        self.u.push(u);
        self.v.push(v);
        self.energy.push(energy);
        self.dissipated.push(dissipated);
    }

    /// The conserved quantity `energy + dissipated` at every step.
    pub fn balance(&self) -> Vec<f64> {
        self.energy
            .iter()
            .zip(&self.dissipated)
            .map(|(e, d)| e + d)
            .collect()
    }
}

/// Largest absolute difference between two equally long series.
pub(crate) fn max_abs_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}
