//! The one table of parameter ranges: for each physical quantity a model takes, the range its
//! specification accepts (scenes, presets, the CLI) and, inside it, the narrower range the
//! instrument offers as a control (the engine's parameter table reads it from here).
//!
//! Why two ranges: a scene may model a 10 m plate or a 1 MN string for a study, while the
//! instrument's knobs cover what plays in real time and sounds like an instrument; both come
//! from this table, so they cannot drift apart. Every check names the field, the value and the
//! range ([`ParamError`]). Static data, read by any thread.

use crate::error::{check_closed, check_non_negative, ParamError};

/// The allowed values of one quantity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Range {
    /// Smallest value a specification accepts (in `unit`).
    pub min: f64,
    /// Largest value a specification accepts (in `unit`; `f64::MAX` for "no upper bound").
    pub max: f64,
    /// Smallest value of the instrument's control (`min ≤ play_min`).
    pub play_min: f64,
    /// Largest value of the instrument's control (`play_max ≤ max`).
    pub play_max: f64,
    /// Unit (SI; empty for dimensionless quantities).
    pub unit: &'static str,
}

impl Range {
    /// A range whose instrument control covers all of it.
    pub const fn new(min: f64, max: f64, unit: &'static str) -> Self {
        Self {
            min,
            max,
            play_min: min,
            play_max: max,
            unit,
        }
    }

    /// The same range with the instrument's control limited to `[lo, hi]`.
    pub const fn playable(self, lo: f64, hi: f64) -> Self {
        Self {
            play_min: lo,
            play_max: hi,
            ..self
        }
    }

    /// `value` if it is finite and in `[min, max]`, else an error naming `field`, the value and
    /// the range.
    pub fn check(&self, field: &str, value: f64) -> Result<f64, ParamError> {
        if self.min == 0.0 && self.max == f64::MAX {
            check_non_negative(field, value)
        } else {
            check_closed(field, value, self.min, self.max)
        }
    }
}

// ---------------------------------------------------------------- plates

/// Plate radius `a` (circular) or side `lx`, `ly` (rectangle).
pub const PLATE_SIZE: Range = Range::new(0.01, 10.0, "m").playable(0.05, 3.0);
/// Rectangle aspect `ly / lx` (implied by the sides' range; the instrument's control is the
/// ratio itself).
pub const PLATE_ASPECT: Range = Range::new(1e-3, 1e3, "").playable(0.2, 5.0);
/// Plate thickness `h`.
pub const PLATE_THICKNESS: Range = Range::new(1e-5, 0.1, "m").playable(1e-4, 1e-2);
/// Young's modulus `E`.
pub const YOUNGS_MODULUS: Range = Range::new(1e6, 1e13, "Pa").playable(1e9, 5e11);
/// Density `ρ`.
pub const DENSITY: Range = Range::new(10.0, 1e5, "kg/m^3").playable(500.0, 25_000.0);
/// Poisson's ratio `ν` (the instrument keeps away from the incompressible limit).
pub const POISSON: Range = Range::new(0.0, 0.5, "").playable(0.1, 0.45);
/// Exponent `b` of the damping law `c = a ω^b + c0`.
pub const DAMPING_B: Range = Range::new(0.0, 2.0, "");
/// Coefficient `a` of the damping law (s^(b-1)).
pub const DAMPING_A: Range = Range::new(0.0, f64::MAX, "s^(b-1)").playable(0.0, 1.0);
/// Constant `c0` of the damping law (1/s).
pub const DAMPING_C0: Range = Range::new(0.0, f64::MAX, "1/s").playable(0.0, 100.0);
/// Duration of a raised-cosine strike.
pub const STRIKE_DURATION: Range = Range::new(1e-5, 0.1, "s").playable(1e-4, 0.05);
/// Peak force of a plate strike (at velocity 1 on the instrument).
pub const STRIKE_FORCE: Range = Range::new(0.0, 1e6, "N").playable(0.01, 1000.0);
/// Transverse modes `N_Φ`.
pub const PLATE_MODES: Range = Range::new(1.0, 4000.0, "").playable(4.0, 2000.0);
/// In-plane modes `N_Ψ` (0: linear plate).
pub const PLATE_IN_PLANE_MODES: Range = Range::new(0.0, 4000.0, "").playable(0.0, 200.0);
/// The instrument's plate band limit: the highest transverse mode frequency a note keeps.
pub const PLATE_BAND_LIMIT: Range = Range::new(500.0, 20_000.0, "Hz").playable(500.0, 20_000.0);
/// A plate's simulation rate.
/// Time constant of the SAV scheme's relaxation of `ψ` toward `√(2U(q))`
/// (`plate.sav_relaxation`, [`crate::models::sav_relaxation`]); 0 switches it off.
pub const SAV_RELAXATION_TIME: Range = Range::new(0.0, 10.0, "s");
pub const PLATE_SIM_RATE: Range = Range::new(1e3, 4e6, "Hz").playable(8000.0, 400_000.0);

