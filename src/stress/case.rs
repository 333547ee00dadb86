//! One case of the extremes sweep and what it needs to run: the [`Case`] (identity, whether a
//! refusal or a divergence is acceptable, the run), its [`RunResult`] and classified
//! [`Outcome`], the power-balance meter and tolerance, the sweep [`Density`]. The families
//! ([`super::oscillators`], [`super::plate`], [`super::string`]) build cases from these;
//! [`super::run`] runs them.
//!
//! Runs on the calling thread (a test or the CLI); nothing here is real-time code.

use crate::error::ParamError;
use crate::render::source::EnergyTerms;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Relative power-balance tolerance of the conservative schemes: `max_n |B_n - B_0| / E_max`
/// with `B = total + dissipated - work` sampled every step and `E_max` the largest of
/// `|total|`, `dissipated`, `|work|` over the run. Each step rounds at about `1e-16` of the
/// energy scale, but stiff solves amplify it: the string's per-node contact solve at
/// K = 1e16 has a stiffness ratio `h²K/μ ≈ 4e9` and stops at a relative step of 1e-13
/// (`NEWTON_TOL`), and the measured worst case of the bounded sweep is 2.1e-9 (penetrating sitar
/// bridge, K = 1e16, 960 steps; 1.65e-9 on re-measuring, fretboard touching at K = 1e13). It is
/// the strings' and plates' bound; the oscillators, which reach 1e-12 to 3e-11, are held to a
/// tighter one of their own (`stress::oscillators`). `1e-8` keeps a factor 5 of
/// margin on that, while a real leak of the energy identity (a wrong coefficient, a missed
/// force term) shows at 1e-6 or above within a few hundred steps.
pub const ENERGY_TOLERANCE: f64 = 1e-8;

/// How dense and long the sweep is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Density {
    /// Bounded sweep for `cargo test` (a few seconds at opt-level 3 per family).
    Quick,
    /// The `noether stress` sweep: more values per axis, more modes, more steps.
    Full,
}

/// What happened to one case.
#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    /// Ran to the end within tolerance.
    Ok,
    /// Construction refused the (expected-unstable) setting with this error.
    Refused(String),
    /// An amplitude-conditionally stable explicit scheme diverged; detected and silenced.
    Diverged(String),
    /// Something went wrong (the reason).
    Failed(String),
}

/// One case's outcome.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// Family (table row), for example `plate circular-free conservative`.
    pub family: String,
    /// Parameters of the case.
    pub label: String,
    /// Result.
    pub status: Status,
    /// Relative power-balance error (conservative schemes that ran), else `None`.
    pub energy_error: Option<f64>,
    /// Steps taken.
    pub steps: u64,
}

/// What a case runner returns when the case ran (construction succeeded).
#[derive(Debug, Clone, Default)]
pub struct RunResult {
    /// Relative power-balance error, when the scheme is energy conserving.
    pub energy_error: Option<f64>,
    /// Steps taken.
    pub steps: u64,
    /// A failure found while running (non-finite value, divergence), if any.
    pub failure: Option<String>,
    /// Whether the failure is a divergence the model detected (outputs silenced).
    pub diverged: bool,
    /// The run's own balance tolerance when it differs from [`ENERGY_TOLERANCE`] for a stated
    /// reason (tighter for the oscillators, looser for an oversampled plate: see the family's
    /// module), else `None`.
    pub tolerance: Option<f64>,
}

/// One case: its identity, whether refusal is acceptable, and how to run it.
pub struct Case {
    /// Family (table row).
    pub family: String,
    /// Parameters, for the failure list.
    pub label: String,
    /// Whether the setting is conditionally unstable, so construction may (must) refuse it.
    pub may_refuse: bool,
    /// Whether the scheme is explicit with an amplitude-dependent stability limit, so a
    /// detected divergence is reported as such rather than as a failure.
    pub may_diverge: bool,
    /// Builds and runs the case: `Err` is a construction refusal.
    pub run: Box<dyn FnOnce() -> Result<RunResult, ParamError> + Send>,
}

