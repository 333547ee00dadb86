//! What the preset state does to the host parameters (GUI thread): loading a preset, the
//! edited mark, A/B switching and copying ([`PresetState`], [`CurrentPreset`]).
//!
//! The editor marks the current preset as edited ("gong *") while any host parameter differs
//! from its reference values, so moving a slider back clears the mark. Continuous parameters
//! are compared as the host holds them, normalized to [0, 1], within
//! [`NORMALIZED_TOLERANCE`]; integers and enumerations exactly.
//!
//! Switching A/B stores the active set and writes the other through the host's parameter
//! setter (a begin/set/end gesture per parameter that changes, so the host records it);
//! copying stores the active set into the other slot.

use crate::params::{NoetherParams, Slot};
use crate::preset_state::{AbSlot, CurrentPreset, PresetState, Snapshot};
use nice_plug::prelude::*;
use noether_core::engine::{ParamValues, PARAMS};

/// Largest difference of a continuous parameter's normalized value from the preset's that
/// still counts as unedited: 1e-6, above the few-ulp round trip of a plain value through
/// nice-plug's skewed ranges (about 1e-7 of the travel) and far below one pixel of a slider
/// (about 5e-3) or one step of a fine drag.
pub const NORMALIZED_TOLERANCE: f32 = 1e-6;

impl CurrentPreset {
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

#[cfg(test)]
#[path = "preset_ops_tests.rs"]
mod tests;
