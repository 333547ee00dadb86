//! What every modal basis of a unit plate offers, whatever its shape: the trait
//! [`ModalBasis`] and the point type [`UnitPoint`] its mode shapes are evaluated at.

use super::tensor::CouplingTensor;

/// The coordinate system a basis reads a [`UnitPoint`] in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coordinates {
    /// Discs: `u = r` (radius, `[0, 1]`), `v = θ` (radians).
    Polar,
    /// Rectangles: `u = ξ = x/Lx`, `v = η = y/Ly`, both fractions of the sides in `[0, 1]`.
    Sides,
}

/// A point of the unit plate, two coordinates whose meaning is the basis's
/// [`ModalBasis::coordinates`]: `(r, θ)` on discs, `(ξ, η)` fractions of the sides on
/// rectangles. Plain data, any thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnitPoint {
    /// `r` (discs) or `ξ = x/Lx` (rectangles).
    pub u: f64,
    /// `θ` in radians (discs) or `η = y/Ly` (rectangles).
    pub v: f64,
}

impl UnitPoint {
    /// A point of a disc: radius `r ∈ [0, 1]`, angle `theta` (radians).
    pub fn polar(r: f64, theta: f64) -> Self {
        Self { u: r, v: theta }
    }

    /// A point of a rectangle: `xi = x/Lx`, `eta = y/Ly`, both in `[0, 1]`.
    pub fn sides(xi: f64, eta: f64) -> Self {
        Self { u: xi, v: eta }
    }
}

/// The dimensionless modal basis of a plate of unit size (`a = 1` or `Lx = 1`, `D = ρh = 1`):
/// transverse eigenvalues `λ_s²`, in-plane eigenvalues `ζ_l⁴`, mode shapes `Φ_s` and the
/// coupling tensor `H^l_{ij} = ∫ Ψ_l L(Φ_i, Φ_j) dS`.
///
/// Implemented by [`super::PlateModes`] (circular) and [`super::rect::RectModes`]. Built on a
/// worker thread, read-only afterwards; `phi_at` never allocates (any thread).
pub trait ModalBasis: std::fmt::Debug + Send + Sync {
    /// `λ_s²` of each transverse mode, increasing (the dimensionless pulsation; physical
    /// `ω_s = λ_s² √(D/ρh) / L²` with `L` the radius or `Lx`).
    fn lambda2(&self) -> &[f64];

    /// `ζ_l⁴` of each in-plane mode (`ΔΔΨ_l = ζ_l⁴ Ψ_l`), increasing.
    fn zeta4(&self) -> &[f64];

    /// The coordinates [`Self::phi_at`] reads.
    fn coordinates(&self) -> Coordinates;

    /// `Φ_mode` (normalised to `∫Φ² dS = 1` on the unit plate) at `p`, read in
    /// [`Self::coordinates`]. Allocation-free. Panics if `mode >= n_phi()`.
    fn phi_at(&self, mode: usize, p: UnitPoint) -> f64;

    /// The coupling tensor `H^l_{ij}`.
    fn coupling(&self) -> &CouplingTensor;

    /// For a basis whose every mode is `R_s(r) cos(n_s θ)` (a circular basis of cosine modes,
    /// such as the strike-mirror subspace): the angular order `n_s` of `mode`, so that
    /// `Φ_s(r, θ) = Φ_s(r, 0) cos(n_s θ)` rotates a point without evaluating the radial factor
    /// again. `None` for any other basis. Allocation-free.
    fn cosine_order(&self, _mode: usize) -> Option<u32> {
        None
    }

    /// Number of transverse modes `N_Φ`.
    fn n_phi(&self) -> usize {
        self.lambda2().len()
    }
}
