//! One-oscillator experiments: any scheme of SEED.md 1.1-1.4 from given initial conditions.

use super::{max_abs_difference, Duration, Summary, Trace};
use crate::analysis::{analytic, energy::max_relative_drift, frequency};
use crate::error::{check_finite, check_positive, ParamError};
use crate::schemes::duffing::DuffingVerlet;
use crate::schemes::{build_oscillator, OscillatorSpec, OscillatorStepper, StepperStats};

/// Step refinement of the reference run used when no closed-form solution exists.
pub const REFERENCE_REFINEMENT: u64 = 16;

/// A configured one-oscillator experiment.
#[derive(Debug, Clone, PartialEq)]
pub struct OscillatorExperiment {
    /// The scheme and its parameters.
    pub spec: OscillatorSpec,
    /// Time step h.
    pub h: f64,
    /// Initial displacement u(0).
    pub u0: f64,
    /// Initial velocity u̇(0).
    pub v0: f64,
    /// How long to run.
    pub duration: Duration,
}

/// Result of [`OscillatorExperiment::run`].
#[derive(Debug, Clone)]
pub struct OscillatorRun {
    /// The recorded series.
    pub trace: Trace,
    /// The summary figures.
    pub summary: Summary,
}

impl OscillatorExperiment {
    /// Natural angular frequency of the linear part (used for `Duration::Periods`).
    pub fn linear_omega0(&self) -> Option<f64> {
        match self.spec {
            OscillatorSpec::Theta { omega0, .. }
            | OscillatorSpec::Exact { omega0, .. }
            | OscillatorSpec::DuffingVerlet { omega0, .. }
            | OscillatorSpec::DuffingConservative { omega0, .. } => Some(omega0),
            OscillatorSpec::Impact {
                mass, stiffness, ..
            } => (stiffness > 0.0 && mass > 0.0).then(|| (stiffness / mass).sqrt()),
        }
    }

