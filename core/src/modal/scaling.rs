//! The physical scale of a plate's unit modes, written once (SEED.md 3.1; Bilbao, Thomas,
//! Touzé, Ducceschi 2015, eq. 2): the bases are computed for the unit plate (radius or `lx`
//! = 1), and a plate of size `a`, thickness `h` and material `(E, ρ, ν)` has the pulsations
//! `ω_s = λ_s² √(D/ρh) / a²` with `D = E h³ / (12 (1 − ν²))`, and the in-plane eigenvalues
//! `ζ_s⁴ / a⁴`. The engine's voices (at every note, on the audio thread), the scenes' voices,
//! the automatic quality's spectrum and `noether modes` all scale through these functions.
//!
//! Any thread; no allocation, no validation (the callers' parameters are validated: see
//! [`super::omega_scale`] for the checked form).

/// Flexural rigidity `D = E h³ / (12 (1 − ν²))` (N·m) of Young's modulus `young` (Pa),
/// `thickness` (m) and Poisson ratio `nu`.
#[inline]
pub fn flexural_rigidity(young: f64, thickness: f64, nu: f64) -> f64 {
    young * thickness.powi(3) / (12.0 * (1.0 - nu * nu))
}

/// The factor of the unit plate's `λ_s²` giving the pulsations (rad/s): `√(D/ρh) / a²` for
/// `rigidity` D (N·m), `surface_density` ρh (kg/m²) and characteristic `length` a (m).
#[inline]
pub fn pulsation_scale(rigidity: f64, surface_density: f64, length: f64) -> f64 {
    (rigidity / surface_density).sqrt() / (length * length)
}

/// The divisor `a⁴` (m⁴) of the unit plate's in-plane eigenvalues for a plate of
/// characteristic `length` a (m): the plate's are `ζ_s⁴ / a⁴`. Computed once per plate (or
/// note) and divided by, mode after mode.
#[inline]
pub fn in_plane_divisor(length: f64) -> f64 {
    length.powi(4)
}
