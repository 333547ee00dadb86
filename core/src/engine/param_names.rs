//! The names of the enumeration parameters' values ([`super::params::PARAMS`]): what the
//! editor and the host show, and what presets and plugin states write. Static data, any
//! thread.

use super::kinds::ModelKind;
use crate::models::plate::PlateScheme;

/// Names of `ParamId::Model` values, in index order (see [`ModelKind`](super::ModelKind)).
pub const MODEL_NAMES: &[&str] = &[
    "gong (circular, free edge)",
    "cymbal (circular, clamped edge)",
    "rectangular plate (simply supported)",
    "sitar",
    "tanpura",
    "tanpura drone",
    "sitar with taraf",
];

/// Preset names of `ParamId::Model` values, in index order ([`ModelKind::key`](super::ModelKind::key)).
pub const MODEL_KEYS: &[&str] = &ModelKind::KEYS;

/// Names of `ParamId::DroneTuning` values: the first string's note (`models::tanpura::Tuning`).
pub const DRONE_TUNING_NAMES: &[&str] =
    &["Pa-Sa-Sa-Sa", "Ma-Sa-Sa-Sa", "Ni-Sa-Sa-Sa", "Sa-Sa-Sa-Sa"];

/// Preset names of `ParamId::DroneTuning` values, in index order (the scenes' names).
pub const DRONE_TUNING_KEYS: &[&str] = &["pa", "ma", "ni", "sa"];

/// Names of `ParamId::DronePattern` values (`models::tanpura::Pattern`).
pub const DRONE_PATTERN_NAMES: &[&str] = &["three and a pause", "even"];

/// Preset names of `ParamId::DronePattern` values, in index order (the scenes' names).
pub const DRONE_PATTERN_KEYS: &[&str] = &["classic", "even"];

/// Names of `ParamId::SitarThaat` values (`models::sitar::Thaat`), their degrees.
pub const THAAT_NAMES: &[&str] = &[
    "Bilawal (S R G M P D N)",
    "Kalyan (S R G M# P D N)",
    "Khamaj (S R G M P D n)",
    "Kafi (S R g M P D n)",
    "Asavari (S R g M P d n)",
    "Bhairavi (S r g M P d n)",
    "Bhairav (S r G M P d N)",
    "Purvi (S r G M# P d N)",
    "Marwa (S r G M# P D N)",
    "Todi (S r g M# P d N)",
];

/// Preset names of `ParamId::SitarThaat` values, in index order (the scenes' names).
pub const THAAT_KEYS: &[&str] = &crate::models::sitar::Thaat::KEYS;

/// Names of the two values of a switch parameter (`limiter`).
pub const ON_OFF_NAMES: &[&str] = &["off", "on"];

/// Names of `ParamId::Exciter` values: the prescribed force pulse or the physical mallet.
pub const EXCITER_NAMES: &[&str] = &["pulse", "mallet"];

/// Names of `ParamId::MalletHead` values: the mass, hardness and fixed felt loss of the
/// other mallet parameters, or a factory head ([`crate::models::plate::MalletHead`]).
pub const MALLET_HEAD_NAMES: &[&str] = &[
    "custom",
    "soft-felt",
    "hard-felt",
    "rubber",
    "wood",
    "metal",
];

/// Names of `ParamId::Material` values (see [`Material`](super::Material)).
pub const MATERIAL_NAMES: &[&str] = &["steel", "bronze", "brass", "aluminium", "custom"];

/// Names of `ParamId::Scheme` values (plates; strings always use their exact modal scheme
/// with Newton contact).
pub const SCHEME_NAMES: &[&str] = &[
    "conservative (theta = 1)",
    "conservative, exact linear part",
    "Stormer-Verlet (explicit, not conservative)",
    "SAV (explicit, energy-conserving)",
];

/// Preset names of `ParamId::Scheme` values, in index order: the schemes' own names
/// ([`PlateScheme::name`], in the order of [`PlateScheme::ALL`]).
pub const SCHEME_KEYS: &[&str] = &[
    PlateScheme::ALL[0].name(),
    PlateScheme::ALL[1].name(),
    PlateScheme::ALL[2].name(),
    PlateScheme::ALL[3].name(),
];
