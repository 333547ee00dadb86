//! The `[plate]` table of a scene: geometry, material, modes, scheme, losses, excitation,
//! pickups.

use super::mallet_heads::{HeadLaw, MalletHead};
use super::rest_shape::validate_parts;
/// One part of `plate.imperfection` (the rest shape's own type).
pub use super::rest_shape::ShapePart;
use crate::error::{check_closed, ParamError};
use crate::modal::scaling::{flexural_rigidity, pulsation_scale};
use crate::models::ranges::*;
use serde::{Deserialize, Serialize};

/// Plate geometry and boundary conditions (its own leaf module, re-exported here).
pub use super::geometry::PlateShape;

/// Time scheme of the plate (`plate.scheme`): the model's own enumeration.
pub use super::params::PlateScheme;

/// Storage of the coupling tensor (`plate.tensor_storage`): the tensor's own enumeration.
pub use crate::modal::TensorStorage;

/// Which motions a circular plate's modal basis represents (`plate.symmetry`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Symmetry {
    /// Every mode (`cos nθ` and `sin nθ`): any motion.
    #[default]
    Full,
    /// Only modes even about the strike's diameter (`cos n(θ - θ_strike)`): exact for the
    /// motion a strike excites, half the modes for the same band, so about an eighth of the
    /// coupling work; leaves out symmetry-breaking motion (see
    /// [`crate::modal::CircularPlateSpec::mirror_symmetric`]). Circular plates only.
    StrikeMirror,
}

impl Symmetry {
    /// The subspace's name in scenes and reports (`full`, `strike-mirror`).
    pub fn name(self) -> &'static str {
        match self {
            Symmetry::Full => "full",
            Symmetry::StrikeMirror => "strike-mirror",
        }
    }
}

/// Isotropic material; fields left out take the lecture's steel values.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E in Pa (1e6 to 1e13).
    pub youngs_modulus: f64,
    /// Density ρ in kg/m³ (10 to 1e5).
    pub density: f64,
    /// Poisson's ratio ν (0 to 0.5).
    pub poisson: f64,
}

impl Material {
    /// Steel: E = 200 GPa, ρ = 7860 kg/m³, ν = 0.3 (the lecture's gong).
    pub const STEEL: Material = Material {
        youngs_modulus: 2.0e11,
        density: 7860.0,
        poisson: 0.3,
    };
    /// Bell bronze (CuSn20): E = 104 GPa, ρ = 8600 kg/m³, ν = 0.34 (handbook values).
    pub const BRONZE: Material = Material {
        youngs_modulus: 1.04e11,
        density: 8600.0,
        poisson: 0.34,
    };
    /// Brass (CuZn37): E = 110 GPa, ρ = 8440 kg/m³, ν = 0.34.
    pub const BRASS: Material = Material {
        youngs_modulus: 1.1e11,
        density: 8440.0,
        poisson: 0.34,
    };
    /// Aluminium alloy: E = 70 GPa, ρ = 2700 kg/m³, ν = 0.33.
    pub const ALUMINIUM: Material = Material {
        youngs_modulus: 7.0e10,
        density: 2700.0,
        poisson: 0.33,
    };
}

impl Default for Material {
    /// The lecture's steel ([`Material::STEEL`]).
    fn default() -> Self {
        Self::STEEL
    }
}

/// Modal damping law.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(tag = "law", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Damping {
    /// No losses.
    #[default]
    None,
    /// `c_p = a ω_p^b + c0` in 1/s (the lecture's gong: a = 0.005, b = 0.6), acting as
    /// `c_p q̇_p` in the modal equations.
    Power {
        /// Coefficient a (≥ 0).
        a: f64,
        /// Exponent b (0 to 2).
        b: f64,
        /// Constant part c0 in 1/s (≥ 0).
        #[serde(default)]
        c0: f64,
    },
    /// Constant quality factor: `c_p = ω_p / Q`.
    Q {
        /// Quality factor Q (1 to 1e7).
        q: f64,
    },
    /// The same 60 dB decay time for every mode: `c_p = 2 ln(1000) / T60` (the energy of a
    /// mode decays as `e^{-c t}`, its amplitude as `e^{-c t/2}`).
    T60 {
        /// Decay time T60 in seconds (1e-3 to 1e4).
        seconds: f64,
    },
}

