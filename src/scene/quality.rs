//! The `[quality]` table of a scene: render the model as given, or let `noether` choose the
//! cheapest model that stays within a stated distance of it (`mode = "auto"`).
//!
//! ```toml
//! [quality]
//! mode = "auto"          # "as-given" (default) or "auto"
//! tolerance_db = 1.0     # largest log-spectral distance to the full model (dB)
//! l2_tolerance = 0.05    # optional: largest relative L2 error over the first 50 ms
//! excerpt_seconds = 0.25 # optional: length of the verification renders (s)
//! ```
//!
//! With `mode = "auto"` the scene's own `n_phi`, `n_psi`, `symmetry` and `sim_rate` (a string
//! scene's `modes` and `sim_rate`) describe the FULL model: the upper bound of the search and the reference every candidate is verified
//! against ([`crate::render::auto`]). Parsed and validated on the thread loading the scene.

use crate::error::{check_closed, ParamError};
use serde::{Deserialize, Serialize};

/// Smallest accepted `quality.tolerance_db` (dB).
pub const TOLERANCE_DB_MIN: f64 = 1e-9;
/// Largest accepted `quality.tolerance_db` (dB).
pub const TOLERANCE_DB_MAX: f64 = 60.0;
/// Default length of the verification excerpt (s).
pub const DEFAULT_EXCERPT_SECONDS: f64 = 0.25;

/// What `noether render` does with the scene's model sizes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum QualityMode {
    /// Render `n_phi`, `n_psi`, `symmetry` and `sim_rate` exactly as written.
    #[default]
    AsGiven,
    /// Choose the cheapest verified model within the tolerance (plates and strings).
    Auto,
}

fn default_tolerance_db() -> f64 {
    1.0
}

fn default_excerpt() -> f64 {
    DEFAULT_EXCERPT_SECONDS
}

/// The `[quality]` table.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Quality {
    /// `as-given` (default) or `auto`.
    #[serde(default)]
    pub mode: QualityMode,
    /// Largest log-spectral distance (dB, [`crate::render::metrics::log_spectral_distance`],
    /// worst pickup) of the chosen model against the full model over the excerpt
    /// (1e-9 to 60 dB; default 1 dB).
    #[serde(default = "default_tolerance_db")]
    pub tolerance_db: f64,
    /// Optional largest relative L2 error over the first 50 ms (worst pickup; 1e-12 to 10).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub l2_tolerance: Option<f64>,
    /// Length of the verification renders in seconds (0.01 to 2; default 0.25), capped at the
    /// scene's duration.
    #[serde(default = "default_excerpt")]
    pub excerpt_seconds: f64,
}

impl Default for Quality {
    fn default() -> Self {
        Self {
            mode: QualityMode::AsGiven,
            tolerance_db: default_tolerance_db(),
            l2_tolerance: None,
            excerpt_seconds: DEFAULT_EXCERPT_SECONDS,
        }
    }
}

impl Quality {
    /// Checks every field's range; errors name `quality.<field>`.
    pub fn validate(&self) -> Result<(), ParamError> {
        let t = self.tolerance_db;
        if !(t.is_finite() && (TOLERANCE_DB_MIN..=TOLERANCE_DB_MAX).contains(&t)) {
            return Err(ParamError::new(
                "quality.tolerance_db",
                t,
                "finite number in [1e-9, 60] dB",
            ));
        }
        if let Some(l2) = self.l2_tolerance {
            if !(l2.is_finite() && (1e-12..=10.0).contains(&l2)) {
                return Err(ParamError::new(
                    "quality.l2_tolerance",
                    l2,
                    "finite number in [1e-12, 10]",
                ));
            }
        }
        check_closed("quality.excerpt_seconds", self.excerpt_seconds, 0.01, 2.0)?;
        Ok(())
    }

    /// Whether the scene asks for automatic selection.
    pub fn is_auto(&self) -> bool {
        self.mode == QualityMode::Auto
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Out-of-range and non-finite tolerances are refused with the field and the range.
    #[test]
    fn ranges_are_checked() {
        assert!(Quality::default().validate().is_ok());
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, 61.0] {
            let q = Quality {
                tolerance_db: bad,
                ..Quality::default()
            };
            let e = q.validate().unwrap_err();
            assert_eq!(e.field, "quality.tolerance_db");
            assert!(
                e.allowed.contains("1e-9") && e.allowed.contains("60"),
                "{e}"
            );
        }
        let q = Quality {
            l2_tolerance: Some(0.0),
            ..Quality::default()
        };
        assert_eq!(q.validate().unwrap_err().field, "quality.l2_tolerance");
    }
}
