//! Scene files: a TOML description of one offline render (model, excitation, pickups, rates).
//!
//! A scene is parsed with serde (`deny_unknown_fields` everywhere, so a misspelt field is an
//! error naming it), overridden field by field with `--set dotted.path=value`, then validated:
//! every numeric field is checked against its allowed range and an error names the dotted
//! field, the value and the range ([`crate::ParamError`]).
//!
//! Parsing and validation run on the thread that loads the scene (CLI main thread, or the
//! plugin's worker), never on the audio thread.

pub mod overrides;
pub use noether_core::models::plate::spec as plate;
pub mod quality;
pub use noether_core::models::sitar::SitarSpec;
pub use noether_core::models::string::spec as string;
pub use noether_core::models::tanpura::TanpuraSpec;

pub use plate::PlateSpec;
pub use quality::{Quality, QualityMode};
pub use string::StringSpec;

pub use crate::error::{SceneError, SetError};

use crate::error::{check_closed, ParamError};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// Output of a render: WAV rate and length.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// WAV sample rate in Hz (8 000 to 384 000); the simulation is resampled to it.
    pub sample_rate: u32,
    /// Rendered duration in seconds (0 < seconds ≤ 600).
    pub seconds: f64,
    /// Gain applied to the pickup signals before writing, in dB (-120 to 120). The WAV is
    /// 32-bit float, so nothing is clipped; the report gives the peak.
    #[serde(default)]
    pub gain_db: f64,
}

impl OutputSpec {
    /// Checks the ranges of every field.
    pub fn validate(&self) -> Result<(), ParamError> {
        if !(8_000..=384_000).contains(&self.sample_rate) {
            return Err(ParamError::new(
                "output.sample_rate",
                self.sample_rate,
                "8000 to 384000 Hz",
            ));
        }
        check_closed("output.seconds", self.seconds, 1e-6, 600.0)?;
        check_closed("output.gain_db", self.gain_db, -120.0, 120.0)?;
        Ok(())
    }
}

/// A complete scene.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Short name (used for output file names); defaults to the file stem.
    #[serde(default)]
    pub name: String,
    /// Free text describing the scene.
    #[serde(default)]
    pub description: String,
    /// WAV rate and duration.
    pub output: OutputSpec,
    /// The plate model, when the scene is a plate or gong.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub plate: Option<PlateSpec>,
    /// The stiff string model, when the scene is a sitar, tanpura or other string.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub string: Option<StringSpec>,
    /// The tanpura drone (strings on a moving bridge, plucked in a cycle).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tanpura: Option<TanpuraSpec>,
    /// The sitar with its taraf (one note on the played string, the sympathetic strings
    /// answering).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sitar: Option<SitarSpec>,
    /// Model selection (`[quality]`): as given, or `mode = "auto"` with a tolerance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub quality: Option<Quality>,
}

impl Scene {
    /// Parses TOML text, applies `overrides` (`dotted.path=value`), and validates.
    pub fn from_toml(text: &str, origin: &str, overrides: &[String]) -> Result<Self, SceneError> {
        let mut value: toml::Table =
            toml::from_str(text).map_err(|e| SceneError::Parse(format!("{origin}: {e}")))?;
        for o in overrides {
            overrides::apply(&mut value, o)?;
        }
        let scene: Scene =
            serde_path_to_error::deserialize(toml::Value::Table(value)).map_err(|e| {
                let path = e.path().to_string();
                let inner = e.into_inner();
                let msg = inner.message().trim_end();
                SceneError::Parse(if path == "." || path.is_empty() {
                    format!("{origin}: {msg}")
                } else {
                    format!("{origin}: field `{path}`: {msg}")
                })
            })?;
        scene.validate()?;
        Ok(scene)
    }

    /// Reads and parses a scene file; the name defaults to the file stem.
    pub fn load(path: &Path, overrides: &[String]) -> Result<Self, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|source| SceneError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let mut scene = Self::from_toml(&text, &path.display().to_string(), overrides)?;
        if scene.name.is_empty() {
            scene.name = path
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default();
        }
        Ok(scene)
    }

    /// Checks every field's range; errors name the dotted field.
    pub fn validate(&self) -> Result<(), ParamError> {
        self.output.validate()?;
        if let Some(q) = &self.quality {
            q.validate()?;
        }
        const ONE: &str = "exactly one model table: [plate], [string], [tanpura] or [sitar]";
        let given = [
            self.plate.is_some(),
            self.string.is_some(),
            self.tanpura.is_some(),
            self.sitar.is_some(),
        ];
        match given.iter().filter(|&&g| g).count() {
            0 => Err(ParamError::new(
                "plate",
                "missing",
                format!("a scene needs {ONE}"),
            )),
            1 => {
                if let Some(p) = &self.plate {
                    p.validate()
                } else if let Some(s) = &self.string {
                    s.validate()
                } else if let Some(t) = &self.tanpura {
                    t.validate()
                } else {
                    self.sitar.as_ref().map_or(Ok(()), |s| s.validate())
                }
            }
            _ => {
                // Name the second table given.
                let names = ["plate", "string", "tanpura", "sitar"];
                let second = (0..4).filter(|&i| given[i]).nth(1).unwrap_or(1);
                Err(ParamError::new(
                    names[second],
                    format!(
                        "given with [{}]",
                        names[given.iter().position(|&g| g).unwrap_or(0)]
                    ),
                    ONE,
                ))
            }
        }
    }

    /// The model table's name (`plate`, `string`, `tanpura` or `sitar`), the prefix of its
    /// dotted fields.
    pub fn model_key(&self) -> &'static str {
        if self.string.is_some() {
            "string"
        } else if self.tanpura.is_some() {
            "tanpura"
        } else if self.sitar.is_some() {
            "sitar"
        } else {
            "plate"
        }
    }

    /// The simulation rate of the scene's model (Hz).
    pub fn sim_rate(&self) -> f64 {
        match (&self.plate, &self.string, &self.tanpura) {
            (Some(p), _, _) => p.sim_rate,
            (None, Some(s), _) => s.sim_rate,
            (None, None, Some(t)) => t.sim_rate,
            (None, None, None) => self.sitar.as_ref().map_or(0.0, |s| s.sim_rate),
        }
    }

    /// Whether the scene asks for automatic model selection (`quality.mode = "auto"`).
    pub fn is_auto(&self) -> bool {
        self.quality.is_some_and(|q| q.is_auto())
    }

    /// Sets the simulation rate of the scene's model to `fs` (Hz) and re-validates.
    pub fn set_sim_rate(&mut self, fs: f64) -> Result<(), ParamError> {
        if let Some(p) = &mut self.plate {
            p.sim_rate = fs;
        }
        if let Some(s) = &mut self.string {
            s.sim_rate = fs;
        }
        if let Some(t) = &mut self.tanpura {
            t.sim_rate = fs;
        }
        if let Some(s) = &mut self.sitar {
            s.sim_rate = fs;
        }
        self.validate()
    }
}
