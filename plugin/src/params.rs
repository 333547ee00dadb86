//! The plugin's parameters: one nice-plug parameter per row of the engine's static table
//! ([`noether_core::engine::PARAMS`]), same stable key, name, unit and range, so hosts automate
//! exactly the engine's parameters. Enumerations and integers become `IntParam`s (with the
//! enumeration names as their text), floats `FloatParam`s (log-like skew where the table marks
//! the range as spanning decades).
//!
//! Threads: the host and the editor write the nice-plug parameters (any thread, atomics inside
//! nice-plug); the audio thread copies them into the engine's [`SharedParams`] at the start of
//! every (sample-accurately split) block in [`NoetherParams::sync_to_engine`].

use crate::bypass::BYPASS_KEY;
use crate::format::{format_value, parse_value};
use crate::preset_state::{CurrentPreset, Origin, PresetState};
use crate::tuning::{StoredTuning, TuningState};
use nice_plug::editor::dpi::LogicalSize;
use nice_plug::prelude::*;
use nice_plug_egui::EguiEditorState;
use noether_core::engine::voice::modulation::poly_slot;
use noether_core::engine::{
    ParamId, ParamInfo, ParamKind, ParamValues, Preset, SharedParams, PARAMS,
};
use std::collections::BTreeMap;
use std::sync::{Arc, RwLock};

/// A nice-plug parameter mirroring one engine parameter.
pub enum Slot {
    /// A continuous engine parameter.
    Float(FloatParam),
    /// An integer or enumeration engine parameter.
    Int(IntParam),
}

impl Slot {
    /// The current plain value as the engine stores it (f32, integers exact). Any thread.
    pub fn value(&self) -> f32 {
        match self {
            Slot::Float(p) => p.value(),
            Slot::Int(p) => p.value() as f32,
        }
    }
}

/// The skew factor that puts the geometric mean of `[min, max]` at the middle of the control,
/// so a range spanning decades gets about equal travel per decade near the middle
/// (nice-plug has no logarithmic range; `FloatRange::Skewed` maps `n = t^factor` with `t` the
/// linear fraction). This is what hosts' generic controls and automation lanes use. A power
/// law matches a logarithm only at this one point: over the 13 decades of the contact
/// stiffness (factor 0.046) the first 16 % of travel covers 1000 to 1000.1, and over the 3.5
/// decades of the release T60 the first 10 % covers 0.0200 to 0.0201 s. The editor's own
/// sliders therefore map their travel logarithmically themselves (see `editor::grid`).
fn log_like_skew(min: f32, max: f32) -> f32 {
    let min = f64::from(min);
    let max = f64::from(max);
    let mid = (min * max).sqrt();
    let t = (mid - min) / (max - min);
    (0.5f64.ln() / t.ln()) as f32
}

fn float_slot(info: &ParamInfo, log: bool) -> FloatParam {
    let range = if log && info.min > 0.0 {
        FloatRange::Skewed {
            min: info.min,
            max: info.max,
            factor: log_like_skew(info.min, info.max),
        }
    } else {
        FloatRange::Linear {
            min: info.min,
            max: info.max,
        }
    };
    let id = info.id;
    let p = FloatParam::new(info.name, info.default, range)
        .with_value_to_string(Arc::new(move |v| format_value(id, v)))
        .with_string_to_value(Arc::new(move |s| parse_value(id, s)));
    // The per-note parameters carry their slot as the poly-modulation id (`crate::poly`).
    match poly_slot(id) {
        Some(slot) => p.with_poly_modulation_id(slot as u32),
        None => p,
    }
}

fn int_slot(info: &ParamInfo) -> IntParam {
    let range = IntRange::Linear {
        min: info.min as i32,
        max: info.max as i32,
    };
    let p = IntParam::new(info.name, info.default as i32, range);
    let id = info.id;
    match info.kind {
        ParamKind::Enum { names, .. } => p
            .with_value_to_string(Arc::new(move |v| {
                names
                    .get(v.max(0) as usize)
                    .map_or_else(|| v.to_string(), |s| (*s).to_string())
            }))
            // A display name or a preset key (the table's one lookup), or the index.
            .with_string_to_value(Arc::new(move |s| {
                id.info()
                    .enum_index(s)
                    .map(|i| i as i32)
                    .or_else(|| s.trim().parse().ok())
            })),
        _ => p
            .with_value_to_string(Arc::new(move |v| format_value(id, v as f32)))
            .with_string_to_value(Arc::new(move |s| {
                parse_value(id, s).map(|v| v.round() as i32)
            })),
    }
}

