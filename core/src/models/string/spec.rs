//! The `[string]` table of a scene: the stiff string against an obstacle (SEED.md 3.2), its
//! losses, contact law, excitation, outputs and the instants of the shape plot.
//!
//! Parsed and validated on the thread that loads the scene; [`StringSpec::config`] turns it into
//! the model's [`StringConfig`] (no audio-thread use).

use crate::error::ParamError;
use crate::models::string::{
    ContactLaw, ContactScheme, Losses, Obstacle, OutputChannel, Quantity, Readout, SitarBridge,
    Stiffness, StrikeForce, StringConfig, StringParams, TrianglePluck, ValetteLosses,
};
use serde::{Deserialize, Serialize};

#[path = "spec_validate.rs"]
mod validate;

/// Largest number of modes a scene may ask for (grid of 20 001 intervals).
pub const MAX_MODES: usize = 20_000;

/// Modal damping of the string.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(tag = "law", rename_all = "kebab-case", deny_unknown_fields)]
pub enum StringLosses {
    /// No losses: the scheme conserves its discrete energy exactly.
    #[default]
    None,
    /// Air, viscoelastic and thermoelastic losses of Issanchou et al. 2017 (after Valette);
    /// coefficients left out take that paper's values.
    Valette {
        /// Air viscosity η_air in Pa·s (0 to 1).
        #[serde(default = "default_air_viscosity")]
        air_viscosity: f64,
        /// Air density ρ_air in kg/m³ (0 to 100).
        #[serde(default = "default_air_density")]
        air_density: f64,
        /// Viscoelastic loss angle δ_ve (0 to 1).
        #[serde(default = "default_delta_ve")]
        viscoelastic_delta: f64,
        /// Thermoelastic inverse quality factor Q_te⁻¹ (0 to 1).
        #[serde(default = "default_q_te")]
        thermoelastic_q_inv: f64,
    },
    /// A per-mode law `σ_j = a ω_j^b + c0` in 1/s (amplitude decays as `e^{-σ_j t}`).
    Power {
        /// Coefficient a (≥ 0).
        a: f64,
        /// Exponent b (0 to 2).
        b: f64,
        /// Constant part c0 in 1/s (≥ 0).
        #[serde(default)]
        c0: f64,
    },
    /// Given `σ_j` in 1/s for every mode `j = 1..=modes` (list of length `modes`).
    PerMode {
        /// The damping of each mode, 1/s (each 0 to 1e6).
        sigma: Vec<f64>,
    },
}

/// The default of [`StringSpec::sav_relaxation`] (s).
pub fn default_contact_relaxation() -> f64 {
    crate::models::sav_relaxation::DEFAULT_CONTACT_TIME_CONSTANT
}

fn default_contact_scheme() -> String {
    ContactScheme::default().name().into()
}
fn default_air_viscosity() -> f64 {
    ValetteLosses::default().air_viscosity
}
fn default_air_density() -> f64 {
    ValetteLosses::default().air_density
}
fn default_delta_ve() -> f64 {
    ValetteLosses::default().viscoelastic_delta
}
fn default_q_te() -> f64 {
    ValetteLosses::default().thermoelastic_q_inv
}

/// The obstacle under the string (heights in m on the displacement axis; the string
/// penetrates where `u < g`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum StringObstacle {
    /// No obstacle (a linear string).
    #[default]
    None,
    /// Curved sitar bridge `g(x) = height - curvature (x - position)²` for `0 < x ≤ extent`
    /// (the lecture's `g = a x²` with `a = -curvature`).
    Sitar {
        /// Apex position in m (0 to L).
        #[serde(default)]
        position: f64,
        /// Curvature in 1/m (-1e4 to 1e4).
        curvature: f64,
        /// Apex height in m (-0.1 to 0.1).
        #[serde(default)]
        height: f64,
        /// The bridge covers `0 < x ≤ extent`, m (inside the string).
        extent: f64,
    },
    /// A point bridge (the lecture's tanpura: position 6 mm, height 0).
    Point {
        /// Position in m (inside the string).
        position: f64,
        /// Height in m (-0.1 to 0.1).
        #[serde(default)]
        height: f64,
        /// Flat top length in m (0 to L); 0 = the nearest node only.
        #[serde(default)]
        width: f64,
    },
    /// A flat fretboard under the whole string at `g = -distance`.
    Fretboard {
        /// Distance below the rest line, m (0 to 0.1).
        distance: f64,
    },
    /// Point contacts `[position (m), height (m)]`, each on its nearest node.
    Points {
        /// The contacts.
        points: Vec<[f64; 2]>,
    },
}

