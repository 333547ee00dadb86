//! Presets: a TOML file naming parameter values by their stable keys ([`ParamInfo::key`]),
//! and the factory presets of `assets/presets/` (embedded in the library).
//!
//! ```toml
//! name = "Lecture gong, 40 N"
//! description = "..."
//! [params]
//! model = "gong"          # enumerations by name (or index)
//! size = 0.4              # numbers in the parameter's unit
//! ```
//!
//! Parameters a preset does not name take their defaults. Unknown keys, unknown names, wrong
//! types and out-of-range values are errors naming the key, the value and the allowed range.
//! Parsing and applying run on the GUI / main thread (they allocate).

use super::params::{ParamId, ParamInfo, ParamKind, ParamValues, SharedParams, PARAMS};
use crate::error::ParamError;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// A parameter value in a preset: a number in the parameter's unit, or an enumeration name.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum PresetValue {
    /// A number (enumerations accept their index).
    Number(f64),
    /// An enumeration value by name (see [`enum_keys`]).
    Name(String),
}

/// A named set of parameter values.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Preset {
    /// Display name.
    pub name: String,
    /// What it is and where its values come from.
    #[serde(default)]
    pub description: String,
    /// Values by parameter key.
    #[serde(default)]
    pub params: BTreeMap<String, PresetValue>,
}

/// Preset names of an enumeration parameter's values, in index order (`None` for other
/// parameters).
pub fn enum_keys(id: ParamId) -> Option<&'static [&'static str]> {
    match id.info().kind {
        ParamKind::Enum { keys, .. } => Some(keys),
        _ => None,
    }
}

/// The key under which presets and states before the bridge became a fraction of the string
/// stored its position or extent, in metres; read as `bridge_fraction = value / size`.
pub const LEGACY_BRIDGE_POSITION: &str = "bridge_position";

/// `bridge_fraction` for a legacy bridge position of `metres` on a string `length` m long
/// (the saved `size`; missing, not finite or not positive: the table's default size). The one
/// migration of the legacy field, for presets and plugin states alike.
pub fn legacy_bridge_fraction(metres: f64, length: Option<f64>) -> f64 {
    let length = length
        .filter(|l| l.is_finite() && *l > 0.0)
        .unwrap_or(f64::from(ParamId::Size.info().default));
    metres / length
}

/// The factory presets' TOML sources, embedded at build time (`assets/presets/`).
const FACTORY: &[(&str, &str)] = &[
    (
        "gong-40N",
        include_str!("../../../assets/presets/gong-40N.toml"),
    ),
    (
        "gong-80N",
        include_str!("../../../assets/presets/gong-80N.toml"),
    ),
    (
        "rect-plate",
        include_str!("../../../assets/presets/rect-plate.toml"),
    ),
    ("sitar", include_str!("../../../assets/presets/sitar.toml")),
    (
        "sitar-b0",
        include_str!("../../../assets/presets/sitar-b0.toml"),
    ),
    (
        "tanpura",
        include_str!("../../../assets/presets/tanpura.toml"),
    ),
    (
        "tanpura-b0",
        include_str!("../../../assets/presets/tanpura-b0.toml"),
    ),
    (
        "opera-gong-rising",
        include_str!("../../../assets/presets/opera-gong-rising.toml"),
    ),
    (
        "opera-gong-falling",
        include_str!("../../../assets/presets/opera-gong-falling.toml"),
    ),
    (
        "tam-tam",
        include_str!("../../../assets/presets/tam-tam.toml"),
    ),
    ("crash", include_str!("../../../assets/presets/crash.toml")),
    ("ride", include_str!("../../../assets/presets/ride.toml")),
    (
        "tanpura-drone",
        include_str!("../../../assets/presets/tanpura-drone.toml"),
    ),
    (
        "sitar-taraf",
        include_str!("../../../assets/presets/sitar-taraf.toml"),
    ),
];

/// `x` as the f64 whose shortest decimal text is the f32's shortest text (so a saved preset
/// reads `1.7468022`, not `1.7468022108078003`) when that f64 rounds back to `x` bit for bit,
/// else `x` widened exactly: either way reading the text back gives `x` exactly.
fn short_f64(x: f32) -> f64 {
    match x.to_string().parse::<f64>() {
        Ok(short) if (short as f32).to_bits() == x.to_bits() => short,
        _ => f64::from(x),
    }
}

impl Preset {
    /// Parses a preset (checks the structure only; [`Self::values`] checks the values).
    pub fn from_toml(text: &str) -> Result<Preset, ParamError> {
        toml::from_str(text)
            .map_err(|e| ParamError::new("preset", e.message(), "a valid preset TOML file"))
    }

