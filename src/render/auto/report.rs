//! The outcome of `quality = "auto"` as the render report carries it ([`AutoReport`], with one
//! [`CandidateResult`] per candidate rendered); [`super::verify`] fills it in.
//!
//! Plain data; any thread.

use super::ladder::Candidate;
use super::size::ModelSize;
use serde::Serialize;

/// One candidate as verified.
#[derive(Debug, Clone, Serialize)]
pub struct CandidateResult {
    /// What was tried.
    pub candidate: Candidate,
    /// Wall-clock seconds of its excerpt's simulation loop.
    pub wall_seconds: f64,
    /// Wall-clock seconds spent building or loading its modal data.
    pub build_seconds: f64,
    /// Worst-pickup log-spectral distance to the full model over the excerpt (dB).
    pub lsd_db: f64,
    /// Worst-pickup relative L2 error to the full model over the first 50 ms.
    pub l2_50ms: f64,
    /// Whether it is within the tolerance (and finite).
    pub passed: bool,
}

/// The `auto` section of the render report.
#[derive(Debug, Clone, Serialize)]
pub struct AutoReport {
    /// Tolerance on the log-spectral distance (dB).
    pub tolerance_db: f64,
    /// Tolerance on the 50 ms relative L2 error, if set.
    pub l2_tolerance: Option<f64>,
    /// Length of the verification renders (s): `min(quality.excerpt_seconds, output.seconds)`.
    pub excerpt_seconds: f64,
    /// The scene's own model (the reference).
    pub full: ModelSize,
    /// The model rendered.
    pub chosen: ModelSize,
    /// Whether no candidate passed and the full model is kept.
    pub chosen_is_full: bool,
    /// Measured worst-pickup log-spectral distance of the chosen model to the full model over
    /// the excerpt (dB; 0 when the full model is kept).
    pub lsd_db: f64,
    /// Measured worst-pickup relative L2 error over the first 50 ms (0 when full).
    pub l2_50ms: f64,
    /// Simulation wall time of the full model's excerpt (s).
    pub full_wall_seconds: f64,
    /// Simulation wall time of the chosen model's excerpt (s).
    pub chosen_wall_seconds: f64,
    /// `full_wall_seconds / chosen_wall_seconds` (1 when full).
    pub speedup: f64,
    /// One sentence per choice.
    pub reasons: Vec<String>,
    /// Every candidate rendered, in the order tried.
    pub candidates: Vec<CandidateResult>,
    /// Candidates of the ladder not rendered (costlier than the one chosen).
    pub untried: usize,
    /// Wall-clock seconds of the whole selection (renders, bases, comparisons).
    pub selection_wall_seconds: f64,
}
