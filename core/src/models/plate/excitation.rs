//! Losses, excitation signals and pickups of the modal plate.
//!
//! - Losses: modal damping `c_s q̇_s` (1/s), from the power law of Ducceschi & Touzé (JSV 2015,
//!   SEED 3.1: `c_p = 0.005 ω_p^0.6` for the gong) or from decay times T60.
//! - Forcing: the model receives per-mode weights `Φ_s(x₀)` (1/m, the transverse modes at the
//!   strike point, position handled by the caller) and a scalar force `F(t)` (N); the modal
//!   forcing is `p_s = Φ_s(x₀) F / ρh`. Signals: [`RaisedCosine`] strikes and one-step impulses
//!   ([`impulse_force`]).
//! - Outputs: [`PickupWeights`]s, each a weight vector `Φ_s(x_out)` and a [`PickupKind`].
//!
//! Threads: helpers run on a worker thread when building; [`RaisedCosine::force`] and
//! [`impulse_force`] are cheap, non-allocating and may be called on the audio thread.

use std::f64::consts::{LN_10, PI};

use crate::error::{check_finite, check_non_negative, check_positive, ParamError};

/// Modal damping from the power law `c_p = a ω_p^b + c0` (1/s), for each `ω_p` (rad/s).
///
/// The gong of SEED 3.1 uses `a = 0.005`, `b = 0.6`, `c0 = 0`. Errors: `a`, `c0` finite ≥ 0,
/// `b` finite, every `ω_p` finite > 0. Runs on a worker thread (allocates the result).
pub fn damping_law(omega: &[f64], a: f64, b: f64, c0: f64) -> Result<Vec<f64>, ParamError> {
    check_non_negative("damping.a", a)?;
    check_finite("damping.b", b)?;
    check_non_negative("damping.c0", c0)?;
    omega
        .iter()
        .enumerate()
        .map(|(p, &w)| {
            check_positive(&format!("omega[{p}]"), w)?;
            Ok(a * w.powf(b) + c0)
        })
        .collect()
}

/// Damping coefficient `c` (1/s) of `q̈ + c q̇ + ω² q = 0` whose amplitude decays by 60 dB in
/// `t60` seconds: the envelope is `e^{-c t/2}`, so `c = 2 ln(1000) / t60 = 6 ln(10) / t60`
/// (under-damped modes). Errors: `t60` finite > 0.
pub fn t60_to_damping(t60: f64) -> Result<f64, ParamError> {
    let t = check_positive("t60", t60)?;
    Ok(6.0 * LN_10 / t)
}

/// Inverse of [`t60_to_damping`]: the 60 dB decay time (s) of damping `c` (1/s); infinite for
/// `c = 0`. Errors: `c` finite ≥ 0.
pub fn damping_to_t60(c: f64) -> Result<f64, ParamError> {
    let c = check_non_negative("damping", c)?;
    Ok(if c == 0.0 {
        f64::INFINITY
    } else {
        6.0 * LN_10 / c
    })
}

/// A raised-cosine strike `F(t) = (F_max/2) (1 - cos(2π t / T))` for `0 ≤ t ≤ T`, 0 elsewhere
/// (Ducceschi & Touzé 2015, section 4; the lecture's gong uses `F_max` = 40 N and 80 N).
///
/// Built on a worker thread; [`Self::force`] may be called on the audio thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RaisedCosine {
    /// Contact duration `T` (s), > 0.
    pub duration: f64,
    /// Peak force `F_max` (N), finite (sign gives the direction).
    pub peak: f64,
}

impl RaisedCosine {
    /// Validated constructor. Errors: `duration` finite > 0, `peak` finite.
    pub fn new(duration: f64, peak: f64) -> Result<Self, ParamError> {
        Ok(Self {
            duration: check_positive("strike.duration", duration)?,
            peak: check_finite("strike.peak", peak)?,
        })
    }

