//! What the editor sees of a string, for every voice made of strings (the single string, the
//! drone, the sitar): its displacement sampled from the grid (one inverse transform, then
//! linear interpolation between nodes) and its lowest modes.
//!
//! Audio thread; no allocation.

use crate::engine::telemetry::{SNAPSHOT_POINTS, SPECTRUM_MODES};
use crate::models::string::StiffString;

/// Samples the grid displacement `u` (m; the interior nodes of `u.len() + 1` equal
/// intervals, zero at both ends) into `out`, point `p` at the fraction `fraction(p)` (0 to
/// 1) of the length, linearly interpolated between the nodes.
pub(super) fn sample_grid(u: &[f64], out: &mut [f32], fraction: impl Fn(usize) -> f64) {
    let intervals = u.len() + 1;
    let at = |k: usize| {
        if k == 0 || k >= intervals {
            0.0
        } else {
            u[k - 1]
        }
    };
    for (p, d) in out.iter_mut().enumerate() {
        let xi = fraction(p).clamp(0.0, 1.0) * intervals as f64;
        let k = (xi.floor() as usize).min(intervals - 1);
        let w = xi - k as f64;
        *d = ((1.0 - w) * at(k) + w * at(k + 1)) as f32;
    }
}

/// Where the voice snapshot's point `p` lies, as a fraction of the length: the
/// [`SNAPSHOT_POINTS`] points evenly inside the string, its ends left out.
pub(super) fn snapshot_fraction(p: usize) -> f64 {
    (p + 1) as f64 / (SNAPSHOT_POINTS + 1) as f64
}

/// The string's lowest modes: their frequencies (Hz) and `|q_j|` (m), at most
/// [`SPECTRUM_MODES`] (the caller has zeroed the rest).
pub(super) fn mode_spectrum(
    s: &StiffString,
    freq: &mut [f32; SPECTRUM_MODES],
    amp: &mut [f32; SPECTRUM_MODES],
) {
    let q = s.modal_displacement();
    let params = s.params();
    for j in 0..q.len().min(SPECTRUM_MODES) {
        freq[j] = (params.omega(j + 1) / std::f64::consts::TAU) as f32;
        amp[j] = q[j].abs() as f32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The samples interpolate the nodes and the ends are zero: a triangle of three interior
    /// nodes sampled at the nodes, between them and at the ends.
    #[test]
    fn samples_interpolate_the_nodes() {
        let u = [1.0, 2.0, 1.0];
        let mut out = [0.0f32; 9];
        sample_grid(&u, &mut out, |p| p as f64 / 8.0);
        assert_eq!(out, [0.0, 0.5, 1.0, 1.5, 2.0, 1.5, 1.0, 0.5, 0.0]);
    }
}
