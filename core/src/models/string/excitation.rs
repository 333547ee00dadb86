//! Excitations: the lecture's triangular pluck (initial condition) and a time-limited
//! raised-cosine force (for real-time plucks and strikes).
//!
//! Plain data validated on the control thread; the force's time profile is evaluated on the
//! audio thread (no allocation).

use super::params::StringParams;
use crate::error::{check_finite, check_positive, ParamError};
use std::f64::consts::PI;

/// Triangular initial displacement at rest (SEED.md 3.2, "plucked"):
/// `u0(x) = A x/x_p` for `x ≤ x_p`, `A (L - x)/(L - x_p)` beyond; zero velocity.
///
/// Read on the control or audio thread (`StiffString::pluck` does not allocate).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrianglePluck {
    /// Pluck position `x_p` in m (`0 < x_p < L`).
    pub position: f64,
    /// Peak displacement `A` in m (finite).
    pub amplitude: f64,
}

impl TrianglePluck {
    /// Checks the position and amplitude against the string `p`.
    pub fn validate(&self, p: &StringParams) -> Result<(), ParamError> {
        p.check_position("pluck.position", self.position)?;
        check_finite("pluck.amplitude", self.amplitude)?;
        Ok(())
    }

    /// Displacement `u0(x)` in m.
    pub fn displacement(&self, length: f64, x: f64) -> f64 {
        if x <= self.position {
            self.amplitude * x / self.position
        } else {
            self.amplitude * (length - x) / (length - self.position)
        }
    }
}

/// Raised-cosine point force `F(t) = F_peak · ½(1 - cos(2πt/T_d))` for `0 ≤ t ≤ T_d`, zero
/// otherwise, applied at `position` (Bilbao, Numerical Sound Synthesis 2009, §7.1.5 uses the
/// same pulse for strikes). Its modal projection is exact: `F_j(t) = F(t) φ_j(x_e)`.
///
/// Read on the audio thread each step while active.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrikeForce {
    /// Application point `x_e` in m (`0 < x_e < L`).
    pub position: f64,
    /// Duration `T_d` in s (> 0); a pluck is typically 1-10 ms, a strike 0.5-2 ms.
    pub duration: f64,
    /// Peak force `F_peak` in N (finite, any sign; positive pushes towards `+u`).
    pub peak: f64,
}

impl StrikeForce {
    /// Checks every field against the string `p`.
    pub fn validate(&self, p: &StringParams) -> Result<(), ParamError> {
        p.check_position("strike.position", self.position)?;
        check_positive("strike.duration", self.duration)?;
        check_finite("strike.peak", self.peak)?;
        Ok(())
    }

    /// Force in N at time `t` (s) after the onset.
    pub fn force(&self, t: f64) -> f64 {
        if (0.0..=self.duration).contains(&t) {
            0.5 * self.peak * (1.0 - (2.0 * PI * t / self.duration).cos())
        } else {
            0.0
        }
    }
}
