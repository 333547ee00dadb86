//! The `[tanpura]` table of a scene (and, later, of the engine's drone): Sa, the tuning, the
//! strings, the pluck cycle, the jivari and the fine tuning of each string, and the
//! simulation's grid and rate. [`TanpuraSpec::network`] turns it into the
//! [`NetworkConfig`] of its strings on the bridge.
//!
//! Parsed and validated on the thread that loads it; never on the audio thread.

use super::cycle::Pattern;
use super::tuning::{strings, TanpuraString, Tuning};
use crate::error::{check_closed, ParamError};
use crate::models::network::{BridgeMode, NetworkConfig, SeatedString};
use crate::models::string::{
    ContactLaw, Losses, Obstacle, SeatSpec, Stiffness, StringConfig, StringParams, ValetteLosses,
};
use serde::{Deserialize, Serialize};

/// Length of the bridge's top under the string, m (the curved jawari's extent).
pub const BRIDGE_TOP: f64 = 0.02;

/// Seat spring of every string (N/m): the string's node on the bridge's back edge follows the
/// bridge (its own resonance on the spring, `√(K/(μΔx))/2π`, lies far above the audio band).
pub const SEAT_STIFFNESS: f64 = 2e5;

/// The jawari's contact law: the lecture's tanpura softened as in the `tanpura` preset
/// (`K = 1e11`, `α = 1.5`), so a grid of a few hundred modes resolves the contact.
pub const JAWARI_CONTACT: ContactLaw = ContactLaw {
    stiffness: 1e11,
    exponent: 1.5,
};

/// The tanpura's bridge: a bounce mode at 180 Hz (40 g) and a rocking mode at 430 Hz (25 g),
/// both decaying in 0.3 s (the bridge and the soundboard under it; orders of magnitude from
/// Issanchou et al., JASA 2018, for a bridge on a thin top).
pub fn bridge_modes() -> Vec<BridgeMode> {
    vec![
        BridgeMode {
            frequency: 180.0,
            mass: 0.04,
            t60: 0.3,
        },
        BridgeMode {
            frequency: 430.0,
            mass: 0.025,
            t60: 0.3,
        },
    ]
}

/// A tanpura scene or drone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TanpuraSpec {
    /// Sa, the key the player holds, in Hz (30 to 1000).
    pub sa: f64,
    /// The first string's note.
    #[serde(default)]
    pub tuning: Tuning,
    /// Number of strings (4 to 6).
    #[serde(default = "default_strings")]
    pub strings: usize,
    /// Speaking length of every string in m (0.4 to 1.5).
    #[serde(default = "default_length")]
    pub length: f64,
    /// Modes per string (32 to 4000); the grid step `Δx = L/(modes + 1)` also sets how finely
    /// the jivari's position is resolved.
    #[serde(default = "default_modes")]
    pub modes: usize,
    /// Simulation rate in Hz (16 000 to 1 000 000).
    #[serde(default = "default_sim_rate")]
    pub sim_rate: f64,
    /// Period of the pluck cycle in s (0.5 to 30).
    #[serde(default = "default_cycle")]
    pub cycle_seconds: f64,
    /// The cycle's rhythm.
    #[serde(default)]
    pub pattern: Pattern,
    /// Largest shift of an onset, ms (0 to 50).
    #[serde(default)]
    pub timing_jitter_ms: f64,
    /// Largest relative change of a pluck's strength (0 to 0.5).
    #[serde(default)]
    pub strength_jitter: f64,
    /// Seed of the variation.
    #[serde(default = "default_seed")]
    pub seed: u64,
    /// The jivari (the thread under the string) of each string: its distance from the bridge's
    /// back edge in mm, where the string grazes the bridge (one value for every string, or one
    /// per string; 0 takes the thread out: no jawari). Resolved to the nearest grid node,
    /// which must lie beyond the seat (at least `1.5 Δx`) and within 30 mm.
    #[serde(default = "default_jivari")]
    pub jivari_mm: Vec<f64>,
    /// Curvature of the bridge's top in 1/m (0 to 100): 0 makes the jawari a point contact at
    /// the jivari (the lecture's tanpura); above 0 the top is a parabola over the bridge's
    /// first [`BRIDGE_TOP`] m whose crest the thread puts at the jivari, touching the string's
    /// rest line there and falling away on both sides (`g = -c (x - x_j)²`).
    #[serde(default)]
    pub bridge_curvature: f64,
    /// Fine tuning of each string in cents (-100 to 100; empty for none, or one per string).
    #[serde(default)]
    pub fine_cents: Vec<f64>,
    /// Pluck position as a fraction of the length from the bridge (0.05 to 0.95).
    #[serde(default = "default_pluck_position")]
    pub pluck_position: f64,
    /// Pluck amplitude in m (1e-5 to 5e-3).
    #[serde(default = "default_pluck_amplitude")]
    pub pluck_amplitude: f64,
    /// Tune every string by ear at build: pluck it alone on the bridge, measure its first
    /// partial after the attack and correct its tension, twice (see [`super::tune`]).
    #[serde(default = "default_true")]
    pub tune_by_ear: bool,
    /// Step only each string's modes below [`ALIAS_FREE_BAND`] of the Nyquist frequency, at
    /// every key (the grid, and the jivari's place on it, stay as `modes` sets them): no
    /// string mode aliases, and the jawari's contact is solved against the modes that sound
    /// ([`crate::models::string::StiffString::set_band_limit`]). Needs a point jawari
    /// (`bridge_curvature = 0`). Left out of the serialised spec when off, so the tuning
    /// caches of drones that step every mode keep their names.
    #[serde(default, skip_serializing_if = "is_off")]
    pub alias_free: bool,
}