/// A point on the plate: `r` (fraction of the radius, 0 to 1) and `angle` (rad) on circular
/// plates; `x`, `y` (fractions of `lx`, `ly`, 0 to 1) on rectangles.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct Position {
    /// Radial position as a fraction of the radius (circular plates).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub r: Option<f64>,
    /// Angle in radians (circular plates; default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle: Option<f64>,
    /// Position along `lx` as a fraction (rectangles).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<f64>,
    /// Position along `ly` as a fraction (rectangles).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<f64>,
}

impl Position {
    /// Checks the coordinates fit `shape`; `field` is the dotted name used in errors.
    pub fn validate(&self, shape: PlateShape, field: &str) -> Result<(), ParamError> {
        if shape.is_circular() {
            if self.x.is_some() || self.y.is_some() {
                return Err(ParamError::new(
                    format!("{field}.x"),
                    "given",
                    "r and angle on circular plates",
                ));
            }
            let r = self.r.ok_or_else(|| {
                ParamError::new(format!("{field}.r"), "missing", "a number in [0, 1]")
            })?;
            check_closed(&format!("{field}.r"), r, 0.0, 1.0)?;
            check_closed(
                &format!("{field}.angle"),
                self.angle.unwrap_or(0.0),
                -1e3,
                1e3,
            )?;
        } else {
            if self.r.is_some() || self.angle.is_some() {
                return Err(ParamError::new(
                    format!("{field}.r"),
                    "given",
                    "x and y on rectangular plates",
                ));
            }
            for (name, v) in [("x", self.x), ("y", self.y)] {
                let v = v.ok_or_else(|| {
                    ParamError::new(format!("{field}.{name}"), "missing", "a number in [0, 1]")
                })?;
                check_closed(&format!("{field}.{name}"), v, 0.0, 1.0)?;
            }
        }
        Ok(())
    }
}

/// How the plate is set in motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum Excitation {
    /// Raised-cosine force pulse `F(t) = (F_max/2)(1 - cos(2πt/T))` for `0 ≤ t ≤ T`, applied at
    /// a point.
    Strike {
        /// Where.
        at: Position,
        /// Pulse length T in seconds (1e-5 to 0.1).
        duration: f64,
        /// Peak force F_max in newtons (0 to 1e6).
        peak_force: f64,
    },
    /// A Dirac impulse in time and space: velocity kick of `impulse / (ρh)` times the mode
    /// shapes at the point, at t = 0.
    Impulse {
        /// Where.
        at: Position,
        /// Impulse in N·s (0 to 1e3).
        impulse: f64,
    },
    /// A physical mallet (a lumped mass with a power-law felt, [`super::Mallet`]) launched
    /// against the plate at a point at t = 0; it may rebound and strike again by itself.
    /// `head` names a factory mallet ([`super::mallet_heads`]: `soft-felt`, `hard-felt`,
    /// `rubber`, `wood`, `metal`) whose mass and contact law fill the fields not given;
    /// without it `mass`, `stiffness` and `exponent` are required ([`Excitation::mallet_law`]).
    Mallet {
        /// Where.
        at: Position,
        /// A factory head (optional).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        head: Option<MalletHead>,
        /// Mallet mass M in kg (1e-4 to 10).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mass: Option<f64>,
        /// Felt stiffness K in N/m^α (1 to 1e13).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        stiffness: Option<f64>,
        /// Felt exponent α (1 to 4).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        exponent: Option<f64>,
        /// Launch speed in m/s (1e-3 to 50).
        speed: f64,
        /// Felt (Hunt-Crossley) loss λ in s/m (0 to 10; default the head's, else 0: a
        /// lossless felt).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        loss: Option<f64>,
    },
    /// Initial modal state: transverse mode `mode` (1-based, in frequency order) starts with
    /// displacement `displacement` and velocity `velocity` (modal coordinates: with normalised
    /// modes, `w = Φ q`, so `q` is in m·m).
    Initial {
        /// Mode index, 1 to N_Φ.
        mode: usize,
        /// Initial modal displacement q(0) (|q| ≤ 1).
        displacement: f64,
        /// Initial modal velocity q̇(0) (|q̇| ≤ 1e4 per second).
        #[serde(default)]
        velocity: f64,
    },
}

