//! The `[sitar]` table of a scene: the played string and its taraf of sympathetic strings,
//! tuned to a thaat, on the main bridge and the taraf's small bridge. [`SitarSpec::network`]
//! turns it into the network of strings on the bridges.
//!
//! Parsed and validated on the thread that loads it; never on the audio thread.

use super::phrase::SitarStroke;
use super::thaat::Thaat;
use crate::error::{check_closed, ParamError};
use crate::models::network::{BridgeMode, NetworkConfig, SeatedString};
use crate::models::string::{
    Losses, Obstacle, SeatSpec, Stiffness, StringConfig, StringParams, ValetteLosses,
};
use crate::models::tanpura::spec::{
    curved_top, default_pluck_amplitude, default_true, JAWARI_CONTACT, SEAT_STIFFNESS,
};
use crate::models::tanpura::Metal;
use serde::{Deserialize, Serialize};

/// Length of the played string, m.
pub const MAIN_LENGTH: f64 = 0.9;
/// Diameter of the played string (steel), m.
pub const MAIN_DIAMETER: f64 = 0.3e-3;
/// Length of a taraf string, m.
pub const TARAF_LENGTH: f64 = 0.45;
/// Diameter of a taraf string (steel), m.
pub const TARAF_DIAMETER: f64 = 0.2e-3;
/// Diameter of a chikari string (steel), m.
pub const CHIKARI_DIAMETER: f64 = 0.2e-3;
/// A chikari string's length times its pitch, m/s: half the transverse wave speed
/// `√(σ/ρ)` of steel at a stress `σ` of 1.5 GPa, 60 % of a music wire's tensile strength
/// (about 2.5 GPa). Set so, each chikari is as long as its pitch allows (Sa' 0.40 m, Sa''
/// 0.20 m on Sa = C#4): a sitar's chikari pegs sit along the neck at about those lengths.
pub const CHIKARI_SPEED: f64 = 218.5;
/// The chikari's notes over Sa, in the order they are strung: the upper Sa, the Sa above it,
/// and Pa between them (a third chikari on some sitars).
pub const CHIKARI_RATIOS: [f64; 3] = [2.0, 4.0, 3.0];
/// Pan of the chikari in the image (-1 left to 1 right): the chikari lie beside the played
/// string on the main bridge.
pub const CHIKARI_PAN: f64 = -0.3;

/// Curvature of the main bridge's top (1/m; the lecture's sitar bridge, 80 µm below the
/// string's rest line 20 mm from the edge).
pub const MAIN_BRIDGE_CURVATURE: f64 = 0.2;

/// The bridges: the main bridge's bounce (190 Hz, 60 g) and rocking (480 Hz, 30 g) modes and
/// the taraf bridge's own mode (850 Hz, 10 g), with the shapes under the played string and
/// under the taraf ([`MAIN_SHAPE`], [`TARAF_SHAPE`]): a modal model of the two bridges on one
/// soundboard, which moves the taraf bridge when the main bridge moves and back.
pub fn bridge_modes() -> Vec<BridgeMode> {
    vec![
        BridgeMode {
            frequency: 190.0,
            mass: 0.06,
            t60: 0.3,
        },
        BridgeMode {
            frequency: 480.0,
            mass: 0.03,
            t60: 0.3,
        },
        BridgeMode {
            frequency: 850.0,
            mass: 0.01,
            t60: 0.2,
        },
    ]
}

/// The bridge modes' shapes under the played string.
pub const MAIN_SHAPE: [f64; 3] = [1.0, 0.6, 0.2];
/// The bridge modes' shapes under every taraf string.
pub const TARAF_SHAPE: [f64; 3] = [0.4, -0.5, 1.0];

