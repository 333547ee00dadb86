//! The sizes and rate of one plate or string model ([`ModelSize`]), the unit every step of
//! `quality = "auto"` speaks in, and how to apply them to a scene.
//!
//! Plain data; any thread.

use crate::error::Error;
use crate::scene::plate::Symmetry;
use crate::scene::string::StringLosses;
use crate::scene::Scene;
use serde::Serialize;

/// The sizes and rate of one plate or string model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ModelSize {
    /// Whether this is a string model: then `n_phi` is the string's mode count N_m, `n_psi` is
    /// 0 and `symmetry` is `Full` (unused).
    pub string: bool,
    /// Transverse modes N_Φ (in the model's basis); for a string, its mode count N_m.
    pub n_phi: usize,
    /// In-plane modes N_Ψ (in the model's basis); 0 for a string.
    pub n_psi: usize,
    /// Basis symmetry (`Full` for a string).
    pub symmetry: Symmetry,
    /// Simulation rate (Hz).
    pub sim_rate: f64,
    /// Highest transverse frequency of the basis (Hz).
    pub f_max_hz: f64,
}

/// A string model of `modes` modes at `sim_rate` Hz whose top mode is `f_max_hz`.
pub fn string_size(modes: usize, sim_rate: f64, f_max_hz: f64) -> ModelSize {
    ModelSize {
        string: true,
        n_phi: modes,
        n_psi: 0,
        symmetry: Symmetry::Full,
        sim_rate,
        f_max_hz,
    }
}

impl ModelSize {
    /// `scene` with its plate (or string) resized to `self` and its `[quality]` table removed
    /// (the result is a plain scene: rendering it renders exactly this model). Errors if the
    /// scene has no model of this kind or the result does not validate. A string's per-mode
    /// damping list keeps its first `modes` values (the same modes).
    pub fn apply(&self, scene: &Scene) -> Result<Scene, Error> {
        let mut s = scene.clone();
        if self.string {
            let st = s.string.as_mut().ok_or(Error::WrongModel(
                "a string model size applied to a scene without [string]",
            ))?;
            st.modes = self.n_phi;
            st.sim_rate = self.sim_rate;
            if let StringLosses::PerMode { sigma } = &mut st.losses {
                sigma.truncate(self.n_phi);
            }
            s.quality = None;
            s.validate()?;
            return Ok(s);
        }
        let p = s.plate.as_mut().ok_or(Error::WrongModel(
            "quality = \"auto\" is implemented for plate scenes only",
        ))?;
        p.n_phi = self.n_phi;
        p.n_psi = self.n_psi;
        p.symmetry = self.symmetry;
        p.sim_rate = self.sim_rate;
        s.quality = None;
        s.validate()?;
        Ok(s)
    }

    /// `n_phi x n_psi, symmetry, rate` for logs.
    pub fn label(&self) -> String {
        if self.string {
            return format!(
                "{} modes, {} Hz (band {:.0} Hz)",
                self.n_phi, self.sim_rate, self.f_max_hz
            );
        }
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
