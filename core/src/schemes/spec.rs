//! Naming and building one-oscillator schemes from plain parameters (CLI, scene files, tests).

use super::duffing::{DuffingConservative, DuffingVerlet};
use super::exact::ExactScheme;
use super::impact::ImpactScheme;
use super::linear::ThetaScheme;
use super::OscillatorStepper;
use crate::error::ParamError;
use serde::{Deserialize, Serialize};

/// Which one-oscillator scheme to run, with its physical and numerical parameters.
///
/// Angular frequencies in rad per time unit; `h` is given separately to [`build_oscillator`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "scheme", rename_all = "kebab-case", deny_unknown_fields)]
pub enum OscillatorSpec {
    /// θ-family for `ü + ω0² u = 0` (SEED.md 1.1), any θ in [0, 1].
    Theta {
        /// Natural angular frequency ω0 (> 0).
        omega0: f64,
        /// θ in [0, 1]: 1 explicit, 0 unconditionally stable, ½ the stability boundary.
        theta: f64,
    },
    /// Exact scheme for `ü + 2ξω0 u̇ + ω0² u = 0` (SEED.md 1.2), any ξ ≥ 0.
    Exact {
        /// Natural angular frequency ω0 (> 0).
        omega0: f64,
        /// Damping ratio ξ (≥ 0; 1 is critical).
        xi: f64,
    },
    /// Störmer-Verlet for Duffing `ü + ω0² u + γ u³ = 0` (SEED.md 1.3); not energy conserving.
    DuffingVerlet {
        /// Linear angular frequency ω0 (> 0).
        omega0: f64,
        /// Cubic coefficient γ (≥ 0, hardening).
        gamma: f64,
    },
    /// Conservative (θ1, θ2) family for Duffing (SEED.md 1.3).
    DuffingConservative {
        /// Linear angular frequency ω0 (> 0).
        omega0: f64,
        /// Cubic coefficient γ (≥ 0).
        gamma: f64,
        /// θ1 in [0, 1], weight of the linear term as in the θ-family.
        theta1: f64,
        /// θ2 in [0, 1]: 1 explicit, otherwise a cubic in `u_{n+1}` is solved each step.
        theta2: f64,
    },
    /// Impact oscillator `m ü + k u = -K [u - d]_+^α` with the discrete-gradient force (SEED.md 1.4).
    Impact {
        /// Mass m (> 0).
        mass: f64,
        /// Linear spring stiffness k (≥ 0).
        stiffness: f64,
        /// Contact stiffness K (> 0).
        contact_stiffness: f64,
        /// Contact exponent α in [1, 4].
        alpha: f64,
        /// Distance d from rest to the wall (any sign; negative means pre-penetration).
        gap: f64,
        /// θ of the linear part, in [0, 1].
        theta: f64,
    },
}

impl OscillatorSpec {
    /// The scheme identifier used on the command line (`theta`, `exact`, `duffing-verlet`, ...).
    pub fn scheme_name(&self) -> &'static str {
        match self {
            Self::Theta { .. } => "theta",
            Self::Exact { .. } => "exact",
            Self::DuffingVerlet { .. } => "duffing-verlet",
            Self::DuffingConservative { .. } => "duffing-conservative",
            Self::Impact { .. } => "impact",
        }
    }
}

/// Builds the stepper described by `spec` with time step `h`, validating every parameter.
pub fn build_oscillator(
    spec: &OscillatorSpec,
    h: f64,
) -> Result<Box<dyn OscillatorStepper>, ParamError> {
    Ok(match *spec {
        OscillatorSpec::Theta { omega0, theta } => Box::new(ThetaScheme::new(omega0, theta, h)?),
        OscillatorSpec::Exact { omega0, xi } => Box::new(ExactScheme::new(omega0, xi, h)?),
        OscillatorSpec::DuffingVerlet { omega0, gamma } => {
            Box::new(DuffingVerlet::new(omega0, gamma, h)?)
        }
        OscillatorSpec::DuffingConservative {
            omega0,
            gamma,
            theta1,
            theta2,
        } => Box::new(DuffingConservative::new(omega0, gamma, theta1, theta2, h)?),
        OscillatorSpec::Impact {
            mass,
            stiffness,
            contact_stiffness,
            alpha,
            gap,
            theta,
        } => Box::new(ImpactScheme::new(
            mass,
            stiffness,
            contact_stiffness,
            alpha,
            gap,
            theta,
            h,
        )?),
    })
}
