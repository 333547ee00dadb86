//! Stability at the extremes: sweeps of every model and scheme over extreme parameters,
//! shared by `tests/robustness/extremes.rs` (bounded) and `noether stress` (denser, longer).
//!
//! Each case is built from plain parameters and run for a bounded number of steps inside
//! `catch_unwind`. A case ends in one of four ways:
//! - **ok**: every output and energy value finite; for energy-conserving schemes the power
//!   balance `total + dissipated - work` stays constant to [`ENERGY_TOLERANCE`] relative to the
//!   largest energy seen (or the run's own stated tolerance: tighter for the oscillators, looser
//!   for an oversampled plate);
//! - **refused**: construction returned a [`ParamError`](crate::error::ParamError) naming
//!   field, value and allowed range for a setting the case declares conditionally unstable
//!   (for example θ = 1 above its stability limit); this is the required behaviour, not a
//!   failure;
//! - **failed**: a non-finite value, a balance error above tolerance, a refusal the case did not
//!   expect, a refusal that is not a clear [`ParamError`](crate::error::ParamError), or a model
//!   that reported divergence;
//! - **panicked**: counted as a failure.
//!
//! Families: [`oscillators`] (θ-family, exact, Duffing Störmer-Verlet and conservative, impact
//! with K from 1e3 to 1e16 and α from 1 to 4), [`plate`] (circular free and clamped, rectangular
//! simply supported, each [`crate::models::plate::PlateScheme`]) and [`string`] (stiff string,
//! every obstacle kind touching, far from and penetrating the string at rest).
//!
//! Runs on the calling thread (a test or the CLI), the cases on rayon's threads; nothing here
//! is real-time code.

mod case;
pub mod oscillators;
pub mod plate;
pub mod string;

pub use case::{
    check_finite_outputs, BalanceMeter, Case, Density, Outcome, RunResult, Status, ENERGY_TOLERANCE,
};

use rayon::prelude::*;
use std::fmt::Write as _;
use std::sync::atomic::{AtomicUsize, Ordering};

/// All cases of every family at the given density.
pub fn all_cases(density: Density) -> Vec<Case> {
    let mut cases = oscillators::cases(density);
    cases.extend(plate::cases(density));
    cases.extend(string::cases(density));
    cases
}

/// Per-family totals.
#[derive(Debug, Clone, Default)]
pub struct FamilyRow {
    /// Family name.
    pub family: String,
    /// Cases run.
    pub runs: usize,
    /// Cases refused with a clear error (expected).
    pub refused: usize,
    /// Detected divergences of amplitude-conditionally stable explicit schemes.
    pub diverged: usize,
    /// Failures (including panics).
    pub failures: usize,
    /// Largest relative power-balance error among conservative runs.
    pub worst_energy: f64,
    /// The case with that error.
    pub worst_label: String,
    /// Steps taken in total.
    pub steps: u64,
}

/// Summary of a sweep.
#[derive(Debug, Clone, Default)]
pub struct Summary {
    /// One row per family, in first-seen order.
    pub rows: Vec<FamilyRow>,
    /// Every failure: family, label, reason.
    pub failures: Vec<(String, String, String)>,
}

impl Summary {
    /// Builds the summary of a list of outcomes.
    pub fn of(outcomes: &[Outcome]) -> Self {
        let mut s = Summary::default();
        for o in outcomes {
            let idx = match s.rows.iter().position(|r| r.family == o.family) {
                Some(i) => i,
                None => {
                    s.rows.push(FamilyRow {
                        family: o.family.clone(),
                        ..FamilyRow::default()
                    });
                    s.rows.len() - 1
                }
            };
            let row = &mut s.rows[idx];
            row.runs += 1;
            row.steps += o.steps;
            match &o.status {
                Status::Ok => {}
                Status::Refused(_) => row.refused += 1,
                Status::Diverged(_) => row.diverged += 1,
                Status::Failed(why) => {
                    row.failures += 1;
                    s.failures
                        .push((o.family.clone(), o.label.clone(), why.clone()));
                }
            }
            if let Some(e) = o.energy_error {
                if e > row.worst_energy || row.worst_label.is_empty() {
                    row.worst_energy = row.worst_energy.max(e);
                    row.worst_label = o.label.clone();
                }
            }
        }
        s
    }

    /// Total number of failures.
    pub fn failure_count(&self) -> usize {
        self.failures.len()
    }

    /// The table printed by the test and the CLI.
    pub fn table(&self) -> String {
        let mut t = String::new();
        let _ = writeln!(
            t,
            "{:<44} {:>6} {:>8} {:>9} {:>9} {:>11} {:>12}  worst case",
            "family", "runs", "refused", "diverged", "failures", "steps", "worst dE/E"
        );
        let (mut runs, mut refused, mut fails, mut steps, mut worst) = (0, 0, 0, 0u64, 0.0f64);
        let mut diverged = 0;
        for r in &self.rows {
            let _ = writeln!(
                t,
                "{:<44} {:>6} {:>8} {:>9} {:>9} {:>11} {:>12.2e}  {}",
                r.family,
                r.runs,
                r.refused,
                r.diverged,
                r.failures,
                r.steps,
                r.worst_energy,
                r.worst_label
            );
            runs += r.runs;
            refused += r.refused;
            diverged += r.diverged;
            fails += r.failures;
            steps += r.steps;
            worst = worst.max(r.worst_energy);
        }
        let _ = writeln!(
            t,
            "{:<44} {:>6} {:>8} {:>9} {:>9} {:>11} {:>12.2e}",
            "TOTAL", runs, refused, diverged, fails, steps, worst
        );
        for (f, l, why) in &self.failures {
            let _ = writeln!(t, "FAILED [{f}] {l}: {why}");
        }
        t
    }
}

/// Runs every case, in parallel on the cores (rayon), calling `progress(done, total)` after
/// each (from the thread that ran it), and summarises; the outcomes keep the cases' order.
pub fn run(cases: Vec<Case>, progress: impl Fn(usize, usize) + Sync) -> (Vec<Outcome>, Summary) {
    let total = cases.len();
    let done = AtomicUsize::new(0);
    // A panicking case also prints its message through the panic hook (left as it is: the
    // hook is process-global and tests run in parallel); the outcome records it.
    let outcomes: Vec<Outcome> = cases
        .into_par_iter()
        .map(|c| {
            let o = c.execute();
            progress(done.fetch_add(1, Ordering::Relaxed) + 1, total);
            o
        })
        .collect();
    let summary = Summary::of(&outcomes);
    (outcomes, summary)
}