/// Every plugin parameter plus the persisted non-parameter state.
pub struct NoetherParams {
    /// One slot per engine parameter, indexed by `ParamId::index()`.
    pub slots: Vec<Slot>,
    /// Editor window size and zoom (GUI thread; nice-plug-egui 0.6 cannot persist it).
    pub editor_state: Arc<EguiEditorState>,
    /// The current preset, its reference values and the A/B slots (persisted; see
    /// [`PresetState`]). GUI and main thread, never the audio thread.
    pub preset: RwLock<PresetState>,
    /// The engine's parameter atomics and key table: the audio thread copies the slots into
    /// them every block; the main thread (state load) and the GUI thread (editor) publish the
    /// key table through [`TuningState::apply`].
    pub engine: Arc<SharedParams>,
    /// The Scala tuning files (persisted) and what the engine plays (see [`crate::tuning`]).
    /// Main and GUI thread, never the audio thread.
    pub tuning: RwLock<TuningState>,
    /// The host's bypass (flagged as CLAP's and VST3's bypass parameter; a plugin-only
    /// parameter, not in the engine's table). The audio thread reads it every block
    /// ([`crate::bypass`]).
    pub bypass: BoolParam,
}

impl Default for NoetherParams {
    fn default() -> Self {
        let slots = PARAMS
            .iter()
            .map(|info| match info.kind {
                ParamKind::Float { log } => Slot::Float(float_slot(info, log)),
                ParamKind::Int | ParamKind::Enum { .. } => Slot::Int(int_slot(info)),
            })
            .collect();
        let engine = Arc::new(SharedParams::new());
        let tuning = RwLock::new(TuningState::apply(StoredTuning::default(), &engine));
        Self {
            slots,
            editor_state: EguiEditorState::from_size(LogicalSize::new(1040.0, 720.0), 1.0),
            preset: RwLock::new(PresetState::default()),
            engine,
            tuning,
            bypass: BoolParam::new("Bypass", false).make_bypass(),
        }
    }
}

impl NoetherParams {
    /// The slot of `id`.
    pub fn slot(&self, id: ParamId) -> &Slot {
        &self.slots[id.index()]
    }

    /// Every parameter's plain value before host modulation, clamped to the table's range as
    /// in [`Self::sync_to_engine`] (so a preset saved from it passes the engine's checks).
    /// GUI and main thread (it only reads atomics).
    pub fn plain_values(&self) -> ParamValues {
        let mut v = ParamValues::defaults();
        for (slot, info) in self.slots.iter().zip(PARAMS) {
            let x = match slot {
                Slot::Float(p) => p.unmodulated_plain_value(),
                Slot::Int(p) => p.unmodulated_plain_value() as f32,
            };
            v.0[info.id.index()] = x.clamp(info.min, info.max);
        }
        v
    }

    /// Copies every value whose bits differ from the engine's into `shared` (audio thread,
    /// once per block; wait-free, no allocation). Values are clamped to the table's range
    /// first: nice-plug keeps plain values inside the range up to the rounding of its skewed
    /// map, and the engine refuses values one ulp outside.
    pub fn sync_to_engine(&self, shared: &SharedParams) {
        for (slot, info) in self.slots.iter().zip(PARAMS) {
            let v = slot.value().clamp(info.min, info.max);
            if v.to_bits() != shared.get(info.id).to_bits() {
                // Cannot fail: finite, inside the range, integral for Int slots.
                let _ = shared.set(info.id, v);
            }
        }
    }
}

/// Persisted field: the current preset's name.
const PRESET_KEY: &str = "preset";
/// Persisted field: the whole [`PresetState`] (JSON).
const PRESET_STATE_KEY: &str = "preset_state";
/// Persisted field: the [`StoredTuning`] (the `.scl` and `.kbm` texts and names, JSON).
pub const TUNING_KEY: &str = "tuning";

// SAFETY: the pointers in `param_map` point into `self.slots`, which is never resized after
// construction, and the `Params` object lives in an `Arc` that outlives the wrapper's use.
unsafe impl Params for NoetherParams {
    fn param_map(&self) -> Vec<(String, ParamPtr, String)> {
        self.slots
            .iter()
            .zip(PARAMS)
            .map(|(slot, info)| {
                let ptr = match slot {
                    Slot::Float(p) => p.as_ptr(),
                    Slot::Int(p) => p.as_ptr(),
                };
                (info.key.to_string(), ptr, info.group.title().to_string())
            })
            .chain([(BYPASS_KEY.to_string(), self.bypass.as_ptr(), String::new())])
            .collect()
    }

