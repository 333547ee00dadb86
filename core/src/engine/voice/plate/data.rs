//! A plate bank's data shared read-only by its voices: the strike and pickup frame, the
//! modes' constants, the tier ladder and the band above's modes.
//!
//! Threads: built on the worker thread (inside a bank); read on the audio thread.

use super::super::above::AboveModes;
use crate::models::plate::basis::PlateBasis;

/// Smallest in-plane count of a tier of a nonlinear plate.
pub(crate) const MIN_TIER_PSI: usize = 4;

/// Where the strike and the pickups sit in the basis's frame.
#[derive(Debug, Clone)]
pub(crate) enum Frame {
    /// Circular plate in the strike-mirror basis: every mode is `Φ_s(r, 0) cos(n_s θ)`.
    Mirror {
        /// The basis, for `Φ̂_s` at a note's own strike or pickup radius.
        basis: PlateBasis,
        /// Strike radius (fraction of the radius) of `strike`.
        strike_radius: f64,
        /// Pickup radii (fractions of the radius) of `pickups`.
        pickup_radii: [f64; 2],
        /// Angular order `n_s` of each mode.
        orders: Vec<u32>,
        /// `Φ̂_s(r_strike, 0)` (unit plate).
        strike: Vec<f64>,
        /// `Φ̂_s(r_hand, 0)` (unit plate, [`crate::engine::voice::hand_placement::hand_radius`]); the hand sits at angle π of the frame.
        hand: Vec<f64>,
        /// `Φ̂_s(r_p, 0)` of the left and right pickups (unit plate).
        pickups: [Vec<f64>; 2],
        /// Polar angles `θ_p` of the pickups (rad, plate frame).
        pickup_angles: [f64; 2],
    },
    /// Full basis (rectangles): the strike point is evaluated at each fresh note.
    Fixed {
        /// The basis, for `Φ̂_s` at the strike point.
        basis: PlateBasis,
        /// Strike position parameter (fraction of the half-diagonal from the centre).
        strike_radius: f64,
        /// `Φ̂_s` at the left and right pickups (unit plate).
        pickups: [Vec<f64>; 2],
        /// Pickup positions `(r, θ)` of `pickups` (fraction of the half-diagonal, rad).
        pickup_points: [(f64, f64); 2],
    },
}

/// Per-bank data of a plate model, shared read-only by the voices of a bank.
#[derive(Debug, Clone)]
pub(crate) struct PlateData {
    /// `λ_s²` of every mode of the bank's basis, increasing: `ω_s = λ_s² √(D/ρh) / a²`.
    pub lambda2: Vec<f64>,
    /// `ζ̂_l⁴` of the unit plate (`ζ_l⁴ = ζ̂_l⁴ / a⁴`).
    pub zeta4: Vec<f64>,
    /// Whether the plate is linear (no in-plane modes: `κ = 0`).
    pub linear: bool,
    /// Strike and pickup placement.
    pub frame: Frame,
    /// `Φ̂_s` at the snapshot points, row-major `[point][mode]` (every mode of the basis; the
    /// strike's diameter for a circular plate, the diagonal for a rectangle).
    pub snapshot: Vec<f64>,
    /// Poisson ratio `ν` the basis was built with.
    pub poisson: f64,
    /// The tiers `(N_Φ, N_Ψ)`, largest first; voices hold one model per tier.
    pub tiers: Vec<(usize, usize)>,
    /// The CPU governor's price of one step of each tier (s; measured on the worker under the
    /// governor, else the prior estimate; see `engine/governor.rs`), same order as `tiers`.
    pub tier_price: Vec<f64>,
    /// Band limit (Hz): a note keeps the modes up to it.
    pub band_hz: f64,
    /// The plate's modes continued past the basis, for the band above ([`super::above`]).
    pub above: AboveModes,
    /// Heap bytes of the tiers' coupling tensors (shared by the voices; the basis's own tensor,
    /// in the worker's cache, not counted).
    pub tensor_bytes: usize,
    /// The dome's rest shape per unit rise on the unit plate, every mode (dimensionless;
    /// `a_k = L h · dome · shape_dome_k`, [`super::rest_shape`]).
    pub shape_dome: Vec<f64>,
    /// The boss's, likewise (zeros on the rectangle).
    pub shape_boss: Vec<f64>,
}

/// The tier ladder for a budget of `n_phi` transverse and `n_psi` in-plane modes (`n_psi` 0:
/// linear plate, built with one in-plane slot and `κ = 0`): `N_k = ⌈N 2^{-k/2}⌉` down to 8
/// modes, in-plane counts in proportion. Worker thread.
pub(crate) fn tier_ladder(n_phi: usize, n_psi: usize) -> Vec<(usize, usize)> {
    let mut tiers: Vec<(usize, usize)> = Vec::new();
    let mut k = 0;
    loop {
        let n = (n_phi as f64 * (-0.5 * k as f64).exp2()).ceil() as usize;
        if k > 0 && (n < 8 || tiers.last().is_some_and(|t| t.0 == n)) {
            break;
        }
        let m = if n_psi == 0 {
            1
        } else {
            ((n_psi * n) as f64 / n_phi as f64)
                .round()
                .max(MIN_TIER_PSI.min(n_psi) as f64) as usize
        };
        tiers.push((n, m.min(n_psi.max(1))));
        k += 1;
    }
    tiers
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ladder halves the mode count every two tiers, stops at 8 modes, and keeps the
    /// in-plane count in proportion with its floor.
    #[test]
    fn ladder_shapes() {
        let t = tier_ladder(510, 15);
        assert_eq!(t[0], (510, 15));
        assert_eq!(t[1], (361, 11));
        assert_eq!(t[2], (255, 8));
        assert!(t
            .iter()
            .all(|&(n, m)| n >= 8 && (MIN_TIER_PSI..=15).contains(&m)));
        assert!(t.windows(2).all(|w| w[1].0 < w[0].0));
        assert_eq!(t.last().unwrap().0, 8);
        assert_eq!(tier_ladder(50, 0).iter().map(|t| t.1).max(), Some(1));
        assert_eq!(tier_ladder(6, 2), vec![(6, 2)]);
    }
}