    /// Name of the physical system (`linear`, `duffing`, `impact`).
    pub fn system_name(&self) -> &'static str {
        match self.spec {
            OscillatorSpec::Theta { .. } | OscillatorSpec::Exact { .. } => "linear",
            OscillatorSpec::DuffingVerlet { .. } | OscillatorSpec::DuffingConservative { .. } => {
                "duffing"
            }
            OscillatorSpec::Impact { .. } => "impact",
        }
    }

    /// Number of steps this experiment takes (validates the duration).
    pub fn steps(&self) -> Result<u64, ParamError> {
        check_positive("h", self.h)?;
        match (self.duration, self.linear_omega0()) {
            (Duration::Periods(p), None) => Err(ParamError::new(
                "periods",
                p,
                "not available without a linear spring (stiffness = 0): give --seconds",
            )),
            (d, w) => d.steps(self.h, w.unwrap_or(1.0)),
        }
    }

    /// Runs the experiment and measures it.
    pub fn run(&self) -> Result<OscillatorRun, ParamError> {
        check_finite("u0", self.u0)?;
        check_finite("v0", self.v0)?;
        let steps = self.steps()?;
        let mut stepper = build_oscillator(&self.spec, self.h)?;
        if let OscillatorSpec::DuffingVerlet { omega0, gamma } = self.spec {
            DuffingVerlet::new(omega0, gamma, self.h)?.check_amplitude(self.u0, self.v0)?;
        }
        let (mut trace, stats) = record(stepper.as_mut(), self.u0, self.v0, steps, 1);
        let (reference, label) = self.reference(&trace.t, steps)?;
        trace.reference_label = label;
        let max_err = reference.as_ref().map(|r| max_abs_difference(&trace.u, r));
        trace.reference = reference;
        let summary = self.summarise(&trace, steps, stats, max_err)?;
        Ok(OscillatorRun { trace, summary })
    }

    /// Closed-form solution at `t` where one exists, else the same scheme at `h/16`.
    fn reference(&self, t: &[f64], steps: u64) -> Result<(Option<Vec<f64>>, String), ParamError> {
        let (u0, v0) = (self.u0, self.v0);
        match self.spec {
            OscillatorSpec::Theta { omega0, .. } => Ok((
                Some(
                    t.iter()
                        .map(|&t| analytic::damped_linear(omega0, 0.0, u0, v0, t).0)
                        .collect(),
                ),
                "exact solution".into(),
            )),
            OscillatorSpec::Exact { omega0, xi } => Ok((
                Some(
                    t.iter()
                        .map(|&t| analytic::damped_linear(omega0, xi, u0, v0, t).0)
                        .collect(),
                ),
                "exact solution".into(),
            )),
            OscillatorSpec::DuffingVerlet { omega0, gamma }
            | OscillatorSpec::DuffingConservative { omega0, gamma, .. }
                if v0 == 0.0 =>
            {
                let exact = analytic::DuffingFree::new(omega0, gamma, u0)?;
                Ok((
                    Some(t.iter().map(|&t| exact.displacement(t)).collect()),
                    "exact solution u0 cn(Ωt, m)".into(),
                ))
            }
            _ => {
                let fine_h = self.h / REFERENCE_REFINEMENT as f64;
                let mut fine = build_oscillator(&self.spec, fine_h)?;
                let (trace, _) = record(
                    fine.as_mut(),
                    u0,
                    v0,
                    steps * REFERENCE_REFINEMENT,
                    REFERENCE_REFINEMENT,
                );
                Ok((
                    Some(trace.u),
                    format!("same scheme at h/{REFERENCE_REFINEMENT}"),
                ))
            }
        }
    }

    /// Reference frequency for the cents figure, and what it is.
    fn reference_frequency(&self) -> Result<(f64, String), ParamError> {
        Ok(match self.spec {
            OscillatorSpec::Theta { omega0, .. } => (omega0, "omega0".into()),
            OscillatorSpec::Exact { omega0, xi } if xi < 1.0 => {
                let wd = omega0 * (1.0 - xi * xi).sqrt();
                let seen = frequency::fold_to_band(wd, self.h);
                if (seen - wd).abs() <= 1e-12 * wd {
                    (wd, "damped natural frequency omega0*sqrt(1-xi^2)".into())
                } else {
                    (seen, format!("omega0*sqrt(1-xi^2) = {wd} as the samples show it (aliased into [0, pi/h])"))
                }
            }
            OscillatorSpec::Exact { omega0, .. } => (omega0, "omega0".into()),
            OscillatorSpec::DuffingVerlet { omega0, gamma }
            | OscillatorSpec::DuffingConservative { omega0, gamma, .. } => {
                let exact = analytic::DuffingFree::new(
                    omega0,
                    gamma,
                    duffing_amplitude(omega0, gamma, self.u0, self.v0),
                )?;
                (
                    exact.angular_frequency(),
                    "exact nonlinear frequency 2*pi/T, T = 4K(m)/Omega".into(),
                )
            }
            OscillatorSpec::Impact { gap, .. } => {
                let w0 = self.linear_omega0().unwrap_or(f64::NAN);
                let amplitude = (self.u0 * self.u0 + (self.v0 / w0).powi(2)).sqrt();
                if gap >= 0.0 && amplitude > gap && self.u0 <= gap {
                    // Rigid-wall limit (K -> inf): the free harmonic arc from the wall back to
                    // the wall lasts (2π - 2 acos(d/A))/ω0 and the impact is instantaneous.
                    let period = (2.0 * std::f64::consts::PI - 2.0 * (gap / amplitude).acos()) / w0;
                    (
                        std::f64::consts::TAU / period,
                        "rigid-wall limit 2*pi/T, T = (2*pi - 2*acos(d/A))/omega0".into(),
                    )
                } else {
                    (
                        w0,
                        "omega0 of the linear spring (the wall is out of reach)".into(),
                    )
                }
            }
        })
    }

    fn summarise(
        &self,
        trace: &Trace,
        steps: u64,
        stats: StepperStats,
        max_err: Option<f64>,
    ) -> Result<Summary, ParamError> {
        let measured = frequency::measure(&trace.u, self.h);
        let (omega_ref, omega_ref_kind) = self.reference_frequency()?;
        let closed = match self.spec {
            OscillatorSpec::Theta { omega0, theta } => {
                analytic::theta_frequency(theta, self.h, omega0)
            }
            OscillatorSpec::Exact { xi, .. } if xi < 1.0 => Some(omega_ref),
            _ => None,
        };
        let finite = trace
            .u
            .iter()
            .chain(&trace.v)
            .chain(&trace.energy)
            .all(|x| x.is_finite());
        Ok(Summary {
            system: self.system_name().into(),
            scheme: self.spec.scheme_name().into(),
            h: self.h,
            steps,
            omega_d: measured.map(|m| m.omega),
            period: measured.map(|m| m.period),
            omega_ref,
            omega_ref_kind,
            cents: measured.map(|m| frequency::cents(m.omega, omega_ref)),
            omega_d_closed_form: closed,
            max_rel_energy_error: max_relative_drift(&trace.balance()),
            max_abs_error_vs_reference: max_err,
            solver_iterations: stats.solver_iterations,
            max_iterations_per_step: stats.max_iterations_per_step,
            solver_failures: stats.solver_failures,
            impacts: stats.impacts,
            finite,
        })
    }
}

/// Amplitude (largest displacement) of the free Duffing motion with energy
/// `H0 = ½v0² + ½ω0²u0² + ¼γu0⁴`: the positive root of `½ω0²A² + ¼γA⁴ = H0`. The period of a
/// free Duffing oscillation depends on its energy only, so this gives the exact reference
/// period for any initial condition.
pub fn duffing_amplitude(omega0: f64, gamma: f64, u0: f64, v0: f64) -> f64 {
    let w2 = omega0 * omega0;
    let h0 = 0.5 * v0 * v0 + 0.5 * w2 * u0 * u0 + 0.25 * gamma * u0.powi(4);
    if gamma > 0.0 {
        // A² = (√(ω0⁴ + 4γH0) - ω0²)/γ, written without cancellation.
        (4.0 * h0 / (w2 + (w2 * w2 + 4.0 * gamma * h0).sqrt())).sqrt()
    } else {
        (2.0 * h0 / w2).sqrt()
    }
}

/// Runs `steps` steps from `(u0, v0)`, keeping every `stride`-th state (and the first).
fn record(
    stepper: &mut dyn OscillatorStepper,
    u0: f64,
    v0: f64,
    steps: u64,
    stride: u64,
) -> (Trace, StepperStats) {
    let kept = (steps / stride + 1) as usize;
    let mut tr = Trace::with_capacity(kept);
    stepper.reset(u0, v0);
    let h = stepper.step_size();
    let mut push = |s: &dyn OscillatorStepper, n: u64| {
        tr.push(
            n as f64 * h,
            s.displacement(),
            s.velocity(),
            s.discrete_energy(),
            s.dissipated_energy(),
        )
    };
    push(stepper, 0);
    for n in 1..=steps {
        stepper.step();
        if n % stride == 0 {
            push(stepper, n);
        }
    }
    let stats = stepper.stats();
    (tr, stats)
}