/// The band an alias-free string steps, as a fraction of the Nyquist frequency (21.6 kHz at
/// 48 kHz: above hearing, and every mode stepped stays a sampled sinusoid).
pub const ALIAS_FREE_BAND: f64 = 0.9;

/// Serde's skip test for a flag that is off.
fn is_off(flag: &bool) -> bool {
    !*flag
}

fn default_strings() -> usize {
    4
}
fn default_length() -> f64 {
    1.0
}
fn default_modes() -> usize {
    480
}
/// Serde default (shared with the sitar).
pub(crate) fn default_sim_rate() -> f64 {
    48_000.0
}
fn default_cycle() -> f64 {
    4.0
}
fn default_seed() -> u64 {
    1
}
fn default_jivari() -> Vec<f64> {
    vec![5.0]
}
fn default_pluck_position() -> f64 {
    0.3
}
/// Serde default (shared with the sitar).
pub(crate) fn default_pluck_amplitude() -> f64 {
    1e-3
}
/// Serde default (shared with the sitar).
pub(crate) fn default_true() -> bool {
    true
}

impl TanpuraSpec {
    /// A four-string tanpura at `sa` Hz with every other field at its default.
    pub fn at(sa: f64) -> Self {
        Self {
            sa,
            tuning: Tuning::default(),
            strings: default_strings(),
            length: default_length(),
            modes: default_modes(),
            sim_rate: default_sim_rate(),
            cycle_seconds: default_cycle(),
            pattern: Pattern::default(),
            timing_jitter_ms: 0.0,
            strength_jitter: 0.0,
            seed: default_seed(),
            jivari_mm: default_jivari(),
            fine_cents: Vec::new(),
            bridge_curvature: 0.0,
            pluck_position: default_pluck_position(),
            pluck_amplitude: default_pluck_amplitude(),
            tune_by_ear: true,
            alias_free: false,
        }
    }

    /// The highest mode frequency each string steps (Hz): [`ALIAS_FREE_BAND`] of the Nyquist
    /// frequency when `alias_free`, else infinite (every mode).
    pub fn band_limit(&self) -> f64 {
        if self.alias_free {
            ALIAS_FREE_BAND * 0.5 * self.sim_rate
        } else {
            f64::INFINITY
        }
    }

    /// Grid step in m.
    pub fn dx(&self) -> f64 {
        self.length / self.intervals() as f64
    }

    /// Grid intervals: `modes + 1`.
    pub fn intervals(&self) -> usize {
        self.modes + 1
    }

