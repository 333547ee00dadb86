//! Where the player's hand rests on an engine voice and how hard it damps at full pressure
//! (the per-note pressure expression; the damper itself is the model's:
//! [`crate::models::plate::hand_damper`], [`crate::models::string::hand_damper`]).
//!
//! Threads: constants and pure functions, any thread.

/// 60 dB decay time (s) of the note's fundamental under the player's hand at full pressure
/// (per-note pressure 1): a firm mute, as a percussionist's palm stops a gong within a
/// fraction of a second.
pub const HAND_T60: f64 = 0.15;

/// Where the player's hand rests on an engine string: this fraction of the length from the
/// bridge end (`x = 0`), i.e. 0.1 L from the nut, away from the bridge.
pub const HAND_STRING_POSITION: f64 = 0.9;

/// Smallest radius of the hand point (fraction of the radius, or of the half-diagonal of a
/// rectangle): the hand rests opposite the strike across the centre, at the strike's radius
/// but at least this far out (a centre strike would otherwise put the hand on the strike).
pub const HAND_MIN_RADIUS: f64 = 0.5;

/// The hand's radius for a strike at radius `strike_radius` (same units): opposite the strike,
/// at `max(strike_radius, HAND_MIN_RADIUS)`.
pub(crate) fn hand_radius(strike_radius: f64) -> f64 {
    strike_radius.max(HAND_MIN_RADIUS)
}

/// The hand's damper coefficient at full pressure (N·s/m) for a note of surface density
/// `rho_h` (kg/m²) with mode values `weights` = `Φ_s(x_h)` (1/m, lowest mode first) at the hand
/// point: the coefficient under which the note's fundamental decays by 60 dB in [`HAND_T60`],
/// `c_max = 2 ρh ln(1000) / (HAND_T60 Φ_0(x_h)²)` (`σ = c Φ²/2ρh`, see
/// [`crate::models::plate::hand_damping_for_t60`]). If the hand point is (nearly) on a node of
/// the fundamental (`|Φ_0| < 10⁻³ max_s |Φ_s|`) the lowest mode it is not on a node of takes
/// its place; 0 (no hand) if every weight is 0. Any thread, O(N_Φ).
pub(crate) fn hand_c_max(rho_h: f64, weights: &[f64]) -> f64 {
    let top = weights.iter().fold(0.0f64, |m, w| m.max(w.abs()));
    match weights.iter().find(|w| w.abs() >= 1e-3 * top) {
        Some(&phi) if top > 0.0 => crate::models::plate::hand_damping_for_t60(rho_h, phi, HAND_T60),
        _ => 0.0,
    }
}