impl Excitation {
    /// A mallet excitation's mass and contact law: the fields given, the rest from its
    /// `head`. Errors name the field: a field missing without a head;
    /// `plate.excitation.kind` for an excitation that is not a mallet. (A head not in the
    /// factory list is refused when the scene is read, with the names allowed.)
    pub fn mallet_law(&self) -> Result<HeadLaw, ParamError> {
        let Excitation::Mallet {
            head,
            mass,
            stiffness,
            exponent,
            loss,
            ..
        } = self
        else {
            return Err(ParamError::new(
                "plate.excitation.kind",
                "not mallet",
                "mallet",
            ));
        };
        let base = head.map(MalletHead::law);
        let pick = |field: &str, given: Option<f64>, from: fn(&HeadLaw) -> f64| {
            given.or(base.as_ref().map(from)).ok_or_else(|| {
                ParamError::new(
                    format!("plate.excitation.{field}"),
                    "missing",
                    "a number, or a `head` to take it from",
                )
            })
        };
        Ok(HeadLaw {
            mass: pick("mass", *mass, |l| l.mass)?,
            stiffness: pick("stiffness", *stiffness, |l| l.stiffness)?,
            exponent: pick("exponent", *exponent, |l| l.exponent)?,
            loss: loss.or(base.map(|l| l.loss)).unwrap_or(0.0),
        })
    }
}

pub use crate::models::quantity::Quantity;

/// One output channel.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pickup {
    /// Where.
    pub at: Position,
    /// What it measures.
    #[serde(default)]
    pub quantity: Quantity,
}

/// The `[plate]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PlateSpec {
    /// Geometry and boundary conditions.
    pub shape: PlateShape,
    /// Radius a in m (circular plates; 0.01 to 10).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
    /// Side length along x in m (rectangles; 0.01 to 10).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lx: Option<f64>,
    /// Side length along y in m (rectangles; 0.01 to 10).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ly: Option<f64>,
    /// Thickness h in m (1e-5 to 0.1).
    pub thickness: f64,
    /// Material (default: the lecture's steel).
    #[serde(default)]
    pub material: Material,
    /// Number of transverse modes N_Φ (1 to 4000).
    pub n_phi: usize,
    /// Number of in-plane modes N_Ψ (0 to 4000; 0 makes the plate linear).
    pub n_psi: usize,
    /// Modal subspace of circular plates: `"full"` (default) or `"strike-mirror"` (only modes
    /// even about the strike's diameter; `n_phi` and `n_psi` then count those).
    #[serde(default)]
    pub symmetry: Symmetry,
    /// Simulation rate in Hz (1 000 to 4 000 000).
    pub sim_rate: f64,
    /// Time scheme.
    pub scheme: PlateScheme,
    /// The `sav` scheme's relaxation time constant in s (0 to 10; default
    /// [`crate::models::sav_relaxation::DEFAULT_TIME_CONSTANT`]): how fast the auxiliary
    /// variable is pulled back to its definition, with the energy it removes counted as
    /// dissipation ([`crate::models::sav_relaxation`]). 0: the plain SAV scheme (it drifts over
    /// repeated strikes). Ignored by the other schemes.
    #[serde(default = "default_sav_relaxation")]
    pub sav_relaxation: f64,
    /// The truncation closure's strength as a multiple of the calibrated one (0 to 40; default
    /// 0, the plain truncation): how strongly the top half-octave of modes is damped when a
    /// loud strike's cascade piles energy up there ([`super::closure`]; the unit of the
    /// engine's `closure` parameter, which the crash preset sets to 1). Its energy is counted as
    /// dissipation.
    #[serde(default)]
    pub closure: f64,
    /// The band above the simulation (default `false`): the plate's linear modes from the top
    /// of the basis up to 20 kHz (or 0.45 of `sim_rate`), sounding with exactly the energy the
    /// closure absorbs ([`super::extension`]; silent while the closure is off or idle). At
    /// most two pickups, both velocity. Its energy joins the report's terms (stored, and the closure's share
    /// of the dissipation moved to the band's own losses).
    #[serde(default)]
    pub band_above: bool,
    /// With `band_above` and a `kind = "mallet"` excitation: the mallet's contact feels the
    /// modes above the basis (their point resistance and static compliance, a spring and a
    /// dashpot in series with the plate), and the energy it gives them sounds in the band
    /// above (`plate.strike_above`; [`super::contact_residual`]). Default `false`.
    #[serde(default)]
    pub strike_above: bool,
    /// Storage of the coupling tensor's values: `"double"` (default, `f64`) or `"single"`
    /// (every value rounded to `f32` once; faster kernels, the energy still conserved to
    /// round-off; see [`crate::modal::TensorStorage`]).
    #[serde(default)]
    pub tensor_storage: TensorStorage,
    /// Losses.
    #[serde(default)]
    pub damping: Damping,
    /// Excitation.
    pub excitation: Excitation,
    /// The static rest shape (`plate.imperfection`): one part or an array of parts that add
    /// up (a spherical cap, a centre boss, a radial profile, a rectangle's dome, modal
    /// coefficients; [`super::rest_shape::ShapePart`]). Empty (default): a flat plate.
    #[serde(
        default,
        skip_serializing_if = "Vec::is_empty",
        deserialize_with = "super::rest_shape::one_or_many"
    )]
    pub imperfection: Vec<ShapePart>,
    /// Output channels (default: a stereo velocity pair at r = 0.896 a, angles 0.519 and
    /// -0.8 rad on circles; (0.31, 0.37) and (0.63, 0.71) on rectangles).
    #[serde(default)]
    pub pickups: Vec<Pickup>,
}

