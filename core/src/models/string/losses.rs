//! Per-mode damping `σ_j` (s⁻¹) of the string.
//!
//! The physical model is the one Issanchou et al. (JSV 2017, section 2, after Valette and
//! Cuesta) fit to their measurements (SEED.md, "Facts from the cited papers"):
//! `σ_j = π f_j Q_j⁻¹`, `Q_j⁻¹ = Q_air⁻¹ + Q_ve⁻¹ + Q_te⁻¹` with
//! `Q_air⁻¹ = R / (2π μ f_j)`, `R = 2π η_air + 2π d √(π η_air ρ_air f_j)`,
//! `Q_ve⁻¹ = 4π² μ EI δ_ve f_j² / T²` and a constant `Q_te⁻¹`, where `f_j = ω_j / 2π` is the
//! lossless modal frequency.
//!
//! Built on a control thread; the model turns the `σ_j` into scheme coefficients at build time.

use super::params::StringParams;
use crate::error::{check_non_negative, ParamError};
use std::f64::consts::PI;

/// Coefficients of the air / viscoelastic / thermoelastic loss model.
///
/// Read on the control thread at build time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ValetteLosses {
    /// Dynamic viscosity of air `η_air` in Pa·s (≥ 0).
    pub air_viscosity: f64,
    /// Density of air `ρ_air` in kg/m³ (≥ 0).
    pub air_density: f64,
    /// Viscoelastic loss angle `δ_ve` (dimensionless, ≥ 0).
    pub viscoelastic_delta: f64,
    /// Thermoelastic inverse quality factor `Q_te⁻¹` (dimensionless, ≥ 0).
    pub thermoelastic_q_inv: f64,
}

impl Default for ValetteLosses {
    /// The values of Issanchou et al. 2017: η_air = 1.8e-5, ρ_air = 1.2, δ_ve = 4.5e-3,
    /// Q_te⁻¹ = 2.03e-4.
    fn default() -> Self {
        Self {
            air_viscosity: 1.8e-5,
            air_density: 1.2,
            viscoelastic_delta: 4.5e-3,
            thermoelastic_q_inv: 2.03e-4,
        }
    }
}

/// Which damping the modes get.
///
/// Read on the control thread at build time.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Losses {
    /// No damping (`σ_j = 0`): the scheme conserves its discrete energy exactly.
    #[default]
    None,
    /// The air / viscoelastic / thermoelastic model of [`ValetteLosses`].
    Valette(ValetteLosses),
    /// Given `σ_j` in s⁻¹ for `j = 1..=N_m` (length must be `N - 1`, each finite and ≥ 0).
    PerMode(Vec<f64>),
}

impl ValetteLosses {
    /// Checks every coefficient.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_non_negative("losses.air_viscosity", self.air_viscosity)?;
        check_non_negative("losses.air_density", self.air_density)?;
        check_non_negative("losses.viscoelastic_delta", self.viscoelastic_delta)?;
        check_non_negative("losses.thermoelastic_q_inv", self.thermoelastic_q_inv)?;
        Ok(())
    }

    /// Inverse quality factor `Q⁻¹` at frequency `f` (Hz) for the string `p`.
    pub fn q_inv(&self, p: &StringParams, f: f64) -> f64 {
        let r = 2.0 * PI * self.air_viscosity
            + 2.0 * PI * p.diameter * (PI * self.air_viscosity * self.air_density * f).sqrt();
        let q_air = r / (2.0 * PI * p.linear_density * f);
        let q_ve = 4.0
            * PI
            * PI
            * p.linear_density
            * p.bending_stiffness()
            * self.viscoelastic_delta
            * f
            * f
            / (p.tension * p.tension);
        q_air + q_ve + self.thermoelastic_q_inv
    }

    /// Damping `σ = π f Q⁻¹` in s⁻¹ at frequency `f` (Hz).
    pub fn sigma(&self, p: &StringParams, f: f64) -> f64 {
        PI * f * self.q_inv(p, f)
    }
}

impl Losses {
    /// Writes `σ_j` (s⁻¹) for `j = 1..=N_m` into `out[j - 1]` (`out.len() == N - 1`), after
    /// validating the loss description against `p`.
    pub fn sigmas(&self, p: &StringParams, out: &mut [f64]) -> Result<(), ParamError> {
        debug_assert_eq!(out.len(), p.modes());
        match self {
            Losses::None => out.fill(0.0),
            Losses::Valette(v) => {
                v.validate()?;
                for (j, s) in out.iter_mut().enumerate() {
                    let f = p.omega(j + 1) / (2.0 * PI);
                    *s = v.sigma(p, f);
                }
            }
            Losses::PerMode(given) => {
                if given.len() != out.len() {
                    return Err(ParamError::new(
                        "losses.sigma.len",
                        given.len(),
                        format!("exactly N - 1 = {} values", out.len()),
                    ));
                }
                for (j, (&g, s)) in given.iter().zip(out.iter_mut()).enumerate() {
                    *s = check_non_negative(&format!("losses.sigma[{}]", j + 1), g)?;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fundamental_decay_is_a_few_seconds() {
        // Issanchou's string: T60 of the fundamental is several seconds (σ_1 of order 1 s⁻¹),
        // high partials decay faster (viscoelastic term grows like f²).
        let p = StringParams::lecture_guitar(100, 48_000.0);
        let mut s = vec![0.0; 99];
        Losses::Valette(ValetteLosses::default())
            .sigmas(&p, &mut s)
            .unwrap();
        assert!(s[0] > 0.2 && s[0] < 3.0, "{}", s[0]);
        assert!(s[50] > 10.0 * s[0], "{} {}", s[50], s[0]);
    }
}