/// A sitar scene: one played note and the taraf that answers it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SitarSpec {
    /// Sa of the taraf's lower octave, Hz (100 to 600).
    pub sa: f64,
    /// The played note, Hz (60 to 1200): the played string sounds it (its frets are not
    /// modelled: the string is tuned to the note).
    pub note: f64,
    /// The taraf's thaat.
    #[serde(default)]
    pub thaat: Thaat,
    /// Number of taraf strings (0 to 13; a sitar has 11 to 13).
    #[serde(default = "default_taraf")]
    pub taraf: usize,
    /// Fine tuning of each taraf string in cents (-100 to 100; empty, or one per string).
    #[serde(default)]
    pub taraf_cents: Vec<f64>,
    /// Modes of the played string (32 to 4000).
    #[serde(default = "default_modes")]
    pub modes: usize,
    /// Modes of each taraf string (8 to 2000).
    #[serde(default = "default_taraf_modes")]
    pub taraf_modes: usize,
    /// Number of chikari strings (0 to 3; default 0): the high drone strings beside the played
    /// string on the main bridge, with its jawari, tuned to [`CHIKARI_RATIOS`] of Sa and
    /// plucked by the phrase's strokes that ask for them ([`SitarStroke::chikari`]). They come
    /// after the taraf among the strings; their grid spacing is the played string's, so the
    /// jawari is resolved alike.
    #[serde(default)]
    pub chikari: usize,
    /// Simulation rate, Hz (16 000 to 1 000 000; default 192 000, where the played string's
    /// modes stay under the Nyquist frequency).
    #[serde(default = "default_sim_rate")]
    pub sim_rate: f64,
    /// Pluck position as a fraction of the played string's length from the bridge (0.02 to
    /// 0.95; the mizrab strikes near the bridge).
    #[serde(default = "default_pluck_position")]
    pub pluck_position: f64,
    /// Pluck amplitude, m (1e-5 to 5e-3).
    #[serde(default = "default_pluck_amplitude")]
    pub pluck_amplitude: f64,
    /// Tune every string by ear at build ([`crate::models::tanpura::tune`]).
    #[serde(default = "default_true")]
    pub tune_by_ear: bool,
    /// The phrase played on the played string, in time order ([`SitarStroke`]: frets and
    /// meends); empty (the default): `note` plucked at the start. The played string is tuned
    /// (by ear) to `note` either way, its open pitch.
    #[serde(default)]
    pub phrase: Vec<SitarStroke>,
}

fn default_taraf() -> usize {
    11
}
fn default_modes() -> usize {
    300
}
fn default_taraf_modes() -> usize {
    48
}
fn default_pluck_position() -> f64 {
    0.12
}
/// The default simulation rate (Hz): at Ga the played string's 300 modes reach 123 kHz through
/// its stiffness, and only the top 55 lie above the Nyquist frequency of 192 kHz (96 kHz),
/// where the exchange has converged (docs/models.md). Where a string's modes lie far above the Nyquist
/// frequency its sampled couplings (seat, jawari, bridge) alias and the sympathetic exchange
/// collapses erratically (docs/models.md, "Strings on a moving bridge").
fn default_sim_rate() -> f64 {
    192_000.0
}

impl SitarSpec {
    /// A sitar on `sa` Hz playing `note` Hz, every other field at its default.
    pub fn at(sa: f64, note: f64) -> Self {
        Self {
            sa,
            note,
            thaat: Thaat::default(),
            taraf: default_taraf(),
            taraf_cents: Vec::new(),
            modes: default_modes(),
            taraf_modes: default_taraf_modes(),
            chikari: 0,
            sim_rate: default_sim_rate(),
            pluck_position: default_pluck_position(),
            pluck_amplitude: default_pluck_amplitude(),
            tune_by_ear: true,
            phrase: Vec::new(),
        }
    }

