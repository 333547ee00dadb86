//! The current preset and the A/B compare slots (persisted in the plugin state, so a reloaded
//! project shows the preset's name, its edited mark and both A/B slots).
//!
//! The current preset is a name, where it came from ([`Origin`]) and the parameter values it
//! had when it was loaded or saved (its reference). The editor marks it as edited ("gong *")
//! while any host parameter differs from the reference, so moving a slider back clears the mark.
//! Continuous parameters are compared as the host holds them, normalized to [0, 1], within
//! [`NORMALIZED_TOLERANCE`]; integers and enumerations exactly.
//!
//! A/B compare: the active slot is the host parameters themselves; the other slot is a saved
//! [`Snapshot`] (values and current preset). Switching stores the active set and writes the
//! other through the host's parameter setter (a begin/set/end gesture per parameter that
//! changes, so the host records it); copying stores the active set into the other slot.
//!
//! Threads: the GUI thread (switching, loading, marking) and the main thread (state save and
//! load); the state sits behind an `RwLock` in [`NoetherParams`] that the audio thread never
//! takes.

use crate::params::{NoetherParams, Slot};
use nice_plug::prelude::*;
use noether_core::engine::{ParamValues, Preset, PARAMS};
use serde::{Deserialize, Serialize};

/// Largest difference of a continuous parameter's normalized value from the preset's that
/// still counts as unedited: 1e-6, above the few-ulp round trip of a plain value through
/// nice-plug's skewed ranges (about 1e-7 of the travel) and far below one pixel of a slider
/// (about 5e-3) or one step of a fine drag.
pub const NORMALIZED_TOLERANCE: f32 = 1e-6;

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

    /// Whether the host parameters differ from the reference (see the module documentation).
    pub fn is_edited(&self, params: &NoetherParams) -> bool {
        self.reference.as_ref().is_some_and(|r| differs(params, r))
    }

    /// The name with the edited mark: `"name *"` while edited.
    pub fn display(&self, params: &NoetherParams) -> String {
        if self.is_edited(params) {
            format!("{} *", self.name)
        } else {
            self.name.clone()
        }
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

impl PresetState {
    /// Writes `values` to the host parameters and makes `preset` the current preset.
    pub fn load(
        &mut self,
        params: &NoetherParams,
        setter: &ParamSetter,
        preset: CurrentPreset,
        values: &ParamValues,
    ) {
        apply(params, setter, values);
        self.current = preset;
    }

    /// The active slot as a snapshot.
    pub fn snapshot(&self, params: &NoetherParams) -> Snapshot {
        Snapshot {
            preset: self.current.clone(),
            values: Some(params.plain_values()),
        }
    }

    /// Makes `slot` active: stores the active set and writes the other one (a copy of the
    /// active set if the other slot was never used). Nothing happens if `slot` is active.
    pub fn switch_to(&mut self, slot: AbSlot, params: &NoetherParams, setter: &ParamSetter) {
        if slot == self.active {
            return;
        }
        let here = self.snapshot(params);
        let there = self.other.take().unwrap_or_else(|| here.clone());
        if let Some(values) = &there.values {
            apply(params, setter, values);
        }
        self.current = there.preset;
        self.other = Some(here);
        self.active = slot;
    }

    /// Copies the active set into the other slot ("A→B" or "B→A").
    pub fn copy_to_other(&mut self, params: &NoetherParams) {
        self.other = Some(self.snapshot(params));
    }
}

/// Whether the host parameters differ from `reference` (see the module documentation).
pub fn differs(params: &NoetherParams, reference: &ParamValues) -> bool {
    PARAMS.iter().any(|info| {
        let v = reference.get(info.id);
        match params.slot(info.id) {
            Slot::Float(p) => {
                (p.unmodulated_normalized_value() - p.preview_normalized(v)).abs()
                    > NORMALIZED_TOLERANCE
            }
            Slot::Int(p) => p.unmodulated_plain_value() != v.round() as i32,
        }
    })
}

/// Writes `values` to the host parameters through `setter`: a begin/set/end gesture for each
/// parameter whose plain value changes (GUI thread). The host takes normalized values and keeps
/// `preview_plain(normalized)`, which for a skewed range can be a few ulps from the plain value
/// the normalized one came from; [`exact_normalized`] picks the normalized value that gives the
/// plain value back exactly where there is one, so an A/B switch restores bit for bit every
/// value the host or the editor set (those came from normalized values). A plain value that no
/// normalized value reaches (a default, or a value from a loaded state, at a few points of the
/// skewed ranges) comes back within a few ulps, well inside [`NORMALIZED_TOLERANCE`].
pub fn apply(params: &NoetherParams, setter: &ParamSetter, values: &ParamValues) {
    for info in PARAMS {
        let v = values.get(info.id);
        match params.slot(info.id) {
            Slot::Float(p) => {
                if v.to_bits() != p.unmodulated_plain_value().to_bits() {
                    setter.begin_set_parameter(p);
                    setter.set_parameter_normalized(p, exact_normalized(p, v));
                    setter.end_set_parameter(p);
                }
            }
            Slot::Int(p) => {
                let v = v.round() as i32;
                if v != p.unmodulated_plain_value() {
                    setter.begin_set_parameter(p);
                    setter.set_parameter(p, v);
                    setter.end_set_parameter(p);
                }
            }
        }
    }
}

/// The normalized value `n` of `p` with `p.preview_plain(n) == target`, searched from
/// `p.preview_normalized(target)` towards `target` over at most 64 f32 steps (the plain map is
/// monotonic); `p.preview_normalized(target)` if no such `n` is found (a plain value between
/// two that normalized values reach).
pub fn exact_normalized(p: &FloatParam, target: f32) -> f32 {
    let n0 = p.preview_normalized(target);
    let first = p.preview_plain(n0);
    if first.to_bits() == target.to_bits() || !target.is_finite() {
        return n0;
    }
    let up = first < target;
    let mut n = n0;
    for _ in 0..64 {
        let bits = n.to_bits();
        n = match (up, bits) {
            (true, _) => f32::from_bits(bits + 1),
            (false, 0) => break,
            (false, _) => f32::from_bits(bits - 1),
        };
        if !(0.0..=1.0).contains(&n) {
            break;
        }
        let v = p.preview_plain(n);
        if v.to_bits() == target.to_bits() {
            return n;
        }
        if (v > target) == up {
            break;
        }
    }
    n0
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

#[cfg(test)]
#[path = "preset_state_tests.rs"]
mod tests;
