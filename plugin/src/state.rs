//! Loading a saved plugin state robustly.
//!
//! nice-plug stores the state as JSON ([`PluginState`]: the plugin version, one plain value per
//! parameter key, and the persisted fields) and loads it in two steps: it parses the JSON, then
//! calls [`Plugin::filter_state`](nice_plug::prelude::Plugin::filter_state) and writes each
//! value into the parameter with that key. What it does with bad input, read from its source
//! (`nice-plug` 0.4.2, `wrapper/state.rs`):
//! - JSON that does not parse as a `PluginState` (corrupt or truncated blob, wrong CLAP length
//!   prefix, or a state without its `fields` map, which has no serde default): the load
//!   fails before the plugin sees anything; the host is told (CLAP `state.load` returns false),
//!   the instance keeps every parameter it had, and nice-plug logs the parse error only in
//!   debug builds. That is the defined state for those blobs: unchanged.
//! - A parsed state: unknown keys and values of the wrong type are skipped with a warning in
//!   debug builds only, and silently in release; missing keys leave the parameter at whatever
//!   value the instance had (so the result depends on the instance's history); an out-of-range
//!   value is clamped by the parameter's range without a report.
//!
//! [`repair`] runs inside `filter_state` and makes every parsed state defined and reported:
//! every engine parameter ends up with a value of its slot's type inside the engine table's
//! range; missing ones get the table's default; out-of-range values are clamped into the
//! range; values of the wrong type are converted where the conversion is exact (an integer for
//! a float, an integral float or an enumeration name for an integer), otherwise replaced by the
//! default; non-finite values get the default; unknown keys are dropped. Every change is
//! returned as a [`StateIssue`], which the plugin logs as an error naming the key, the value
//! and the allowed range. A state from another plugin version is reported and loaded the same
//! way (parameters are only ever appended to the table, with defaults that keep old sounds,
//! so filling missing keys with defaults is the migration; a renamed key would be mapped here).
//!
//! Threads: the host's main thread (state load), never the audio thread.

use crate::bypass::PLUGIN_ONLY_KEYS;
use nice_plug::plugin::{ParamValue, PluginState};
use noether_core::engine::{
    legacy_bridge_fraction, ParamId, ParamInfo, ParamKind, LEGACY_BRIDGE_POSITION, PARAMS,
};
use std::fmt;

/// One change [`repair`] made to a loaded state.
#[derive(Debug, Clone, PartialEq)]
pub enum StateIssue {
    /// The state was saved by another plugin version (or has no version).
    Version {
        /// The saved version (empty if absent).
        saved: String,
        /// This plugin's version.
        current: &'static str,
    },
    /// A parameter was absent: it gets the table's default.
    Missing {
        /// Parameter key.
        key: &'static str,
        /// The default it gets.
        default: f32,
    },
    /// A key that is no parameter of this plugin: dropped.
    Unknown {
        /// The key as saved.
        key: String,
    },
    /// A value outside the parameter's range: clamped into it.
    OutOfRange {
        /// Parameter key.
        key: &'static str,
        /// The saved value.
        value: f64,
        /// The value loaded instead.
        clamped: f32,
        /// The parameter's range.
        range: (f32, f32),
    },
    /// A value saved under a key this version replaced: converted to the new parameter.
    Migrated {
        /// The old key.
        from: &'static str,
        /// The saved value.
        value: f64,
        /// The new key.
        to: &'static str,
        /// The value it gives the new key (before the range check).
        converted: f64,
    },
    /// A value of the wrong type or not finite: converted exactly, or replaced by the default.
    WrongType {
        /// Parameter key.
        key: &'static str,
        /// The saved value, as JSON would show it.
        value: String,
        /// The value loaded instead.
        loaded: f32,
        /// Whether `loaded` is an exact conversion of `value` (else the default).
        converted: bool,
    },
}

impl fmt::Display for StateIssue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Version { saved, current } => write!(
                f,
                "plugin state saved by version `{saved}`, loading into {current}: missing \
                 parameters get their defaults"
            ),
            Self::Missing { key, default } => {
                write!(
                    f,
                    "plugin state has no `{key}`: using the default {default}"
                )
            }
            Self::Unknown { key } => {
                write!(f, "plugin state has unknown parameter `{key}`: ignored")
            }
            Self::OutOfRange {
                key,
                value,
                clamped,
                range,
            } => write!(
                f,
                "plugin state: `{key}` = {value} is outside [{}, {}]: clamped to {clamped}",
                range.0, range.1
            ),
            Self::Migrated {
                from,
                value,
                to,
                converted,
            } => write!(
                f,
                "plugin state: `{from}` = {value} m is now `{to}`, a fraction of the string's \
                 length: {converted}"
            ),
            Self::WrongType {
                key,
                value,
                loaded,
                converted,
            } => {
                let how = if *converted {
                    "converted to"
                } else {
                    "not a valid value, using the default"
                };
                write!(
                    f,
                    "plugin state: `{key}` = {value} has the wrong type: {how} {loaded}"
                )
            }
        }
    }
}

