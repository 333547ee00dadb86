//! What the candidate ladders of `quality = "auto"` are made of, for plates ([`super::plan`])
//! and strings ([`super::plan_string`]) alike: a [`Candidate`] (one reduced model), the
//! [`Plan`] (the ladder and its reasons), the heard band's limit and the rate rule
//! [`divisor_rate`].
//!
//! Plain data and pure functions; any thread.

use super::size::ModelSize;
use crate::scene::plate::Symmetry;

/// Highest frequency anyone hears (Hz).
pub const HEARING_LIMIT: f64 = 20_000.0;

/// One reduced model to verify.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Candidate {
    /// Its sizes and rate.
    pub size: ModelSize,
    /// Fraction of the heard band its transverse modes cover (1: all of it); for a string,
    /// its top mode over the heard band, `f_max / f_hear` (at least 1 when it covers it).
    pub band_fraction: f64,
    /// Fraction of the full in-plane count it keeps (1 for a string).
    pub psi_fraction: f64,
    /// Estimated work per simulated second, `fs (N_Φ + nnz)`, `nnz` estimated from the
    /// tensor densities of the default gong (ordering only; the verification measures time).
    pub estimated_cost: f64,
}

/// The ladder and why it looks as it does.
#[derive(Debug, Clone)]
pub struct Plan {
    /// The scene's own model (the reference).
    pub full: ModelSize,
    /// The basis symmetry every candidate uses.
    pub symmetry: Symmetry,
    /// Heard band `min(output Nyquist, 20 kHz)` (Hz).
    pub f_hear: f64,
    /// Reasons, one sentence per choice.
    pub reasons: Vec<String>,
    /// Candidates, cheapest (estimated) first; the full model is not among them.
    pub candidates: Vec<Candidate>,
}

/// The lowest rate `scene_rate / m` (integer `m`, integer result when the scene's rate is an
/// integer, at least 1 kHz) that is at least `need`; the scene's rate when none is lower.
pub fn divisor_rate(scene_rate: f64, need: f64) -> f64 {
    let integral = scene_rate.fract() == 0.0;
    let mut best = scene_rate;
    for m in 2..=64u32 {
        let r = scene_rate / f64::from(m);
        if r < need || r < 1_000.0 {
            break;
        }
        if !integral || (scene_rate as u64) % u64::from(m) == 0 {
            best = r;
        }
    }
    best
}