    fn serialize_fields(&self) -> BTreeMap<String, String> {
        let mut map = BTreeMap::new();
        if let Ok(t) = self.tuning.read() {
            if let Ok(s) = nice_plug::params::persist::serialize_field(&t.stored) {
                map.insert(TUNING_KEY.to_string(), s);
            }
        }
        let Ok(state) = self.preset.read() else {
            return map;
        };
        // The name on its own too, as states saved before the preset state had it.
        if let Ok(s) = nice_plug::params::persist::serialize_field(&state.current.name) {
            map.insert(PRESET_KEY.to_string(), s);
        }
        if let Ok(s) = nice_plug::params::persist::serialize_field(&*state) {
            map.insert(PRESET_STATE_KEY.to_string(), s);
        }
        map
    }

    fn deserialize_fields(&self, serialized: &BTreeMap<String, String>) {
        self.load_tuning(serialized);
        let Ok(mut state) = self.preset.write() else {
            return;
        };
        if let Some(s) = serialized.get(PRESET_STATE_KEY) {
            match nice_plug::params::persist::deserialize_field::<PresetState>(s) {
                Ok(v) => {
                    *state = v;
                    return;
                }
                Err(e) => nice_error!("ignoring a corrupt preset state in the plugin state: {e}"),
            }
        }
        // An older state: the name only. A factory preset's name (or file stem) gets that
        // preset's name and values; any other name has unknown values (no edited mark).
        if let Some(s) = serialized.get(PRESET_KEY) {
            match nice_plug::params::persist::deserialize_field::<String>(s) {
                Ok(name) if !name.is_empty() => {
                    let factory = Preset::factory()
                        .into_iter()
                        .find(|(stem, p)| p.name == name || *stem == name)
                        .and_then(|(stem, p)| p.values().ok().map(|v| (stem, p.name, v)));
                    state.current = match factory {
                        Some((stem, display, v)) => {
                            CurrentPreset::new(&display, Origin::Factory(stem.to_string()), v)
                        }
                        None => CurrentPreset {
                            name,
                            origin: Origin::Unsaved,
                            reference: None,
                        },
                    };
                }
                Ok(_) => {}
                Err(e) => nice_error!("ignoring a corrupt preset name in the plugin state: {e}"),
            }
        }
    }
}

impl NoetherParams {
    /// The tuning part of a state load (main thread, from `deserialize_fields`): the stored
    /// tuning parsed and published to [`Self::engine`] through [`TuningState::apply`]; a
    /// state without the field (saved before the plugin had tunings) or with a corrupt one
    /// plays 12-TET, the corrupt one reported.
    fn load_tuning(&self, serialized: &BTreeMap<String, String>) {
        let stored = match serialized.get(TUNING_KEY) {
            None => StoredTuning::default(),
            Some(s) => match nice_plug::params::persist::deserialize_field::<StoredTuning>(s) {
                Ok(t) => t,
                Err(e) => {
                    let message = format!(
                        "plugin state: the `{TUNING_KEY}` field is not a stored tuning ({e}): \
                         playing 12-TET instead"
                    );
                    nice_error!("{message}");
                    let mut state = TuningState::apply(StoredTuning::default(), &self.engine);
                    state.error = Some(message);
                    self.set_tuning(state);
                    return;
                }
            },
        };
        self.set_tuning(TuningState::apply(stored, &self.engine));
    }