// ---------------------------------------------------------------- strings

/// String length.
pub const STRING_LENGTH: Range = Range::new(0.01, 100.0, "m").playable(0.05, 3.0);
/// String tension `T` (at the root key on the instrument).
pub const STRING_TENSION: Range = Range::new(1e-3, 1e6, "N").playable(1.0, 2000.0);
/// String linear mass density `μ`.
pub const STRING_LINEAR_DENSITY: Range = Range::new(1e-6, 100.0, "kg/m").playable(1e-4, 0.05);
/// Inharmonicity `B = π² EI / (T L²)`.
pub const STRING_INHARMONICITY: Range = Range::new(0.0, 1.0, "").playable(0.0, 1e-3);
/// A string's simulation rate.
pub const STRING_SIM_RATE: Range = Range::new(1e3, 1e7, "Hz").playable(8000.0, 400_000.0);
/// Contact stiffness `K` of the penalty law `K [η]_+^α` (N/m^α per unit length).
pub const CONTACT_STIFFNESS: Range = Range::new(1.0, 1e18, "N/m^(alpha+1)").playable(1e3, 1e16);
/// Contact exponent `α`.
pub const CONTACT_EXPONENT: Range = Range::new(1.0, 10.0, "").playable(1.0, 4.0);
/// Signed pluck apex displacement (the instrument's control is its magnitude).
pub const PLUCK_AMPLITUDE: Range = Range::new(-0.05, 0.05, "m").playable(1e-5, 5e-3);
/// Curvature `a` of a sitar bridge `g(x) = -a x²` (the instrument offers convex bridges only).
pub const BRIDGE_CURVATURE: Range = Range::new(-1e4, 1e4, "1/m").playable(0.0, 50.0);

#[cfg(test)]
mod tests {
    use super::*;

    const ALL: &[(&str, Range)] = &[
        ("PLATE_SIZE", PLATE_SIZE),
        ("PLATE_ASPECT", PLATE_ASPECT),
        ("PLATE_THICKNESS", PLATE_THICKNESS),
        ("YOUNGS_MODULUS", YOUNGS_MODULUS),
        ("DENSITY", DENSITY),
        ("POISSON", POISSON),
        ("DAMPING_B", DAMPING_B),
        ("DAMPING_A", DAMPING_A),
        ("DAMPING_C0", DAMPING_C0),
        ("STRIKE_DURATION", STRIKE_DURATION),
        ("STRIKE_FORCE", STRIKE_FORCE),
        ("PLATE_MODES", PLATE_MODES),
        ("PLATE_IN_PLANE_MODES", PLATE_IN_PLANE_MODES),
        ("PLATE_SIM_RATE", PLATE_SIM_RATE),
        ("SAV_RELAXATION_TIME", SAV_RELAXATION_TIME),
        ("PLATE_BAND_LIMIT", PLATE_BAND_LIMIT),
        ("STRING_LENGTH", STRING_LENGTH),
        ("STRING_TENSION", STRING_TENSION),
        ("STRING_LINEAR_DENSITY", STRING_LINEAR_DENSITY),
        ("STRING_INHARMONICITY", STRING_INHARMONICITY),
        ("STRING_SIM_RATE", STRING_SIM_RATE),
        ("CONTACT_STIFFNESS", CONTACT_STIFFNESS),
        ("CONTACT_EXPONENT", CONTACT_EXPONENT),
        ("PLUCK_AMPLITUDE", PLUCK_AMPLITUDE),
        ("BRIDGE_CURVATURE", BRIDGE_CURVATURE),
    ];

    /// The instrument's range lies inside the specification's, for every quantity.
    #[test]
    fn playable_ranges_nest_in_the_model_ranges() {
        for (name, r) in ALL {
            assert!(r.min <= r.max, "{name}");
            assert!(
                r.min <= r.play_min && r.play_min <= r.play_max && r.play_max <= r.max,
                "{name}: playable [{}, {}] outside [{}, {}]",
                r.play_min,
                r.play_max,
                r.min,
                r.max
            );
        }
    }

    #[test]
    fn check_names_field_value_and_range() {
        let e = STRING_TENSION.check("string.tension", 2e6).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("string.tension") && text.contains("2000000"),
            "{text}"
        );
        assert!(STRING_TENSION.check("string.tension", f64::NAN).is_err());
        assert_eq!(
            STRING_TENSION.check("string.tension", 180.5).unwrap(),
            180.5
        );
    }
}