/// Whether the plugin stores `info` as an integer parameter (`IntParam`: integers and
/// enumerations) rather than a float.
fn is_int(info: &ParamInfo) -> bool {
    !matches!(info.kind, ParamKind::Float { .. })
}

/// The saved value `v` for `info` as a number, or `None` (with `converted = false`) when it
/// has no exact numeric meaning for this parameter. Enumeration names are matched ignoring
/// case, as the parameter's text input does: the display names (`"rectangular plate (simply
/// supported)"`) or the names preset files use (`"rect-plate"`, `"sav"`).
fn number_of(info: &ParamInfo, v: &ParamValue) -> (Option<f64>, bool) {
    match (v, is_int(info)) {
        (ParamValue::F32(x), false) => (Some(f64::from(*x)), true),
        (ParamValue::I32(i), true) => (Some(f64::from(*i)), true),
        (ParamValue::I32(i), false) => (Some(f64::from(*i)), false),
        (ParamValue::F32(x), true) if x.is_finite() && x.fract() == 0.0 => {
            (Some(f64::from(*x)), false)
        }
        (ParamValue::String(s), true) => {
            let by_name = info.enum_index(s).map(|i| i as f64);
            (
                by_name.or_else(|| s.trim().parse::<i32>().ok().map(f64::from)),
                false,
            )
        }
        _ => (None, false),
    }
}

fn show(v: &ParamValue) -> String {
    match v {
        ParamValue::F32(x) => x.to_string(),
        ParamValue::I32(i) => i.to_string(),
        ParamValue::Bool(b) => b.to_string(),
        ParamValue::String(s) => format!("{s:?}"),
    }
}

fn stored(info: &ParamInfo, x: f32) -> ParamValue {
    if is_int(info) {
        ParamValue::I32(x as i32)
    } else {
        ParamValue::F32(x)
    }
}

/// States saved before the bridge became a fraction of the string hold its position (or the
/// curved bridge's extent) in metres under [`LEGACY_BRIDGE_POSITION`]: converted with the
/// saved string length (or the default one) unless the new key is present too.
fn migrate_bridge(state: &mut PluginState, issues: &mut Vec<StateIssue>) {
    let Some(old) = state.params.remove(LEGACY_BRIDGE_POSITION) else {
        return;
    };
    let new = ParamId::BridgePosition.info();
    let number = |v: Option<&ParamValue>| match v {
        Some(ParamValue::F32(x)) => Some(f64::from(*x)),
        Some(ParamValue::I32(i)) => Some(f64::from(*i)),
        _ => None,
    };
    let length = number(state.params.get(ParamId::Size.info().key));
    match number(Some(&old)) {
        Some(metres) if !state.params.contains_key(new.key) => {
            let converted = legacy_bridge_fraction(metres, length);
            issues.push(StateIssue::Migrated {
                from: LEGACY_BRIDGE_POSITION,
                value: metres,
                to: new.key,
                converted,
            });
            state
                .params
                .insert(new.key.to_string(), ParamValue::F32(converted as f32));
        }
        _ => issues.push(StateIssue::Unknown {
            key: LEGACY_BRIDGE_POSITION.to_string(),
        }),
    }
}