    /// Reads and parses a preset file.
    pub fn load(path: &Path) -> Result<Preset, ParamError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            ParamError::new(
                "preset file",
                path.display(),
                format!("a readable file ({e})"),
            )
        })?;
        Self::from_toml(&text)
    }

    /// The preset as TOML text.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_default()
    }

    /// The full parameter set: defaults overridden by the preset's values, each checked.
    pub fn values(&self) -> Result<ParamValues, ParamError> {
        let mut v = ParamValues::defaults();
        let mut legacy_bridge = None;
        for (key, value) in &self.params {
            if key == LEGACY_BRIDGE_POSITION {
                legacy_bridge = Some(match value {
                    PresetValue::Number(x) => *x,
                    PresetValue::Name(n) => {
                        return Err(ParamError::new(format!("params.{key}"), n, "a number"))
                    }
                });
                continue;
            }
            let id = ParamId::from_key(key).ok_or_else(|| {
                ParamError::new(
                    format!("params.{key}"),
                    key,
                    "a parameter key of the engine's table",
                )
            })?;
            let info: &ParamInfo = id.info();
            let x = match value {
                PresetValue::Number(x) => *x as f32,
                PresetValue::Name(name) => {
                    let names = enum_keys(id).ok_or_else(|| {
                        ParamError::new(format!("params.{key}"), name, "a number")
                    })?;
                    info.enum_index(name).ok_or_else(|| {
                        ParamError::new(format!("params.{key}"), name, format!("one of {names:?}"))
                    })? as f32
                }
            };
            info.check(x)
                .map_err(|e| ParamError::new(format!("params.{key}"), e.value, e.allowed))?;
            v.0[id.index()] = x;
        }
        if let (Some(metres), false) = (legacy_bridge, self.params.contains_key("bridge_fraction"))
        {
            let fraction = legacy_bridge_fraction(metres, Some(v.get(ParamId::Size) as f64));
            let info = ParamId::BridgePosition.info();
            let x = info.check(fraction as f32).map_err(|e| {
                ParamError::new(
                    format!("params.{LEGACY_BRIDGE_POSITION}"),
                    format!("{metres} m ({} of the string)", e.value),
                    e.allowed,
                )
            })?;
            v.0[ParamId::BridgePosition.index()] = x;
        }
        Ok(v)
    }

    /// A preset holding every value of `v` (enumerations by name; numbers in the shortest
    /// text that reads back as the same f32).
    pub fn from_values(name: &str, description: &str, v: &ParamValues) -> Preset {
        let params = PARAMS
            .iter()
            .map(|p| {
                let x = v.get(p.id);
                let value = match (p.kind, enum_keys(p.id)) {
                    (ParamKind::Enum { .. }, Some(names)) => names
                        .get(x as usize)
                        .map_or(PresetValue::Number(x as f64), |n| {
                            PresetValue::Name(n.to_string())
                        }),
                    _ => PresetValue::Number(short_f64(x)),
                };
                (p.key.to_string(), value)
            })
            .collect();
        Preset {
            name: name.into(),
            description: description.into(),
            params,
        }
    }

    /// Writes the preset's full parameter set into `shared` (nothing is written on error).
    pub fn apply(&self, shared: &SharedParams) -> Result<(), ParamError> {
        shared.set_all(&self.values()?)
    }

    /// The factory presets, `(file stem, preset)`, in a fixed order.
    pub fn factory() -> Vec<(&'static str, Preset)> {
        FACTORY
            .iter()
            .filter_map(|(stem, text)| Self::from_toml(text).ok().map(|p| (*stem, p)))
            .collect()
    }

    /// The factory preset with file stem `stem`.
    pub fn factory_named(stem: &str) -> Option<Preset> {
        FACTORY
            .iter()
            .find(|(s, _)| *s == stem)
            .and_then(|(_, t)| Self::from_toml(t).ok())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn factory_presets_parse_and_validate() {
        assert_eq!(Preset::factory().len(), FACTORY.len());
        for (stem, p) in Preset::factory() {
            p.values().unwrap_or_else(|e| panic!("{stem}: {e}"));
        }
    }

    #[test]
    fn round_trip_and_errors() {
        let mut v = ParamValues::defaults();
        v.set(ParamId::Model, 3.0).unwrap();
        v.set(ParamId::Tension, 150.0).unwrap();
        v.set(ParamId::Size, 1.746_802_2).unwrap();
        let p = Preset::from_values("x", "", &v);
        let text = p.to_toml();
        assert!(text.contains("size = 1.7468022\n"), "{text}");
        let back = Preset::from_toml(&text).unwrap();
        assert_eq!(back.values().unwrap(), v);
        let e = Preset::from_toml("name = \"a\"\n[params]\nsize = 99.0\n")
            .unwrap()
            .values()
            .unwrap_err();
        assert_eq!(e.field, "params.size");
        let e = Preset::from_toml("name = \"a\"\n[params]\nmodel = \"drum\"\n")
            .unwrap()
            .values()
            .unwrap_err();
        assert!(e.allowed.contains("sitar"), "{e}");
        assert!(Preset::from_toml("name = \"a\"\n[params]\nnope = 1\n")
            .unwrap()
            .values()
            .is_err());
        assert!(Preset::from_toml("name = 1").is_err());
    }
}
