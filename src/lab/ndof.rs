//! N-degree-of-freedom experiments: a Hamiltonian test system integrated by one method.

use super::{max_abs_difference, Duration, Summary, Trace};
use crate::analysis::{energy::max_relative_drift, frequency};
use crate::error::{check_finite, check_positive, ParamError};
use crate::schemes::ndof::{build_method_for_system, build_system, HamiltonianSystem, SystemSpec};

/// Step refinement of the Gauss-2 reference run.
pub const REFERENCE_REFINEMENT: u64 = 16;

/// A configured N-DOF experiment.
#[derive(Debug, Clone, PartialEq)]
pub struct NdofExperiment {
    /// The test system.
    pub system: SystemSpec,
    /// Method identifier (one of `schemes::ndof::METHOD_NAMES`).
    pub method: String,
    /// Time step h.
    pub h: f64,
    /// Initial amplitude: the pendulum's angle, or the amplitude of the chain's lowest
    /// normal-mode shape `q_i = a sin(π i/(n+1))`.
    pub amplitude: f64,
    /// Initial momentum scale: the pendulum's momentum, or `p_i = v sin(π i/(n+1))`.
    pub momentum: f64,
    /// How long to run (periods of the lowest linear frequency, or seconds).
    pub duration: Duration,
}

impl NdofExperiment {
    /// The initial state `y0 = [q; p]` for `system`.
    pub fn initial_state(&self, system: &dyn HamiltonianSystem) -> Vec<f64> {
        let n = system.degrees_of_freedom();
        let mut y = vec![0.0; 2 * n];
        for i in 0..n {
            let shape = if n == 1 {
                1.0
            } else {
                (std::f64::consts::PI * (i + 1) as f64 / (n + 1) as f64).sin()
            };
            y[i] = self.amplitude * shape;
            y[n + i] = self.momentum * shape;
        }
        y
    }

    /// Runs the experiment and its fine-step Gauss-2 reference, and measures it.
    pub fn run(&self) -> Result<(Trace, Summary), ParamError> {
        check_positive("h", self.h)?;
        check_finite("amplitude", self.amplitude)?;
        check_finite("momentum", self.momentum)?;
        let system = build_system(&self.system)?;
        let omega = lowest_linear_frequency(&self.system);
        let steps = self.duration.steps(self.h, omega)?;
        let (mut trace, stats) = integrate(
            system.as_ref(),
            &self.method,
            self.h,
            &self.initial_state(system.as_ref()),
            steps,
            1,
        )?;
        let fine_h = self.h / REFERENCE_REFINEMENT as f64;
        let (reference, _) = integrate(
            system.as_ref(),
            "gauss2",
            fine_h,
            &self.initial_state(system.as_ref()),
            steps * REFERENCE_REFINEMENT,
            REFERENCE_REFINEMENT,
        )?;
        let max_err = max_abs_difference(&trace.u, &reference.u);
        trace.reference = Some(reference.u);
        trace.reference_label = format!("gauss2 at h/{REFERENCE_REFINEMENT}");
        let measured = frequency::measure(&trace.u, self.h);
        let finite = trace.u.iter().chain(&trace.energy).all(|x| x.is_finite());
        let summary = Summary {
            system: system.name().into(),
            scheme: self.method.clone(),
            h: self.h,
            steps,
            omega_d: measured.map(|m| m.omega),
            period: measured.map(|m| m.period),
            omega_ref: omega,
            omega_ref_kind: "lowest linear frequency".into(),
            cents: measured.map(|m| frequency::cents(m.omega, omega)),
            omega_d_closed_form: None,
            max_rel_energy_error: max_relative_drift(&trace.energy),
            max_abs_error_vs_reference: Some(max_err),
            solver_iterations: stats.solver_iterations,
            max_iterations_per_step: stats.max_iterations_per_step,
            solver_failures: stats.solver_failures,
            impacts: 0,
            finite,
        };
        Ok((trace, summary))
    }
}

/// Lowest angular frequency of the linearised system (sets `Duration::Periods`):
/// `2√k sin(π/(2(n+1)))` for chains with fixed ends, `ω0` for the pendulum, `√μ` for the
/// circular Kepler orbit of radius 1.
pub fn lowest_linear_frequency(system: &SystemSpec) -> f64 {
    match *system {
        SystemSpec::Fpu { n, k, .. } | SystemSpec::LinearChain { n, k } => {
            2.0 * k.sqrt() * (std::f64::consts::PI / (2.0 * (n as f64 + 1.0))).sin()
        }
        SystemSpec::Pendulum { omega0 } => omega0,
        SystemSpec::Kepler { mu } => mu.sqrt(),
    }
}

fn integrate(
    system: &dyn HamiltonianSystem,
    method: &str,
    h: f64,
    y0: &[f64],
    steps: u64,
    stride: u64,
) -> Result<(Trace, crate::schemes::StepperStats), ParamError> {
    let n = system.degrees_of_freedom();
    let mut stepper = build_method_for_system(method, system)?;
    let mut y = y0.to_vec();
    let kept = (steps / stride + 1) as usize;
    let mut tr = Trace::with_capacity(kept);
    let mut push =
        |y: &[f64], k: u64| tr.push(k as f64 * h, y[0], y[n], system.hamiltonian(y), 0.0);
    push(&y, 0);
    for k in 1..=steps {
        stepper.step(system, h, &mut y);
        if k % stride == 0 {
            push(&y, k);
        }
    }
    Ok((tr, stepper.stats()))
}