/// The default of [`PlateSpec::sav_relaxation`] (s).
pub fn default_sav_relaxation() -> f64 {
    crate::models::sav_relaxation::DEFAULT_TIME_CONSTANT
}

impl PlateSpec {
    /// Checks every field's range; errors name the dotted field (`plate.thickness`, ...).
    pub fn validate(&self) -> Result<(), ParamError> {
        if self.shape.is_circular() {
            let a = self.radius.ok_or_else(|| {
                ParamError::new(
                    "plate.radius",
                    "missing",
                    "0.01 to 10 m for circular plates",
                )
            })?;
            check_closed("plate.radius", a, 0.01, 10.0)?;
        } else {
            for (name, v) in [("plate.lx", self.lx), ("plate.ly", self.ly)] {
                let v = v.ok_or_else(|| {
                    ParamError::new(name, "missing", "0.01 to 10 m for rectangular plates")
                })?;
                PLATE_SIZE.check(name, v)?;
            }
        }
        PLATE_THICKNESS.check("plate.thickness", self.thickness)?;
        YOUNGS_MODULUS.check(
            "plate.material.youngs_modulus",
            self.material.youngs_modulus,
        )?;
        DENSITY.check("plate.material.density", self.material.density)?;
        POISSON.check("plate.material.poisson", self.material.poisson)?;
        for (field, n, r) in [
            ("plate.n_phi", self.n_phi, PLATE_MODES),
            ("plate.n_psi", self.n_psi, PLATE_IN_PLANE_MODES),
        ] {
            if !(r.min..=r.max).contains(&(n as f64)) {
                return Err(ParamError::new(field, n, format!("{} to {}", r.min, r.max)));
            }
        }
        PLATE_SIM_RATE.check("plate.sim_rate", self.sim_rate)?;
        crate::models::ranges::SAV_RELAXATION_TIME
            .check("plate.sav_relaxation", self.sav_relaxation)?;
        check_closed(
            "plate.closure",
            self.closure,
            0.0,
            super::closure::MAX_STRENGTH,
        )?;
        let pickups = self.effective_pickups();
        if self.band_above && pickups.len() > 2 {
            return Err(ParamError::new(
                "plate.band_above",
                "true",
                format!(
                    "false with {} pickups (the band above has two outputs)",
                    pickups.len()
                ),
            ));
        }
        if self.band_above && pickups.iter().any(|p| p.quantity != Quantity::Velocity) {
            return Err(ParamError::new(
                "plate.band_above",
                "true",
                "false with a displacement pickup (the band above sounds as velocity)",
            ));
        }
        if self.symmetry == Symmetry::StrikeMirror && !self.shape.is_circular() {
            return Err(ParamError::new(
                "plate.symmetry",
                "strike-mirror",
                "\"full\" for rectangular plates (\"strike-mirror\" is for circular ones)",
            ));
        }
        match self.damping {
            Damping::None => {}
            Damping::Power { a, b, c0 } => {
                DAMPING_A.check("plate.damping.a", a)?;
                DAMPING_B.check("plate.damping.b", b)?;
                DAMPING_C0.check("plate.damping.c0", c0)?;
            }
            Damping::Q { q } => {
                check_closed("plate.damping.q", q, 1.0, 1e7)?;
            }
            Damping::T60 { seconds } => {
                check_closed("plate.damping.seconds", seconds, 1e-3, 1e4)?;
            }
        }
        match self.excitation {
            Excitation::Strike {
                at,
                duration,
                peak_force,
            } => {
                at.validate(self.shape, "plate.excitation.at")?;
                STRIKE_DURATION.check("plate.excitation.duration", duration)?;
                STRIKE_FORCE.check("plate.excitation.peak_force", peak_force)?;
            }
            Excitation::Impulse { at, impulse } => {
                at.validate(self.shape, "plate.excitation.at")?;
                check_closed("plate.excitation.impulse", impulse, 0.0, 1e3)?;
            }
            Excitation::Mallet { at, speed, .. } => {
                at.validate(self.shape, "plate.excitation.at")?;
                let law = self.excitation.mallet_law()?;
                check_closed("plate.excitation.mass", law.mass, 1e-4, 10.0)?;
                check_closed("plate.excitation.stiffness", law.stiffness, 1.0, 1e13)?;
                check_closed("plate.excitation.exponent", law.exponent, 1.0, 4.0)?;
                check_closed("plate.excitation.speed", speed, 1e-3, 50.0)?;
                check_closed("plate.excitation.loss", law.loss, 0.0, 10.0)?;
            }
            Excitation::Initial {
                mode,
                displacement,
                velocity,
            } => {
                if !(1..=self.n_phi).contains(&mode) {
                    return Err(ParamError::new(
                        "plate.excitation.mode",
                        mode,
                        format!("1 to n_phi = {}", self.n_phi),
                    ));
                }
                check_closed("plate.excitation.displacement", displacement, -1.0, 1.0)?;
                check_closed("plate.excitation.velocity", velocity, -1e4, 1e4)?;
            }
        }
        validate_parts(
            &self.imperfection,
            self.shape,
            self.length_scale(),
            self.thickness,
            self.n_phi,
        )?;
        if self.pickups.len() > 64 {
            return Err(ParamError::new(
                "plate.pickups",
                self.pickups.len(),
                "0 to 64 pickups",
            ));
        }
        for (i, p) in self.pickups.iter().enumerate() {
            p.at.validate(self.shape, &format!("plate.pickups[{i}].at"))?;
        }
        Ok(())
    }

