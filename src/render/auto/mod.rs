//! `quality = "auto"` (model only what a scene requires): from a plate scene whose
//! `n_phi`, `n_psi`, `symmetry` and `sim_rate` describe the FULL model (or a string scene whose
//! `modes` and `sim_rate` do), choose the cheapest reduced model whose render stays within the
//! scene's tolerance of the full model's, and say why.
//!
//! - [`size`]: [`ModelSize`], the sizes and rate of one model (and how to apply them to a scene);
//! - [`ladder`]: what both ladders are made of ([`ladder::Candidate`], [`ladder::Plan`], the rate
//!   rule [`ladder::divisor_rate`]);
//! - [`spectrum`]: the scene's modal frequencies and the strike's band, without building a basis;
//! - [`plan`]: the symmetry decision and the ladder of candidates (transverse band × in-plane
//!   count × rate), each choice with its reason, cheapest first;
//! - [`plan_string`]: the string's ladder (mode count × rate, the contact scheme kept);
//! - [`verify`]: renders a short excerpt of the full model and of the candidates from the
//!   cheapest upward, measures the log-spectral distance (and the 50 ms L2 error) of each
//!   against the full model, and keeps the first within the tolerance (the full model if none);
//! - [`report`]: [`AutoReport`], the outcome as the render report carries it.
//!
//! Runs on the CLI thread (allocates, renders).

pub mod ladder;
pub mod plan;
pub mod plan_string;
pub mod report;
pub mod size;
pub mod spectrum;
pub mod verify;

pub use report::{AutoReport, CandidateResult};
pub use size::{string_size, ModelSize};
pub use verify::select;

use crate::error::Error;
use crate::scene::Scene;

/// The scene as `noether auto --write` saves it: `reduced` (from [`select`]) as TOML, headed by
/// comment lines giving the selection's tolerance, its measured errors and its reasons.
pub fn reduced_toml(reduced: &Scene, report: &AutoReport, origin: &str) -> Result<String, Error> {
    let body = toml::to_string(reduced)?;
    let mut head = format!(
        "# Reduced by `noether auto` from {origin}: {} (full model {}).\n# Verified over {} s: \
         LSD {:.4} dB (tolerance {} dB), L2(50 ms) {:.3e}; excerpt speed-up {:.2}.\n",
        report.chosen.label(),
        report.full.label(),
        report.excerpt_seconds,
        report.lsd_db,
        report.tolerance_db,
        report.l2_50ms,
        report.speedup
    );
    for r in &report.reasons {
        head.push_str(&format!("# - {r}\n"));
    }
    Ok(head + &body)
}
