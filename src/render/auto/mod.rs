//! `quality = "auto"` (issue 6, "model only what a scene requires"): from a plate scene whose
//! `n_phi`, `n_psi`, `symmetry` and `sim_rate` describe the FULL model, choose the cheapest
//! reduced model whose render stays within the scene's tolerance of the full model's, and say
//! why.
//!
//! - [`spectrum`]: the scene's modal frequencies and the strike's band, without building a basis;
//! - [`plan`]: the symmetry decision and the ladder of candidates (transverse band × in-plane
//!   count × rate), each choice with its reason, cheapest first;
//! - [`verify`]: renders a short excerpt of the full model and of the candidates from the
//!   cheapest upward, measures the log-spectral distance (and the 50 ms L2 error) of each
//!   against the full model, and keeps the first within the tolerance (the full model if none).
//!
//! Runs on the CLI thread (allocates, renders).

pub mod plan;
pub mod spectrum;
pub mod verify;

pub use verify::{select, AutoReport, CandidateResult};

use crate::scene::plate::Symmetry;
use crate::scene::Scene;
use serde::Serialize;

/// The sizes and rate of one plate model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ModelSize {
    /// Transverse modes N_Φ (in the model's basis).
    pub n_phi: usize,
    /// In-plane modes N_Ψ (in the model's basis).
    pub n_psi: usize,
    /// Basis symmetry.
    pub symmetry: Symmetry,
    /// Simulation rate (Hz).
    pub sim_rate: f64,
    /// Highest transverse frequency of the basis (Hz).
    pub f_max_hz: f64,
}

impl ModelSize {
    /// `scene` with its plate resized to `self` and its `[quality]` table removed (the result
    /// is a plain scene: rendering it renders exactly this model). Errors if the scene has no
    /// plate or the result does not validate.
    pub fn apply(&self, scene: &Scene) -> Result<Scene, String> {
        let mut s = scene.clone();
        let p = s
            .plate
            .as_mut()
            .ok_or("quality = \"auto\" is implemented for plate scenes only")?;
        p.n_phi = self.n_phi;
        p.n_psi = self.n_psi;
        p.symmetry = self.symmetry;
        p.sim_rate = self.sim_rate;
        s.quality = None;
        s.validate().map_err(|e| e.to_string())?;
        Ok(s)
    }

    /// `n_phi x n_psi, symmetry, rate` for logs.
    pub fn label(&self) -> String {
        format!(
            "{} x {} {}, {} Hz (band {:.0} Hz)",
            self.n_phi,
            self.n_psi,
            match self.symmetry {
                Symmetry::Full => "full",
                Symmetry::StrikeMirror => "mirror",
            },
            self.sim_rate,
            self.f_max_hz
        )
    }
}

/// The scene as `noether auto --write` saves it: `reduced` (from [`select`]) as TOML, headed by
/// comment lines giving the selection's tolerance, its measured errors and its reasons.
pub fn reduced_toml(reduced: &Scene, report: &AutoReport, origin: &str) -> Result<String, String> {
    let body = toml::to_string(reduced).map_err(|e| format!("writing the reduced scene: {e}"))?;
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
