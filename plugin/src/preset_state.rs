//! The current preset and the A/B compare slots as data (persisted in the plugin state, so a
//! reloaded project shows the preset's name, its edited mark and both A/B slots). The
//! operations on the host parameters (loading, the edited mark, switching) are in
//! [`crate::preset_ops`].
//!
//! The current preset is a name, where it came from ([`Origin`]) and the parameter values it
//! had when it was loaded or saved (its reference). A/B compare: the active slot is the host
//! parameters themselves; the other slot is a saved [`Snapshot`] (values and current preset).
//!
//! Threads: the GUI thread and the main thread (state save and load); the state sits behind an
//! `RwLock` in [`crate::params::NoetherParams`] that the audio thread never takes.

use noether_core::engine::{ParamValues, Preset};
use serde::{Deserialize, Serialize};

/// Name shown when the parameters start from the table's defaults and no factory preset has
/// exactly those values.
pub const INIT_NAME: &str = "Init";

/// Where the current preset came from.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub enum Origin {
    /// The parameter table's defaults.
    Init,
    /// A factory preset (its file stem in `assets/presets/`).
    Factory(String),
    /// A user preset (its file stem in the user folder).
    User(String),
    /// A preset that no longer exists (a deleted user preset, or a name from an older state).
    Unsaved,
}

/// The current preset.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CurrentPreset {
    /// Display name.
    pub name: String,
    /// Where it came from.
    pub origin: Origin,
    /// Its values when loaded or saved (`None`: unknown, never marked as edited).
    #[serde(with = "by_key")]
    pub reference: Option<ParamValues>,
}

impl CurrentPreset {
    /// The preset `name` from `origin` with `values` as its reference.
    pub fn new(name: &str, origin: Origin, values: ParamValues) -> Self {
        Self {
            name: name.to_string(),
            origin,
            reference: Some(values),
        }
    }

    /// The start-up preset: the first factory preset whose values equal the table's defaults
    /// bit for bit, else [`INIT_NAME`] with the defaults.
    pub fn initial() -> Self {
        let defaults = ParamValues::defaults();
        Preset::factory()
            .into_iter()
            .find(|(_, p)| p.values().is_ok_and(|v| same_bits(&v, &defaults)))
            .map_or_else(
                || Self::new(INIT_NAME, Origin::Init, defaults),
                |(stem, p)| Self::new(&p.name, Origin::Factory(stem.to_string()), defaults),
            )
    }
}

/// Which A/B slot the host parameters hold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum AbSlot {
    /// Slot A.
    A,
    /// Slot B.
    B,
}

impl AbSlot {
    /// The other slot.
    pub fn other(self) -> Self {
        match self {
            Self::A => Self::B,
            Self::B => Self::A,
        }
    }

    /// "A" or "B".
    pub fn label(self) -> &'static str {
        match self {
            Self::A => "A",
            Self::B => "B",
        }
    }
}

/// A stored parameter set with its preset.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Snapshot {
    /// The preset the set was derived from.
    pub preset: CurrentPreset,
    /// Every parameter's plain value.
    #[serde(with = "by_key")]
    pub values: Option<ParamValues>,
}

/// The persisted preset state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PresetState {
    /// The preset the host parameters come from.
    pub current: CurrentPreset,
    /// The slot the host parameters hold.
    pub active: AbSlot,
    /// The other slot (`None` until first used: switching to it then copies the active set).
    pub other: Option<Snapshot>,
}

impl Default for PresetState {
    fn default() -> Self {
        Self {
            current: CurrentPreset::initial(),
            active: AbSlot::A,
            other: None,
        }
    }
}

fn same_bits(a: &ParamValues, b: &ParamValues) -> bool {
    a.0.iter()
        .zip(&b.0)
        .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// Serde for parameter sets as a map from parameter key to value: f32 widened to f64 (exact,
/// and JSON's shortest f64 text reads back the same f64); missing keys take the default and
/// unknown or non-finite ones are dropped (states from other versions load like
/// [`crate::state::repair`] loads parameters). Values are not clamped here: writing them goes
/// through the host parameters' ranges, which clamp.
mod by_key {
    use noether_core::engine::{ParamId, ParamValues, PARAMS};
    use serde::{Deserialize, Deserializer, Serialize, Serializer};
    use std::collections::BTreeMap;

    pub fn serialize<S: Serializer>(v: &Option<ParamValues>, s: S) -> Result<S::Ok, S::Error> {
        v.as_ref()
            .map(|v| {
                PARAMS
                    .iter()
                    .map(|p| (p.key, f64::from(v.get(p.id))))
                    .collect::<BTreeMap<_, _>>()
            })
            .serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<ParamValues>, D::Error> {
        let map = Option::<BTreeMap<String, f64>>::deserialize(d)?;
        Ok(map.map(|map| {
            let mut v = ParamValues::defaults();
            for (key, x) in map {
                if let Some(id) = ParamId::from_key(&key).filter(|_| x.is_finite()) {
                    v.0[id.index()] = x as f32;
                }
            }
            v
        }))
    }
}