/// Makes `state` defined (see the module documentation) and returns every change made, in
/// table order (then unknown keys). `current` is this plugin's version. Main thread.
pub fn repair(state: &mut PluginState, current: &'static str) -> Vec<StateIssue> {
    let mut issues = Vec::new();
    if state.version != current {
        issues.push(StateIssue::Version {
            saved: state.version.clone(),
            current,
        });
    }
    migrate_bridge(state, &mut issues);
    for info in PARAMS {
        let Some(v) = state.params.get(info.key) else {
            issues.push(StateIssue::Missing {
                key: info.key,
                default: info.default,
            });
            state
                .params
                .insert(info.key.to_string(), stored(info, info.default));
            continue;
        };
        let (number, exact_type) = number_of(info, v);
        let loaded = match number {
            Some(x) if x.is_finite() => {
                let clamped = (x as f32).clamp(info.min, info.max);
                if f64::from(clamped) != x {
                    issues.push(StateIssue::OutOfRange {
                        key: info.key,
                        value: x,
                        clamped,
                        range: (info.min, info.max),
                    });
                } else if !exact_type {
                    issues.push(StateIssue::WrongType {
                        key: info.key,
                        value: show(v),
                        loaded: clamped,
                        converted: true,
                    });
                }
                clamped
            }
            _ => {
                issues.push(StateIssue::WrongType {
                    key: info.key,
                    value: show(v),
                    loaded: info.default,
                    converted: false,
                });
                info.default
            }
        };
        state
            .params
            .insert(info.key.to_string(), stored(info, loaded));
    }
    let unknown: Vec<String> = state
        .params
        .keys()
        .filter(|k| !PARAMS.iter().any(|p| p.key == k.as_str()))
        .filter(|k| !PLUGIN_ONLY_KEYS.contains(&k.as_str()))
        .cloned()
        .collect();
    for key in unknown {
        state.params.remove(&key);
        issues.push(StateIssue::Unknown { key });
    }
    issues
}

#[cfg(test)]
mod tests {
    use super::*;
    use noether_core::engine::MODEL_NAMES;

    const V: &str = "0.1.0";

    fn full_state() -> PluginState {
        let params = PARAMS
            .iter()
            .map(|p| (p.key.to_string(), stored(p, p.default)))
            .collect();
        PluginState {
            version: V.to_string(),
            params,
            fields: Default::default(),
        }
    }

    fn value(s: &PluginState, id: ParamId) -> f32 {
        match s.params[id.info().key] {
            ParamValue::F32(x) => x,
            ParamValue::I32(i) => i as f32,
            ref other => panic!("{other:?}"),
        }
    }

    /// A state from before the bridge became a fraction: its metres become the fraction of
    /// the saved string length (30 mm on a 0.6 m string: 0.05).
    #[test]
    fn a_bridge_in_metres_becomes_a_fraction_of_the_string() {
        let mut s = full_state();
        s.params.remove(ParamId::BridgePosition.info().key);
        s.params
            .insert(LEGACY_BRIDGE_POSITION.into(), ParamValue::F32(0.03));
        s.params
            .insert(ParamId::Size.info().key.into(), ParamValue::F32(0.6));
        let issues = repair(&mut s, V);
        assert!(
            matches!(issues[..], [StateIssue::Migrated { .. }]),
            "{issues:?}"
        );
        assert!((value(&s, ParamId::BridgePosition) - 0.05).abs() < 1e-6);
        assert!(!s.params.contains_key(LEGACY_BRIDGE_POSITION));
    }

    /// A state this version saved is loaded unchanged, with no issue.
    #[test]
    fn a_good_state_is_untouched() {
        let mut s = full_state();
        assert!(repair(&mut s, V).is_empty());
        for p in PARAMS {
            assert_eq!(value(&s, p.id), p.default, "{}", p.key);
        }
    }

    /// The plugin's own bypass is kept as saved, with no issue (it is not in the engine's
    /// table, but it is no unknown key).
    #[test]
    fn the_bypass_is_kept() {
        let mut s = full_state();
        s.params
            .insert(crate::bypass::BYPASS_KEY.into(), ParamValue::Bool(true));
        assert!(repair(&mut s, V).is_empty());
        assert!(matches!(
            s.params.get(crate::bypass::BYPASS_KEY),
            Some(ParamValue::Bool(true))
        ));
    }

    /// An old-version state without some parameters: version reported, the missing ones get
    /// the table's default, every parameter present afterwards.
    #[test]
    fn old_version_missing_parameters_get_defaults() {
        let mut s = full_state();
        s.version = "0.0.9".into();
        s.params.remove("release_t60");
        s.params.remove("mod_wheel_depth");
        s.params
            .insert("release_t60_old".into(), ParamValue::F32(1.0));
        let issues = repair(&mut s, V);
        assert_eq!(issues.len(), 4, "{issues:?}");
        assert!(matches!(issues[0], StateIssue::Version { .. }));
        assert_eq!(
            value(&s, ParamId::ReleaseT60),
            ParamId::ReleaseT60.info().default
        );
        assert!(!s.params.contains_key("release_t60_old"));
        assert_eq!(s.params.len(), PARAMS.len());
    }

