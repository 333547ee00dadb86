//! Physical and discretisation parameters of the stiff string (SEED.md section 3.2).
//!
//! `μ u_tt - T u_xx + EI u_xxxx = f` on `0 < x < L`, simply supported (`u = u_xx = 0` at both
//! ends). Modes `φ_j(x) = √(2/L) sin(jπx/L)` and angular frequencies
//! `ω_j = 2π j (c0 / 2L) √(1 + B j²)`, `c0 = √(T/μ)`, `B = π² EI / (T L²)`.
//! The grid has `N` intervals, `Δx = L/N`, interior nodes `x_i = iΔx`, `i = 1..N-1`, and the
//! model keeps `N_m = N - 1` modes (one per interior node).
//!
//! Everything here is built and validated on a control thread; the audio thread only reads the
//! validated values copied into the model.

use crate::error::{check_closed, check_non_negative, ParamError};
use crate::models::ranges::{
    STRING_INHARMONICITY, STRING_LENGTH, STRING_LINEAR_DENSITY, STRING_TENSION,
};
use std::f64::consts::PI;

/// Largest accepted number of grid intervals `N` (a bound so that build-time allocation and the
/// per-step work stay bounded).
pub const MAX_INTERVALS: usize = 1 << 20;

/// How the bending stiffness is given.
///
/// Read on the control thread at build time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stiffness {
    /// Bending stiffness `EI` in N·m² (≥ 0).
    BendingStiffness(f64),
    /// Inharmonicity coefficient `B = π² EI / (T L²)` (dimensionless, ≥ 0).
    Inharmonicity(f64),
}

/// Parameters of a stiff string and its discretisation.
///
/// Built and validated on a control thread ([`StringParams::validate`]); the model copies them at
/// build time and the audio thread never touches this struct.
#[derive(Debug, Clone, PartialEq)]
pub struct StringParams {
    /// Length `L` in m (> 0).
    pub length: f64,
    /// Tension `T` in N (> 0).
    pub tension: f64,
    /// Linear mass density `μ` in kg/m (> 0).
    pub linear_density: f64,
    /// Bending stiffness, as `EI` (N·m²) or as the inharmonicity `B`.
    pub stiffness: Stiffness,
    /// Diameter `d` in m (≥ 0), used only by the air-friction loss term.
    pub diameter: f64,
    /// Number of grid intervals `N` (2 ..= [`MAX_INTERVALS`]); the model has `N - 1` modes.
    /// Any value works; [`StringParams::smooth_intervals`] picks a fast one.
    pub intervals: usize,
    /// Simulation rate `fs = 1/h` in Hz (> 0). Any value is stable (the linear scheme is exact);
    /// partials above `fs/2` alias but their samples stay exact.
    pub sample_rate: f64,
}

impl StringParams {
    /// The lecture's guitar-like string (SEED.md 3.2): L = 1 m, T = 180.5 N,
    /// μ = 1.17e-3 kg/m, B = 2e-5, d = 0.43 mm (fundamental ≈ 196 Hz), with the given grid and
    /// rate.
    pub fn lecture_guitar(intervals: usize, sample_rate: f64) -> Self {
        Self {
            length: 1.0,
            tension: 180.5,
            linear_density: 1.17e-3,
            stiffness: Stiffness::Inharmonicity(2e-5),
            diameter: 0.43e-3,
            intervals,
            sample_rate,
        }
    }

    /// The smallest `N ≥ min_intervals` whose DST-I is fast: `2N` has no prime factor above 7
    /// (the DST-I of length `N - 1` runs as a complex FFT of length `2N`; a large prime factor
    /// sends rustfft to Rader/Bluestein, 3-5× slower). For example 501 → 504, 1001 → 1008.
    pub fn smooth_intervals(min_intervals: usize) -> usize {
        let smooth = |mut n: usize| {
            for p in [2, 3, 5, 7] {
                while n % p == 0 {
                    n /= p;
                }
            }
            n == 1
        };
        (min_intervals.max(2)..)
            .find(|&n| smooth(2 * n))
            .unwrap_or(min_intervals)
    }