    /// Replaces the tuning state (main or GUI thread).
    pub fn set_tuning(&self, state: TuningState) {
        match self.tuning.write() {
            Ok(mut t) => *t = state,
            Err(e) => *e.into_inner() = state,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mirror has the engine's keys, ranges and defaults (exact for integers; floats
    /// within one f32 ulp-scale of the range from the skewed map's round trip).
    #[test]
    fn mirrors_the_engine_table() {
        let p = NoetherParams::default();
        let map = p.param_map();
        // The engine's table, then the plugin's own bypass.
        assert_eq!(map.len(), PARAMS.len() + 1);
        assert_eq!(map[PARAMS.len()].0, BYPASS_KEY);
        for ((key, _, _), info) in map.iter().zip(PARAMS) {
            assert_eq!(key, info.key);
            let v = p.slot(info.id).value();
            let tol = 1e-6 * (info.max - info.min);
            assert!(
                (v - info.default).abs() <= tol,
                "{}: {v} vs {}",
                info.key,
                info.default
            );
        }
    }

    /// The skew puts the geometric mean at the middle of the control (to f32 rounding).
    #[test]
    fn log_like_skew_centres_the_geometric_mean() {
        for (min, max) in [(1.0e3f32, 1.0e16f32), (0.05, 3.0), (1.0e-4, 1.0e-2)] {
            let r = FloatRange::Skewed {
                min,
                max,
                factor: log_like_skew(min, max),
            };
            let mid = (min as f64 * max as f64).sqrt() as f32;
            assert!((r.normalize(mid) - 0.5).abs() < 1e-4, "{min}..{max}");
        }
    }

    /// The host sees the editor's text: every parameter's nice-plug text at its default is
    /// `format::format_value` of the default (exact strings; enumerations show their names),
    /// and the host's text entry reads it back to the same normalised value within 5e-4 of
    /// the travel (four significant digits round by at most 5e-4 of the value, at most 5e-4
    /// of a linear travel from 0; "143.2°" for 2.5 rad is 1.1e-4 of the travel off).
    #[test]
    fn hosts_show_the_editors_text() {
        let p = NoetherParams::default();
        for info in PARAMS {
            let (text, back, n) = match p.slot(info.id) {
                Slot::Float(f) => {
                    let n = f.preview_normalized(info.default);
                    let t = f.normalized_value_to_string(n, true);
                    (t.clone(), f.string_to_normalized_value(&t), n)
                }
                Slot::Int(i) => {
                    let n = i.preview_normalized(info.default as i32);
                    let t = i.normalized_value_to_string(n, true);
                    (t.clone(), i.string_to_normalized_value(&t), n)
                }
            };
            if !matches!(info.kind, ParamKind::Enum { .. }) {
                assert_eq!(
                    text,
                    crate::format::format_value(info.id, info.default),
                    "{}",
                    info.key
                );
            }
            let back = back.unwrap_or_else(|| panic!("{}: cannot read {text:?}", info.key));
            assert!(
                (back - n).abs() < 5e-4,
                "{}: {text:?} -> {back} vs {n}",
                info.key
            );
        }
    }

    /// The stored tuning round-trips through nice-plug's field serialisation: a new instance
    /// given the saved fields stores the same files (a 19-EDO scale on the white keys) and
    /// publishes the same table (bitwise, unmapped keys included);
    /// a state without the field (saved before tunings) then loads as 12-TET.
    #[test]
    fn the_tuning_round_trips_through_the_state() {
        let p = NoetherParams::default();
        let stored = StoredTuning {
            scl: Some(crate::tuning::TuningFile {
                name: "19edo.scl".into(),
                text: crate::tuning::tests::edo19(),
            }),
            kbm: Some(crate::tuning::TuningFile {
                name: "white.kbm".into(),
                text: crate::tuning::tests::WHITE_KEYS_KBM.into(),
            }),
        };
        p.set_tuning(TuningState::apply(stored.clone(), &p.engine));
        let fields = p.serialize_fields();
        assert!(fields[TUNING_KEY].contains("19-EDO"), "{fields:?}");
        let q = NoetherParams::default();
        assert!(q.engine.tuning().get().is_equal());
        q.deserialize_fields(&fields);
        let t = q.tuning.read().unwrap();
        assert_eq!(t.stored, stored);
        assert!(t.error.is_none(), "{:?}", t.error);
        assert_eq!(q.engine.tuning().get(), p.engine.tuning().get());
        assert_eq!(q.engine.tuning().get().mapped_keys(), 75);
        drop(t);
        let mut old = fields.clone();
        old.remove(TUNING_KEY);
        q.deserialize_fields(&old);
        assert!(q.engine.tuning().get().is_equal());
        assert_eq!(q.tuning.read().unwrap().stored, StoredTuning::default());
        assert_eq!(q.tuning.read().unwrap().description, "12-TET");
    }

    /// A `tuning` field that is not a stored tuning (corrupt JSON) loads as 12-TET with the
    /// error kept for the editor, replacing the tuning the instance had.
    #[test]
    fn a_corrupt_tuning_field_loads_as_12_tet() {
        let p = NoetherParams::default();
        let stored = StoredTuning {
            scl: Some(crate::tuning::TuningFile {
                name: "19edo.scl".into(),
                text: crate::tuning::tests::edo19(),
            }),
            kbm: None,
        };
        p.set_tuning(TuningState::apply(stored, &p.engine));
        assert!(!p.engine.tuning().get().is_equal());
        let mut fields = p.serialize_fields();
        fields.insert(TUNING_KEY.into(), "{\"scl\": 7".into());
        p.deserialize_fields(&fields);
        assert!(p.engine.tuning().get().is_equal());
        let e = p.tuning.read().unwrap().error.clone().expect("an error");
        assert!(e.contains("`tuning`") && e.contains("12-TET"), "{e}");
    }

    /// Syncing writes every value into the engine's atomics, clamped and accepted.
    #[test]
    fn sync_copies_values() {
        let p = NoetherParams::default();
        let shared = SharedParams::new();
        p.sync_to_engine(&shared);
        for info in PARAMS {
            assert_eq!(
                shared.get(info.id),
                p.slot(info.id).value().clamp(info.min, info.max)
            );
        }
    }
}