/// The penalty contact law `f = K [η]_+^α`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StringContact {
    /// Stiffness K in N/m^(α+1) (1 to 1e18).
    pub stiffness: f64,
    /// Exponent α (1 to 10).
    pub exponent: f64,
}

impl From<ValetteLosses> for StringLosses {
    /// The Valette losses as a `[string.losses]` table (the inverse of [`StringSpec::config`]'s
    /// conversion).
    fn from(v: ValetteLosses) -> Self {
        StringLosses::Valette {
            air_viscosity: v.air_viscosity,
            air_density: v.air_density,
            viscoelastic_delta: v.viscoelastic_delta,
            thermoelastic_q_inv: v.thermoelastic_q_inv,
        }
    }
}

impl Default for StringContact {
    /// The lecture's K = 1e13, α = 1.5.
    fn default() -> Self {
        let l = ContactLaw::lecture();
        Self {
            stiffness: l.stiffness,
            exponent: l.exponent,
        }
    }
}

/// How the string is set in motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum StringExcitation {
    /// The lecture's triangular pluck: released at rest from a triangle with its peak
    /// `amplitude` (m) at `position` (m).
    Pluck {
        /// Peak position in m (inside the string).
        position: f64,
        /// Peak displacement in m (-0.05 to 0.05).
        amplitude: f64,
    },
    /// A time-limited raised-cosine force at a point.
    Strike {
        /// Position in m (inside the string).
        position: f64,
        /// Duration in s (1e-6 to 0.1).
        duration: f64,
        /// Peak force in N (-1e4 to 1e4; positive pushes towards +u).
        peak_force: f64,
    },
}

/// One output channel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum StringOutput {
    /// Displacement or velocity at a point.
    Pickup {
        /// Position in m (inside the string).
        position: f64,
        /// What it reads.
        #[serde(default)]
        quantity: Quantity,
        /// How it reads it.
        #[serde(default)]
        readout: Readout,
    },
    /// The total force on the obstacle (N).
    BridgeForce,
}

/// The `[string]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StringSpec {
    /// Length L in m (0.01 to 100).
    pub length: f64,
    /// Diameter d in m (0 to 0.1; used by the air-friction loss).
    #[serde(default)]
    pub diameter: f64,
    /// Tension T in N (1e-3 to 1e6).
    pub tension: f64,
    /// Linear density μ in kg/m (1e-6 to 100).
    pub linear_density: f64,
    /// Inharmonicity B = π² EI / (T L²) (0 to 1); give this or `bending_stiffness`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inharmonicity: Option<f64>,
    /// Bending stiffness EI in N·m² (0 to 1e6); give this or `inharmonicity`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bending_stiffness: Option<f64>,
    /// Number of modes N_m (1 to 20 000); the grid has N = N_m + 1 intervals (N_m + 1 with no
    /// prime factor above 7 keeps the sine transform fast, e.g. 1007, 503).
    pub modes: usize,
    /// Simulation rate in Hz (1 000 to 10 000 000); the scheme is stable at any rate.
    pub sim_rate: f64,
    /// Modal damping.
    #[serde(default)]
    pub losses: StringLosses,
    /// The obstacle.
    #[serde(default)]
    pub obstacle: StringObstacle,
    /// The contact law (default: the lecture's K = 1e13, α = 1.5).
    #[serde(default)]
    pub contact: StringContact,
    /// The contact scheme: `"newton"` (the lecture's discrete gradient solved by Newton, the
    /// default) or `"quadratised"` (energy quadratisation, one division per node; see
    /// `models::string::contact_sav`).
    #[serde(default = "default_contact_scheme")]
    pub contact_scheme: String,
    /// The quadratised contact's relaxation time constant in s (0 to 10; default
    /// [`crate::models::sav_relaxation::DEFAULT_CONTACT_TIME_CONSTANT`]): how fast the
    /// auxiliary `z_i` of a node off the obstacle decays to `√(2ψ(η_i)) = 0` (the energy it
    /// removes counted as dissipation, [`crate::models::sav_relaxation`]). 0: the plain
    /// quadratised scheme. Ignored by the Newton scheme.
    #[serde(default = "default_contact_relaxation")]
    pub sav_relaxation: f64,
    /// The excitation.
    pub excitation: StringExcitation,
    /// Output channels (default: velocity pickups at 0.37 L and 0.83 L, a stereo pair).
    #[serde(default)]
    pub outputs: Vec<StringOutput>,
    /// Instants (s) at which `--plot` draws the string's shape against the obstacle (default:
    /// six instants over the first period of the fundamental).
    #[serde(default)]
    pub snapshots: Vec<f64>,
}