    /// Force (N) at time `t` (s) after the strike start.
    pub fn force(&self, t: f64) -> f64 {
        if (0.0..=self.duration).contains(&t) {
            0.5 * self.peak * (1.0 - (2.0 * PI * t / self.duration).cos())
        } else {
            0.0
        }
    }

    /// Total impulse `∫F dt = F_max T / 2` (N s).
    pub fn impulse(&self) -> f64 {
        0.5 * self.peak * self.duration
    }
}

/// The one-step force (N) that delivers an impulse `impulse` (N s) at sampling rate `fs` (Hz):
/// `F = impulse · fs`, applied during one step only. In the scheme
/// `δ_tt q_s + … = Φ_s F(n) / ρh`, a force applied at step `n` alone changes `δ_{t-} q_s` by
/// `h Φ_s F / ρh = Φ_s impulse / ρh`: a Dirac impulse in velocity.
pub fn impulse_force(impulse: f64, fs: f64) -> f64 {
    impulse * fs
}

/// What a [`PickupWeights`] reads (plain `Copy` data; set at build time, read on the audio thread).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PickupKind {
    /// Displacement `w(x, n+1) = Σ_s Φ_s q_s(n+1)` (m with normalised modes) after the step
    /// that computed `q(n+1)`.
    Displacement,
    /// Centred velocity `Σ_s Φ_s δ_{t.} q_s(n) = Σ_s Φ_s (q_s(n+1) - q_s(n-1)) / 2h` (m/s): the
    /// velocity of the energy balance, but at time `n`, one sample behind the displacement.
    VelocityCentred,
    /// Backward velocity `Σ_s Φ_s δ_{t-} q_s(n+1) = Σ_s Φ_s (q_s(n+1) - q_s(n)) / h` (m/s): the
    /// velocity of the kinetic energy, located at `n + 1/2`.
    VelocityBackward,
}

/// One output point resolved for a model: weights `Φ_s(x_out)` (1/m with normalised modes), one
/// per transverse mode, and what to read there (a scene's `[[pickups]]` entry,
/// [`super::spec::Pickup`], is where it is and what it measures).
///
/// Built on a worker thread and moved into the model.
#[derive(Debug, Clone, PartialEq)]
pub struct PickupWeights {
    /// Mode shapes at the pickup point, `Φ_s(x_out)` (1/m), length `N_Φ`.
    pub weights: Vec<f64>,
    /// Displacement or velocity.
    pub kind: PickupKind,
}

impl PickupWeights {
    /// Validated constructor: every weight finite (the length is checked by the model).
    pub fn new(weights: Vec<f64>, kind: PickupKind) -> Result<Self, ParamError> {
        for (s, &w) in weights.iter().enumerate() {
            check_finite(&format!("pickup.weights[{s}]"), w)?;
        }
        Ok(Self { weights, kind })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn law_t60_and_strike() {
        let c = damping_law(&[1.0, 1000.0], 0.005, 0.6, 0.1).unwrap();
        assert!((c[0] - 0.105).abs() < 1e-15);
        assert!((c[1] - (0.005 * 1000f64.powf(0.6) + 0.1)).abs() < 1e-12);
        assert!(damping_law(&[0.0], 1.0, 1.0, 0.0).is_err());
        // A decay of 60 dB in t60: exp(-c t60 / 2) = 1e-3.
        let c = t60_to_damping(2.5).unwrap();
        assert!(((-c * 2.5 / 2.0).exp() - 1e-3).abs() < 1e-15);
        assert!((damping_to_t60(c).unwrap() - 2.5).abs() < 1e-12);
        assert!(t60_to_damping(0.0).is_err());
        let s = RaisedCosine::new(1e-3, 40.0).unwrap();
        assert!((s.force(0.5e-3) - 40.0).abs() < 1e-12);
        assert_eq!(s.force(-1e-9), 0.0);
        assert_eq!(s.force(2e-3), 0.0);
        assert!((s.impulse() - 0.02).abs() < 1e-15);
        assert!(RaisedCosine::new(-1.0, 1.0).is_err());
        assert_eq!(impulse_force(0.02, 44100.0), 882.0);
    }
}