    /// Out of range: clamped into the table's range and reported with the saved value.
    #[test]
    fn out_of_range_values_are_clamped_and_reported() {
        let mut s = full_state();
        s.params.insert("size".into(), ParamValue::F32(1e30));
        s.params.insert("polyphony".into(), ParamValue::I32(-5));
        let issues = repair(&mut s, V);
        assert_eq!(value(&s, ParamId::Size), ParamId::Size.info().max);
        assert_eq!(value(&s, ParamId::Polyphony), 1.0);
        let text: Vec<String> = issues.iter().map(|i| i.to_string()).collect();
        assert!(
            text[0].contains("`size` = 1") && text[0].contains("outside [0.05, 3]: clamped to 3"),
            "{text:?}"
        );
        assert!(
            text[1].contains("`polyphony` = -5 is outside [1, 16]"),
            "{text:?}"
        );
    }

    /// Enumerations saved by the names preset files use (a preset's `[params]` table written
    /// as a state) load as those values: before, `"rect-plate"` and `"sav"` were not found
    /// among the display names and silently became the defaults (the gong).
    #[test]
    fn preset_file_enum_names_convert() {
        let mut s = full_state();
        s.params
            .insert("model".into(), ParamValue::String("rect-plate".into()));
        s.params
            .insert("scheme".into(), ParamValue::String("Stormer-Verlet".into()));
        s.params
            .insert("material".into(), ParamValue::String("bronze".into()));
        repair(&mut s, V);
        assert_eq!(value(&s, ParamId::Model), 2.0);
        assert_eq!(value(&s, ParamId::Scheme), 2.0);
        assert_eq!(value(&s, ParamId::Material), 1.0);
    }

    /// Wrong types: exact conversions kept, everything else the default; all reported.
    #[test]
    fn wrong_types_convert_or_default() {
        let mut s = full_state();
        s.params.insert("tension".into(), ParamValue::I32(200));
        s.params.insert("modes".into(), ParamValue::F32(64.0));
        s.params.insert("polyphony".into(), ParamValue::F32(2.5));
        s.params
            .insert("model".into(), ParamValue::String("SITAR".into()));
        s.params.insert("gain".into(), ParamValue::Bool(true));
        s.params
            .insert("scheme".into(), ParamValue::String("nope".into()));
        s.params
            .insert("thickness".into(), ParamValue::F32(f32::INFINITY));
        let issues = repair(&mut s, V);
        assert_eq!(issues.len(), 7, "{issues:?}");
        assert_eq!(value(&s, ParamId::Tension), 200.0);
        assert_eq!(value(&s, ParamId::Modes), 64.0);
        assert_eq!(
            value(&s, ParamId::Polyphony),
            ParamId::Polyphony.info().default
        );
        assert_eq!(MODEL_NAMES[value(&s, ParamId::Model) as usize], "sitar");
        assert_eq!(value(&s, ParamId::Gain), ParamId::Gain.info().default);
        assert_eq!(value(&s, ParamId::Scheme), ParamId::Scheme.info().default);
        assert_eq!(
            value(&s, ParamId::Thickness),
            ParamId::Thickness.info().default
        );
        // Every slot has its own type afterwards.
        for p in PARAMS {
            let int = matches!(s.params[p.key], ParamValue::I32(_));
            assert_eq!(int, is_int(p), "{}", p.key);
        }
    }

    /// The blob path nice-plug takes: JSON text parsed into a `PluginState` (a truncated or
    /// corrupt blob fails here, before `filter_state`), then repaired.
    #[test]
    fn json_blobs() {
        let good = serde_json::to_string(&full_state()).unwrap();
        for cut in [0, 1, good.len() / 2, good.len() - 1] {
            assert!(serde_json::from_str::<PluginState>(&good[..cut]).is_err());
        }
        assert!(serde_json::from_str::<PluginState>(r#"{"params": {}}"#).is_err());
        let mut s: PluginState = serde_json::from_str(
            r#"{"params": {"size": {"f32": 1e39}, "model": {"i32": 9}}, "fields": {}}"#,
        )
        .unwrap();
        let issues = repair(&mut s, V);
        assert_eq!(s.params.len(), PARAMS.len());
        // The last model, the range's top.
        assert_eq!(value(&s, ParamId::Model), ParamId::Model.info().max);
        // 1e39 overflows f32 to inf in serde_json: not finite, so the default.
        assert_eq!(value(&s, ParamId::Size), ParamId::Size.info().default);
        assert!(issues.len() >= PARAMS.len(), "{}", issues.len());
    }
}