    /// The pickups to use: the scene's, or the default stereo pair.
    pub fn effective_pickups(&self) -> Vec<Pickup> {
        if !self.pickups.is_empty() {
            return self.pickups.clone();
        }
        let at = |a: (f64, f64)| {
            if self.shape.is_circular() {
                Position {
                    r: Some(a.0),
                    angle: Some(a.1),
                    ..Position::default()
                }
            } else {
                Position {
                    x: Some(a.0),
                    y: Some(a.1),
                    ..Position::default()
                }
            }
        };
        let pair = if self.shape.is_circular() {
            [(0.896, 0.519), (0.896, -0.8)]
        } else {
            [(0.31, 0.37), (0.63, 0.71)]
        };
        pair.iter()
            .map(|&p| Pickup {
                at: at(p),
                quantity: Quantity::Velocity,
            })
            .collect()
    }

    /// Flexural rigidity `D = E h³ / (12 (1 - ν²))` in N·m.
    pub fn rigidity(&self) -> f64 {
        let m = &self.material;
        flexural_rigidity(m.youngs_modulus, self.thickness, m.poisson)
    }

    /// The factor of the unit basis's `λ_s²` giving this plate's pulsations (rad/s):
    /// `√(D/ρh) / a²` ([`pulsation_scale`]).
    pub fn pulsation_scale(&self) -> f64 {
        pulsation_scale(self.rigidity(), self.surface_density(), self.length_scale())
    }

    /// Surface density `ρ h` in kg/m².
    pub fn surface_density(&self) -> f64 {
        self.material.density * self.thickness
    }

    /// Characteristic length: the radius, or `lx` for rectangles (m).
    pub fn length_scale(&self) -> f64 {
        if self.shape.is_circular() {
            self.radius.unwrap_or(1.0)
        } else {
            self.lx.unwrap_or(1.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names reports print are the ones scenes spell (serde), for every variant.
    #[test]
    fn report_names_are_the_scene_spellings() {
        for s in [Symmetry::Full, Symmetry::StrikeMirror] {
            assert_eq!(serde_json::to_value(s).unwrap(), s.name(), "{s:?}");
        }
        for s in [TensorStorage::Double, TensorStorage::Single] {
            assert_eq!(serde_json::to_value(s).unwrap(), s.name(), "{s:?}");
        }
        for s in [
            PlateScheme::ConservativeTheta1,
            PlateScheme::ConservativeExact,
            PlateScheme::StormerVerletExact,
            PlateScheme::SavExact,
        ] {
            assert_eq!(serde_json::to_value(s).unwrap(), s.name(), "{s:?}");
        }
    }
}