    /// Checks every field; errors name `tanpura.<field>`.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_closed("tanpura.sa", self.sa, 30.0, 1000.0)?;
        if !(4..=6).contains(&self.strings) {
            return Err(ParamError::new("tanpura.strings", self.strings, "4 to 6"));
        }
        check_closed("tanpura.length", self.length, 0.4, 1.5)?;
        if !(32..=4000).contains(&self.modes) {
            return Err(ParamError::new("tanpura.modes", self.modes, "32 to 4000"));
        }
        check_closed("tanpura.sim_rate", self.sim_rate, 16_000.0, 1e6)?;
        check_closed("tanpura.cycle_seconds", self.cycle_seconds, 0.5, 30.0)?;
        check_closed("tanpura.timing_jitter_ms", self.timing_jitter_ms, 0.0, 50.0)?;
        check_closed("tanpura.strength_jitter", self.strength_jitter, 0.0, 0.5)?;
        check_closed("tanpura.pluck_position", self.pluck_position, 0.05, 0.95)?;
        check_closed("tanpura.pluck_amplitude", self.pluck_amplitude, 1e-5, 5e-3)?;
        check_closed(
            "tanpura.bridge_curvature",
            self.bridge_curvature,
            0.0,
            100.0,
        )?;
        self.per_string("jivari_mm", &self.jivari_mm, false)?;
        self.per_string("fine_cents", &self.fine_cents, true)?;
        let lo = 1.5 * self.dx() * 1e3;
        for (i, &j) in self.jivari_mm.iter().enumerate() {
            if j != 0.0 && !(j.is_finite() && j >= lo && j <= 30.0) {
                return Err(ParamError::new(
                    format!("tanpura.jivari_mm[{i}]"),
                    j,
                    format!("0 (no thread) or {lo:.2} to 30 mm (beyond the seat, 1.5 grid steps)"),
                ));
            }
        }
        for (i, &c) in self.fine_cents.iter().enumerate() {
            check_closed(&format!("tanpura.fine_cents[{i}]"), c, -100.0, 100.0)?;
        }
        if self.alias_free && self.bridge_curvature != 0.0 {
            return Err(ParamError::new(
                "tanpura.alias_free",
                true,
                "false with a curved bridge top (bridge_curvature > 0); true needs a point jawari",
            ));
        }
        Ok(())
    }

    /// A per-string list: one value, one per string, or (if `may_be_empty`) none.
    fn per_string(&self, field: &str, v: &[f64], may_be_empty: bool) -> Result<(), ParamError> {
        let ok = v.len() == 1 || v.len() == self.strings || (may_be_empty && v.is_empty());
        if ok {
            Ok(())
        } else {
            Err(ParamError::new(
                format!("tanpura.{field}"),
                format!("{} values", v.len()),
                format!("one value or one per string ({})", self.strings),
            ))
        }
    }

    /// String `i`'s value of a per-string list (`default` when the list is empty).
    fn of(v: &[f64], i: usize, default: f64) -> f64 {
        match v.len() {
            0 => default,
            1 => v[0],
            _ => v[i],
        }
    }

    /// The strings in plucking order.
    pub fn string_table(&self) -> Vec<TanpuraString> {
        strings(self.tuning, self.strings)
    }

    /// String `i`'s target frequency in Hz: its ratio times Sa, moved by its fine tuning.
    pub fn target_hz(&self, i: usize) -> f64 {
        let cents = Self::of(&self.fine_cents, i, 0.0);
        self.string_table()[i].ratio * self.sa * 2f64.powf(cents / 1200.0)
    }

    /// String `i`'s jivari in m (`None`: no thread).
    pub fn jivari(&self, i: usize) -> Option<f64> {
        let mm = Self::of(&self.jivari_mm, i, 0.0);
        (mm != 0.0).then_some(mm * 1e-3)
    }

    /// The nominal tension of string `i` (N): `μ (2 L f)²`, the ideal string's.
    pub fn nominal_tension(&self, i: usize) -> f64 {
        let s = self.string_table()[i];
        s.linear_density() * (2.0 * self.length * self.target_hz(i)).powi(2)
    }

    /// The network of the strings on the bridge with string `i` at `tension_scale[i]` times
    /// its nominal tension. Validates first.
    pub fn network(&self, tension_scale: &[f64]) -> Result<NetworkConfig, ParamError> {
        self.validate()?;
        let n = self.strings;
        let table = self.string_table();
        let strings = (0..n)
            .map(|i| {
                let s = table[i];
                let params = StringParams {
                    length: self.length,
                    tension: self.nominal_tension(i) * tension_scale[i],
                    linear_density: s.linear_density(),
                    stiffness: Stiffness::BendingStiffness(s.bending_stiffness()),
                    diameter: s.diameter,
                    intervals: self.intervals(),
                    sample_rate: self.sim_rate,
                };
                let obstacle = match self.jivari(i) {
                    Some(x) if self.bridge_curvature > 0.0 => {
                        curved_top(self.bridge_curvature, x, self.dx(), self.modes)
                    }
                    Some(x) => Obstacle::Point {
                        position: x,
                        height: 0.0,
                        width: 0.0,
                    },
                    None => Obstacle::None,
                };
                // The rocking mode's shape runs across the bridge, string by string.
                let across = if n > 1 {
                    2.0 * i as f64 / (n - 1) as f64 - 1.0
                } else {
                    0.0
                };
                SeatedString {
                    config: StringConfig {
                        params,
                        losses: Losses::Valette(ValetteLosses::default()),
                        obstacle,
                        contact: JAWARI_CONTACT,
                        outputs: Vec::new(),
                    },
                    seat: SeatSpec {
                        position: self.dx(),
                        stiffness: SEAT_STIFFNESS,
                    },
                    bridge_shape: vec![1.0, 0.8 * across],
                    band_limit: self.band_limit(),
                }
            })
            .collect();
        Ok(NetworkConfig {
            strings,
            bridge: bridge_modes(),
            outputs: Vec::new(),
        })
    }
}

/// A bridge's curved top with its crest at `x_c` (m), curvature `c` (1/m): `g = -c (x - x_c)²`
/// on the grid nodes (step `dx` m, `modes` interior nodes) from the second (the first is the
/// seat) to [`BRIDGE_TOP`] or the crest, whichever is further.
pub fn curved_top(c: f64, x_c: f64, dx: f64, modes: usize) -> Obstacle {
    let end = BRIDGE_TOP.max(x_c) + 0.5 * dx;
    Obstacle::Profile(
        (1..=modes)
            .map(|k| {
                let x = k as f64 * dx;
                (k >= 2 && x <= end).then(|| -c * (x - x_c).powi(2))
            })
            .collect(),
    )
}