impl StringSpec {
    /// The string's parameters (grid of `modes + 1` intervals at `sim_rate`).
    pub fn params(&self) -> StringParams {
        StringParams {
            length: self.length,
            tension: self.tension,
            linear_density: self.linear_density,
            stiffness: match (self.inharmonicity, self.bending_stiffness) {
                (_, Some(ei)) => Stiffness::BendingStiffness(ei),
                (b, None) => Stiffness::Inharmonicity(b.unwrap_or(0.0)),
            },
            diameter: self.diameter,
            intervals: self.modes + 1,
            sample_rate: self.sim_rate,
        }
    }

    /// The model configuration (call after [`StringSpec::validate`]).
    pub fn config(&self) -> StringConfig {
        let params = self.params();
        let losses = match &self.losses {
            StringLosses::None => Losses::None,
            StringLosses::Valette {
                air_viscosity,
                air_density,
                viscoelastic_delta,
                thermoelastic_q_inv,
            } => Losses::Valette(ValetteLosses {
                air_viscosity: *air_viscosity,
                air_density: *air_density,
                viscoelastic_delta: *viscoelastic_delta,
                thermoelastic_q_inv: *thermoelastic_q_inv,
            }),
            StringLosses::Power { a, b, c0 } => Losses::PerMode(
                (1..=self.modes)
                    .map(|j| a * params.omega(j).powf(*b) + c0)
                    .collect(),
            ),
            StringLosses::PerMode { sigma } => Losses::PerMode(sigma.clone()),
        };
        let obstacle = match &self.obstacle {
            StringObstacle::None => Obstacle::None,
            StringObstacle::Sitar {
                position,
                curvature,
                height,
                extent,
            } => Obstacle::Sitar(SitarBridge {
                position: *position,
                curvature: *curvature,
                height: *height,
                extent: *extent,
            }),
            StringObstacle::Point {
                position,
                height,
                width,
            } => Obstacle::Point {
                position: *position,
                height: *height,
                width: *width,
            },
            StringObstacle::Fretboard { distance } => Obstacle::Fretboard {
                distance: *distance,
            },
            StringObstacle::Points { points } => {
                Obstacle::Points(points.iter().map(|p| (p[0], p[1])).collect())
            }
        };
        let outputs = self
            .effective_outputs()
            .iter()
            .map(|o| match *o {
                StringOutput::BridgeForce => OutputChannel::ObstacleForce,
                StringOutput::Pickup {
                    position,
                    quantity,
                    readout,
                } => OutputChannel::Pickup {
                    position,
                    quantity,
                    readout,
                },
            })
            .collect();
        StringConfig {
            params,
            losses,
            obstacle,
            contact: ContactLaw {
                stiffness: self.contact.stiffness,
                exponent: self.contact.exponent,
            },
            outputs,
        }
    }

    /// The contact scheme named by `contact_scheme` (error naming `string.contact_scheme` and
    /// the allowed names otherwise).
    pub fn scheme(&self) -> Result<ContactScheme, ParamError> {
        ContactScheme::parse("string.contact_scheme", &self.contact_scheme)
    }

    /// The outputs to use: the scene's, or velocity pickups at 0.37 L and 0.83 L.
    pub fn effective_outputs(&self) -> Vec<StringOutput> {
        if !self.outputs.is_empty() {
            return self.outputs.clone();
        }
        [0.37, 0.83]
            .iter()
            .map(|&f| StringOutput::Pickup {
                position: f * self.length,
                quantity: Quantity::Velocity,
                readout: Readout::Grid,
            })
            .collect()
    }

    /// The instants of the shape plot: the scene's, or six over the first period `2L/c0`.
    pub fn effective_snapshots(&self) -> Vec<f64> {
        if !self.snapshots.is_empty() {
            return self.snapshots.clone();
        }
        let period = 2.0 * self.length / (self.tension / self.linear_density).sqrt();
        (0..6).map(|k| k as f64 * period / 6.0).collect()
    }

    /// The pluck, if the excitation is one.
    pub fn pluck(&self) -> Option<TrianglePluck> {
        match self.excitation {
            StringExcitation::Pluck {
                position,
                amplitude,
            } => Some(TrianglePluck {
                position,
                amplitude,
            }),
            StringExcitation::Strike { .. } => None,
        }
    }

    /// The strike force, if the excitation is one.
    pub fn strike(&self) -> Option<StrikeForce> {
        match self.excitation {
            StringExcitation::Strike {
                position,
                duration,
                peak_force,
            } => Some(StrikeForce {
                position,
                duration,
                peak: peak_force,
            }),
            StringExcitation::Pluck { .. } => None,
        }
    }

    /// Highest modal frequency f_{N_m} in Hz.
    pub fn f_max(&self) -> f64 {
        self.params().omega(self.modes) / std::f64::consts::TAU
    }
}