    /// Checks every field; the error names the field, the value and the allowed range.
    pub fn validate(&self) -> Result<(), ParamError> {
        // The ranges scenes and presets use (`crate::models::ranges`): outside them the
        // derived quantities can overflow or underflow (a 1e308 m string at 1e-310 N and a
        // rate of 1e-307 Hz passes every finiteness check yet steps to NaN).
        STRING_LENGTH.check("length", self.length)?;
        STRING_TENSION.check("tension", self.tension)?;
        STRING_LINEAR_DENSITY.check("linear_density", self.linear_density)?;
        match self.stiffness {
            Stiffness::BendingStiffness(ei) => {
                check_non_negative("bending_stiffness", ei)?;
            }
            Stiffness::Inharmonicity(b) => {
                check_non_negative("inharmonicity", b)?;
            }
        }
        check_non_negative("diameter", self.diameter)?;
        if !(2..=MAX_INTERVALS).contains(&self.intervals) {
            return Err(ParamError::new(
                "intervals",
                self.intervals,
                format!("integer in [2, {MAX_INTERVALS}]"),
            ));
        }
        // Wider than scenes' `STRING_SIM_RATE`: convergence studies run the exact scheme up to
        // tens of MHz; what must be refused is a rate whose step overflows the phases.
        check_closed("sample_rate", self.sample_rate, 1.0, 1e10)?;
        // Derived quantities must be finite too (for example a huge EI with a tiny T).
        let b = self.inharmonicity();
        if !(b.is_finite() && b <= STRING_INHARMONICITY.max) {
            return Err(ParamError::new(
                "bending_stiffness",
                self.bending_stiffness(),
                format!(
                    "value giving an inharmonicity π²EI/(TL²) of at most {}",
                    STRING_INHARMONICITY.max
                ),
            ));
        }
        if !self.omega(self.modes()).is_finite() {
            return Err(ParamError::new(
                "intervals",
                self.intervals,
                "value giving finite modal frequencies",
            ));
        }
        // The exact scheme evaluates cos(ω_j h) and sin(ω_j h): the phase per step of the top
        // mode must be finite (a rate of 1e-307 Hz with ω of 1e151 rad/s is not).
        if !(self.omega(self.modes()) * self.h()).is_finite() {
            return Err(ParamError::new(
                "sample_rate",
                self.sample_rate,
                "value giving a finite phase step ω_max/fs",
            ));
        }
        Ok(())
    }

    /// Bending stiffness `EI` in N·m².
    pub fn bending_stiffness(&self) -> f64 {
        match self.stiffness {
            Stiffness::BendingStiffness(ei) => ei,
            Stiffness::Inharmonicity(b) => b * self.tension * self.length * self.length / (PI * PI),
        }
    }

    /// Inharmonicity `B = π² EI / (T L²)`.
    pub fn inharmonicity(&self) -> f64 {
        match self.stiffness {
            Stiffness::BendingStiffness(ei) => {
                PI * PI * ei / (self.tension * self.length * self.length)
            }
            Stiffness::Inharmonicity(b) => b,
        }
    }

    /// Transverse wave speed `c0 = √(T/μ)` in m/s.
    pub fn wave_speed(&self) -> f64 {
        (self.tension / self.linear_density).sqrt()
    }

    /// Number of modes `N_m = N - 1`.
    pub fn modes(&self) -> usize {
        self.intervals - 1
    }

    /// Grid spacing `Δx = L/N` in m.
    pub fn dx(&self) -> f64 {
        self.length / self.intervals as f64
    }

    /// Time step `h = 1/fs` in s.
    pub fn h(&self) -> f64 {
        1.0 / self.sample_rate
    }

    /// Angular frequency of mode `j ≥ 1` in rad/s: `ω_j = 2π j (c0/2L) √(1 + B j²)`.
    pub fn omega(&self, j: usize) -> f64 {
        let j = j as f64;
        2.0 * PI * j * self.wave_speed() / (2.0 * self.length)
            * (1.0 + self.inharmonicity() * j * j).sqrt()
    }

    /// How many of the modes (from the lowest, `1..=modes()`) lie below `hz` (Hz): the modes a
    /// band-limited string steps (`StiffString::set_band_limit`). O(that count).
    pub fn modes_below(&self, hz: f64) -> usize {
        (1..=self.modes())
            .take_while(|&j| self.omega(j) / (2.0 * PI) < hz)
            .count()
    }

    /// Mode shape `φ_j(x) = √(2/L) sin(jπx/L)` in m^-1/2.
    pub fn mode_shape(&self, j: usize, x: f64) -> f64 {
        (2.0 / self.length).sqrt() * (j as f64 * PI * x / self.length).sin()
    }

    /// Checks that `x` (named `field`) is a position strictly inside the string, `0 < x < L`.
    pub fn check_position(&self, field: &str, x: f64) -> Result<f64, ParamError> {
        if x.is_finite() && x > 0.0 && x < self.length {
            Ok(x)
        } else {
            Err(ParamError::new(
                field,
                x,
                format!("position in (0, {}) m (inside the string)", self.length),
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_intervals_have_small_prime_factors() {
        assert_eq!(StringParams::smooth_intervals(501), 504);
        assert_eq!(StringParams::smooth_intervals(1001), 1008);
        assert_eq!(StringParams::smooth_intervals(64), 64);
        assert_eq!(StringParams::smooth_intervals(101), 105);
    }

    #[test]
    fn lecture_string_is_196_hz_and_b_round_trips() {
        let p = StringParams::lecture_guitar(100, 48_000.0);
        p.validate().unwrap();
        let f0 = p.wave_speed() / (2.0 * p.length);
        assert!((f0 - 196.4).abs() < 0.1, "{f0}");
        let q = StringParams {
            stiffness: Stiffness::BendingStiffness(p.bending_stiffness()),
            ..p.clone()
        };
        assert!((q.inharmonicity() / 2e-5 - 1.0).abs() < 1e-14);
        assert!((q.omega(7) / p.omega(7) - 1.0).abs() < 1e-14);
    }
}
