//! The range checks of a scene's `[string]` table ([`StringSpec::validate`]): every field's
//! range, then the model's own checks of the grid and the obstacle. Errors name the dotted
//! field. Runs on the thread that loads the scene.

use super::{StringExcitation, StringLosses, StringObstacle, StringOutput, StringSpec, MAX_MODES};
use crate::error::{check_closed, check_non_negative, ParamError};
use crate::models::ranges::{
    BRIDGE_CURVATURE, CONTACT_EXPONENT, CONTACT_STIFFNESS, PLUCK_AMPLITUDE, STRING_INHARMONICITY,
    STRING_LENGTH, STRING_LINEAR_DENSITY, STRING_SIM_RATE, STRING_TENSION,
};

/// Prefixes a model error's field with `string.` so it names the scene's dotted path.
fn scoped(mut e: ParamError) -> ParamError {
    e.field = format!("string.{}", e.field);
    e
}

impl StringSpec {
    /// Checks every field's range; errors name the dotted field (`string.tension`, ...).
    pub fn validate(&self) -> Result<(), ParamError> {
        let l = STRING_LENGTH.check("string.length", self.length)?;
        check_closed("string.diameter", self.diameter, 0.0, 0.1)?;
        STRING_TENSION.check("string.tension", self.tension)?;
        crate::models::ranges::SAV_RELAXATION_TIME
            .check("string.sav_relaxation", self.sav_relaxation)?;
        STRING_LINEAR_DENSITY.check("string.linear_density", self.linear_density)?;
        match (self.inharmonicity, self.bending_stiffness) {
            (Some(b), None) => {
                STRING_INHARMONICITY.check("string.inharmonicity", b)?;
            }
            (None, Some(ei)) => {
                check_closed("string.bending_stiffness", ei, 0.0, 1e6)?;
            }
            (Some(_), Some(_)) => {
                return Err(ParamError::new(
                    "string.bending_stiffness",
                    "given with string.inharmonicity",
                    "exactly one of inharmonicity (B) and bending_stiffness (EI)",
                ))
            }
            (None, None) => {
                return Err(ParamError::new(
                    "string.inharmonicity",
                    "missing",
                    "exactly one of inharmonicity (B, 0 to 1) and bending_stiffness (EI)",
                ))
            }
        }
        if !(1..=MAX_MODES).contains(&self.modes) {
            return Err(ParamError::new(
                "string.modes",
                self.modes,
                format!("1 to {MAX_MODES}"),
            ));
        }
        STRING_SIM_RATE.check("string.sim_rate", self.sim_rate)?;
        let inside = |field: &str, x: f64| {
            if x.is_finite() && x > 0.0 && x < l {
                Ok(())
            } else {
                Err(ParamError::new(
                    field,
                    x,
                    format!("position in (0, {l}) m, inside the string"),
                ))
            }
        };
        match &self.losses {
            StringLosses::None => {}
            StringLosses::Valette {
                air_viscosity,
                air_density,
                viscoelastic_delta,
                thermoelastic_q_inv,
            } => {
                check_closed("string.losses.air_viscosity", *air_viscosity, 0.0, 1.0)?;
                check_closed("string.losses.air_density", *air_density, 0.0, 100.0)?;
                check_closed(
                    "string.losses.viscoelastic_delta",
                    *viscoelastic_delta,
                    0.0,
                    1.0,
                )?;
                check_closed(
                    "string.losses.thermoelastic_q_inv",
                    *thermoelastic_q_inv,
                    0.0,
                    1.0,
                )?;
            }
            StringLosses::Power { a, b, c0 } => {
                check_non_negative("string.losses.a", *a)?;
                check_closed("string.losses.b", *b, 0.0, 2.0)?;
                check_non_negative("string.losses.c0", *c0)?;
            }
            StringLosses::PerMode { sigma } => {
                if sigma.len() != self.modes {
                    return Err(ParamError::new(
                        "string.losses.sigma",
                        format!("{} values", sigma.len()),
                        format!("exactly string.modes = {} values", self.modes),
                    ));
                }
                for (j, &s) in sigma.iter().enumerate() {
                    check_closed(&format!("string.losses.sigma[{j}]"), s, 0.0, 1e6)?;
                }
            }
        }
        match &self.obstacle {
            StringObstacle::None => {}
            StringObstacle::Sitar {
                position,
                curvature,
                height,
                extent,
            } => {
                check_closed("string.obstacle.position", *position, 0.0, l)?;
                BRIDGE_CURVATURE.check("string.obstacle.curvature", *curvature)?;
                check_closed("string.obstacle.height", *height, -0.1, 0.1)?;
                inside("string.obstacle.extent", *extent)?;
            }
            StringObstacle::Point {
                position,
                height,
                width,
            } => {
                inside("string.obstacle.position", *position)?;
                check_closed("string.obstacle.height", *height, -0.1, 0.1)?;
                check_closed("string.obstacle.width", *width, 0.0, l)?;
            }
            StringObstacle::Fretboard { distance } => {
                check_closed("string.obstacle.distance", *distance, 0.0, 0.1)?;
            }
            StringObstacle::Points { points } => {
                if points.is_empty() || points.len() > 10_000 {
                    return Err(ParamError::new(
                        "string.obstacle.points",
                        format!("{} points", points.len()),
                        "1 to 10000 points",
                    ));
                }
                for (n, p) in points.iter().enumerate() {
                    inside(&format!("string.obstacle.points[{n}][0]"), p[0])?;
                    check_closed(&format!("string.obstacle.points[{n}][1]"), p[1], -0.1, 0.1)?;
                }
            }
        }
        CONTACT_STIFFNESS.check("string.contact.stiffness", self.contact.stiffness)?;
        CONTACT_EXPONENT.check("string.contact.exponent", self.contact.exponent)?;
        self.scheme()?;
        match self.excitation {
            StringExcitation::Pluck {
                position,
                amplitude,
            } => {
                inside("string.excitation.position", position)?;
                PLUCK_AMPLITUDE.check("string.excitation.amplitude", amplitude)?;
            }
            StringExcitation::Strike {
                position,
                duration,
                peak_force,
            } => {
                inside("string.excitation.position", position)?;
                check_closed("string.excitation.duration", duration, 1e-6, 0.1)?;
                check_closed("string.excitation.peak_force", peak_force, -1e4, 1e4)?;
            }
        }
        if self.outputs.len() > 64 {
            return Err(ParamError::new(
                "string.outputs",
                format!("{} outputs", self.outputs.len()),
                "0 to 64 outputs",
            ));
        }
        for (i, o) in self.outputs.iter().enumerate() {
            if let StringOutput::Pickup { position, .. } = o {
                inside(&format!("string.outputs[{i}].position"), *position)?;
            }
        }
        if self.snapshots.len() > 16 {
            return Err(ParamError::new(
                "string.snapshots",
                format!("{} instants", self.snapshots.len()),
                "0 to 16 instants",
            ));
        }
        for (i, &t) in self.snapshots.iter().enumerate() {
            check_closed(&format!("string.snapshots[{i}]"), t, 0.0, 600.0)?;
        }
        // The model's own checks (grid sampling of the obstacle, derived frequencies).
        let config = self.config();
        config.params.validate().map_err(scoped)?;
        config.obstacle.sample(&config.params).map_err(scoped)?;
        Ok(())
    }
}
