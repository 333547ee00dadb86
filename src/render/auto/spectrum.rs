//! What a plate scene's modal basis covers, in Hz, without building the basis: the sorted
//! transverse frequencies of the first N modes (closed forms for the rectangle, Bessel roots
//! for the disc), the in-plane modes a mirror basis of the same band keeps, and the band of
//! the raised-cosine strike.
//!
//! Runs on the thread that selects the model (CLI main thread); allocates.

use crate::modal::rect::transverse_modes;
use crate::modal::{circular_modes_with, CircularEdge, Parity};
use crate::scene::plate::{PlateShape, PlateSpec};
use std::f64::consts::TAU;

/// Transverse edge condition of a circular scene.
fn edge(plate: &PlateSpec) -> CircularEdge {
    if plate.shape == PlateShape::CircularClamped {
        CircularEdge::Clamped
    } else {
        CircularEdge::Free
    }
}

/// `√(D/ρh)/L²` (rad/s per unit of dimensionless `λ²`), `L` the radius or `lx`, as the voice
/// scales its basis ([`PlateSpec::pulsation_scale`]).
fn omega_scale(plate: &PlateSpec) -> f64 {
    plate.pulsation_scale()
}

/// One transverse mode: its frequency (Hz) and whether it is even about the strike diameter
/// (`cos nθ`; always true on rectangles, which have no mirror basis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModeFreq {
    /// Undamped frequency `ω / 2π` in Hz.
    pub hz: f64,
    /// `cos nθ` angular factor (kept by the strike-mirror basis).
    pub even: bool,
}

/// The first `count` transverse modes of the scene's plate in the FULL basis (cos and sin
/// pairs), in the basis's own order (increasing frequency).
pub fn transverse(plate: &PlateSpec, count: usize) -> Vec<ModeFreq> {
    let scale = omega_scale(plate) / TAU;
    match plate.shape {
        PlateShape::RectSs => {
            let aspect = plate.ly.unwrap_or(1.0) / plate.lx.unwrap_or(1.0);
            let (_, lambda2) = transverse_modes(aspect, count);
            lambda2
                .iter()
                .map(|l2| ModeFreq {
                    hz: l2 * scale,
                    even: true,
                })
                .collect()
        }
        _ => circular_modes_with(edge(plate), plate.material.poisson, count, false)
            .iter()
            .map(|m| ModeFreq {
                hz: m.radial.lambda * m.radial.lambda * scale,
                even: m.parity == Parity::Cos,
            })
            .collect(),
    }
}

/// How many `cos nθ` in-plane modes the first `count` in-plane modes of the full basis hold:
/// the `n_psi` of the mirror basis of the same in-plane band (the in-plane modes are of the
/// clamped type, `Ψ = ∂Ψ/∂r = 0` at the edge, whatever the transverse edge).
pub fn mirror_in_plane_count(plate: &PlateSpec, count: usize) -> usize {
    circular_modes_with(CircularEdge::Clamped, plate.material.poisson, count, false)
        .iter()
        .filter(|m| m.parity == Parity::Cos)
        .count()
}

/// Number of modes of `modes` at or below `f_cut` (Hz), counting only the even ones when
/// `even_only` (the mirror basis); at least 1.
pub fn count_below(modes: &[ModeFreq], f_cut: f64, even_only: bool) -> usize {
    modes
        .iter()
        .filter(|m| m.hz <= f_cut * (1.0 + 1e-12) && (m.even || !even_only))
        .count()
        .max(1)
}

/// Highest frequency (Hz) of the first `n` modes of `modes` taken in order, keeping only even
/// ones when `even_only`.
pub fn band_of(modes: &[ModeFreq], n: usize, even_only: bool) -> f64 {
    modes
        .iter()
        .filter(|m| m.even || !even_only)
        .take(n)
        .fold(0.0, |f, m| f.max(m.hz))
}

/// Frequency (Hz) above which the spectrum of a raised-cosine pulse of length `duration` (s)
/// stays 80 dB below its value at 0 Hz: `|F(f)|/F(0) = |sinc(fT)| / |1 - (fT)²|`, whose
/// envelope `1/(π fT |1 - (fT)²|)` falls under 1e-4 for `fT ≥ 14.7` (the first zero of the
/// pulse spectrum is at `fT = 2`; the tail decays as `f⁻³`). Informative: the cascade of the
/// nonlinear plate carries energy above it, which the verification measures.
pub fn strike_band(duration: f64) -> f64 {
    // Solve 1/(π x (x² - 1)) = 1e-4 for x > 1 by bisection (monotone there).
    let (mut lo, mut hi) = (1.5f64, 100.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if 1.0 / (std::f64::consts::PI * mid * (mid * mid - 1.0)) > 1e-4 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi) / duration
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The envelope bound: at the returned `fT` the envelope is 1e-4 (to 1e-9 relative), and the
    /// pulse spectrum itself, evaluated in closed form, is below it.
    #[test]
    fn strike_band_is_the_minus_80_db_point() {
        let x = strike_band(1.0);
        let env = 1.0 / (std::f64::consts::PI * x * (x * x - 1.0));
        assert!((env - 1e-4).abs() < 1e-13, "{x} {env}");
        let sinc = (std::f64::consts::PI * x).sin() / (std::f64::consts::PI * x);
        assert!((sinc / (1.0 - x * x)).abs() <= env);
        assert!((strike_band(0.01) - 100.0 * x).abs() < 1e-9);
    }
}