    /// Checks every field; errors name `sitar.<field>`.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_closed("sitar.sa", self.sa, 100.0, 600.0)?;
        check_closed("sitar.note", self.note, 60.0, 1200.0)?;
        if self.taraf > 13 {
            return Err(ParamError::new("sitar.taraf", self.taraf, "0 to 13"));
        }
        if !(self.taraf_cents.is_empty() || self.taraf_cents.len() == self.taraf) {
            return Err(ParamError::new(
                "sitar.taraf_cents",
                format!("{} values", self.taraf_cents.len()),
                format!("none or one per taraf string ({})", self.taraf),
            ));
        }
        for (i, &c) in self.taraf_cents.iter().enumerate() {
            check_closed(&format!("sitar.taraf_cents[{i}]"), c, -100.0, 100.0)?;
        }
        if self.chikari > CHIKARI_RATIOS.len() {
            return Err(ParamError::new(
                "sitar.chikari",
                self.chikari,
                format!("0 to {}", CHIKARI_RATIOS.len()),
            ));
        }
        if !(32..=4000).contains(&self.modes) {
            return Err(ParamError::new("sitar.modes", self.modes, "32 to 4000"));
        }
        if !(8..=2000).contains(&self.taraf_modes) {
            return Err(ParamError::new(
                "sitar.taraf_modes",
                self.taraf_modes,
                "8 to 2000",
            ));
        }
        check_closed("sitar.sim_rate", self.sim_rate, 16_000.0, 1e6)?;
        check_closed("sitar.pluck_position", self.pluck_position, 0.02, 0.95)?;
        check_closed("sitar.pluck_amplitude", self.pluck_amplitude, 1e-5, 5e-3)?;
        let mut previous = 0.0;
        for (i, stroke) in self.phrase.iter().enumerate() {
            stroke.validate(i, previous)?;
            previous = stroke.at;
        }
        Ok(())
    }

    /// Every string's target frequency (Hz): the played note, then the taraf (the thaat from
    /// Sa up, moved by their fine tuning), then the chikari.
    pub fn targets(&self) -> Vec<f64> {
        let mut t = vec![self.note];
        for (i, r) in self.thaat.taraf(self.taraf).into_iter().enumerate() {
            let cents = self.taraf_cents.get(i).copied().unwrap_or(0.0);
            t.push(self.sa * r * 2f64.powf(cents / 1200.0));
        }
        t.extend(CHIKARI_RATIOS[..self.chikari].iter().map(|r| self.sa * r));
        t
    }

    /// Number of strings: the played string, the taraf and the chikari.
    pub fn strings(&self) -> usize {
        1 + self.taraf + self.chikari
    }

    /// Whether string `i` is a chikari.
    pub fn is_chikari(&self, i: usize) -> bool {
        i > self.taraf && i < self.strings()
    }

    /// String `i`'s `(length m, diameter m, modes)`: the played string first, then the taraf,
    /// then the chikari (length [`CHIKARI_SPEED`] over the pitch, modes for the played
    /// string's grid spacing, at least 16).
    pub fn geometry(&self, i: usize) -> (f64, f64, usize) {
        if i == 0 {
            (MAIN_LENGTH, MAIN_DIAMETER, self.modes)
        } else if self.is_chikari(i) {
            let length = CHIKARI_SPEED / (self.sa * CHIKARI_RATIOS[i - 1 - self.taraf]);
            let dx = MAIN_LENGTH / (self.modes + 1) as f64;
            let modes = ((length / dx).round() as usize).saturating_sub(1).max(16);
            (length, CHIKARI_DIAMETER, modes)
        } else {
            (TARAF_LENGTH, TARAF_DIAMETER, self.taraf_modes)
        }
    }

    /// String `i`'s nominal tension `μ (2 L f)²` (N).
    pub fn nominal_tension(&self, i: usize) -> f64 {
        let (l, d, _) = self.geometry(i);
        let mu = Metal::Steel.linear_density(d);
        mu * (2.0 * l * self.targets()[i]).powi(2)
    }

    /// The network with string `i` at `tension_scale[i]` times its nominal tension. Validates.
    pub fn network(&self, tension_scale: &[f64]) -> Result<NetworkConfig, ParamError> {
        self.validate()?;
        let strings = (0..self.strings())
            .map(|i| {
                let (length, diameter, modes) = self.geometry(i);
                let intervals = modes + 1;
                let dx = length / intervals as f64;
                let params = StringParams {
                    length,
                    tension: self.nominal_tension(i) * tension_scale[i],
                    linear_density: Metal::Steel.linear_density(diameter),
                    stiffness: Stiffness::BendingStiffness(
                        Metal::Steel.bending_stiffness(diameter),
                    ),
                    diameter,
                    intervals,
                    sample_rate: self.sim_rate,
                };
                // The played string and the chikari cross the main bridge and its jawari.
                let (obstacle, shape) = if i == 0 || self.is_chikari(i) {
                    (
                        curved_top(MAIN_BRIDGE_CURVATURE, 0.0, dx, modes),
                        MAIN_SHAPE,
                    )
                } else {
                    (Obstacle::None, TARAF_SHAPE)
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
                        position: dx,
                        stiffness: SEAT_STIFFNESS,
                    },
                    bridge_shape: shape.to_vec(),
                    band_limit: f64::INFINITY,
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