impl Case {
    /// A case from its parts.
    pub fn new(
        family: impl Into<String>,
        label: impl Into<String>,
        may_refuse: bool,
        run: impl FnOnce() -> Result<RunResult, ParamError> + Send + 'static,
    ) -> Self {
        Self {
            family: family.into(),
            label: label.into(),
            may_refuse,
            may_diverge: false,
            run: Box::new(run),
        }
    }

    /// Marks the case as an amplitude-conditionally stable explicit scheme (see [`Status`]).
    pub fn may_diverge(mut self) -> Self {
        self.may_diverge = true;
        self
    }

    /// Runs the case under `catch_unwind` and classifies the result.
    pub fn execute(self) -> Outcome {
        let Case {
            family,
            label,
            may_refuse,
            may_diverge,
            run,
        } = self;
        let result = catch_unwind(AssertUnwindSafe(run));
        let (status, energy_error, steps) = match result {
            Err(p) => {
                let msg = p
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                    .unwrap_or_else(|| "non-string panic".into());
                (Status::Failed(format!("panic: {msg}")), None, 0)
            }
            Ok(Err(e)) => {
                let clear = !e.field.is_empty() && !e.value.is_empty() && !e.allowed.is_empty();
                if !clear {
                    (Status::Failed(format!("unclear error: {e:?}")), None, 0)
                } else if may_refuse {
                    (Status::Refused(e.to_string()), None, 0)
                } else {
                    (Status::Failed(format!("unexpected refusal: {e}")), None, 0)
                }
            }
            Ok(Ok(r)) => {
                let tol = r.tolerance.unwrap_or(ENERGY_TOLERANCE);
                let status = match (&r.failure, r.energy_error) {
                    (Some(f), _) if r.diverged && may_diverge => Status::Diverged(f.clone()),
                    (Some(f), _) => Status::Failed(f.clone()),
                    (None, Some(e)) if e.is_nan() || e > tol => {
                        Status::Failed(format!("power balance error {e:.3e} > {tol:.1e}"))
                    }
                    _ => Status::Ok,
                };
                (status, r.energy_error, r.steps)
            }
        };
        Outcome {
            family,
            label,
            status,
            energy_error,
            steps,
        }
    }
}

/// Tracks the power balance and finiteness of a run from its energy terms.
#[derive(Debug, Clone, Default)]
pub struct BalanceMeter {
    first: Option<f64>,
    scale: f64,
    worst: f64,
    non_finite: bool,
}

impl BalanceMeter {
    /// Records one sample of the energy terms.
    pub fn record(&mut self, e: &EnergyTerms) {
        let vals = [e.kinetic, e.linear, e.nonlinear, e.dissipated, e.work];
        if vals.iter().any(|v| !v.is_finite()) {
            self.non_finite = true;
            return;
        }
        let b = e.balance();
        let b0 = *self.first.get_or_insert(b);
        self.scale = self
            .scale
            .max(e.total().abs())
            .max(e.dissipated.abs())
            .max(e.work.abs());
        self.worst = self.worst.max((b - b0).abs());
    }

    /// Whether a non-finite energy term was seen.
    pub fn non_finite(&self) -> bool {
        self.non_finite
    }

    /// `max |B_n - B_0| / E_max` (0 when the run never had energy).
    pub fn relative_error(&self) -> f64 {
        if self.scale > 0.0 {
            self.worst / self.scale
        } else {
            self.worst
        }
    }
}

/// Checks a slice of outputs for non-finite values; returns a failure message if any.
pub fn check_finite_outputs(what: &str, step: u64, values: &[f64]) -> Option<String> {
    values
        .iter()
        .position(|v| !v.is_finite())
        .map(|i| format!("{what}[{i}] = {} at step {step}", values[i]))
}
