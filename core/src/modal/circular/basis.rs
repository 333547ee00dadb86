//! The modal basis of a circular plate: transverse modes Φ, in-plane (Airy) modes Ψ and their
//! coupling tensor, in dimensionless units (radius `a = 1`, `D = ρh = 1`).
//!
//! Conventions (SEED §3.1 and "Facts"):
//! - `Φ_{n,k}(r, θ) = R_{nk}(r) cos nθ` or `R_{nk}(r) sin nθ`; `n` nodal diameters, `k` interior
//!   nodal circles (Leissa 1969 labelling; the free plate's `n = 0, 1` elastic modes start at
//!   `k = 1` because `(0,0)` and `(1,0)` are its rigid-body modes, which are excluded);
//! - cos/sin pairs count as two modes; modes are sorted by frequency (ties: `n`, `k`, cos first);
//!   a basis of `N` modes is the first `N` of that list, so the last pair may be cut in half;
//! - every mode is normalised to `∫_disc Φ² dS = 1` (the disc has area π), likewise Ψ;
//! - transverse pulsation `ω = λ²` (physical `ω = λ² √(D/ρh)/a²`, see [`omega_scale`]);
//!   in-plane eigenvalue `ζ⁴` of `ΔΔΨ = ζ⁴ Ψ` with `Ψ = ∂Ψ/∂r = 0` at `r = 1` (edge free of
//!   in-plane stress; this is the only in-plane condition implemented), `n = 0` included.
//!
//! Threads: [`PlateModes::build`] runs on a worker thread (allocates, spawns scoped helpers);
//! [`PlateModes::phi_at`] and the tensor kernels are allocation-free (audio thread).

use super::angular::Parity;
use super::assemble::assemble;
use super::radial::CircularEdge;
use crate::error::{check_closed, check_positive, ParamError};
use crate::modal::basis::{Coordinates, ModalBasis, UnitPoint};
use crate::modal::tensor::CouplingTensor;

pub use super::modes::{circular_modes, circular_modes_with, Mode};

/// What to build: a circular plate basis.
///
/// Plain data, built from user input on any thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircularPlateSpec {
    /// Transverse edge condition.
    pub edge: CircularEdge,
    /// Poisson's ratio ν (dimensionless, in `[0, 0.5]`); enters the free-edge condition only.
    pub nu: f64,
    /// Number of transverse modes `N_Φ` (in `[1, 20000]`).
    pub n_phi: usize,
    /// Number of in-plane modes `N_Ψ` (in `[1, 20000]`).
    pub n_psi: usize,
    /// Gauss-Legendre points of the radial quadrature of the tensor (in `[16, 8192]`).
    pub quad_points: usize,
    /// Keep only the modes even about the diameter θ = 0 (`cos nθ`, Φ and Ψ): the motion
    /// excited by forces on that diameter stays in this subspace exactly (see
    /// [`Self::mirror_symmetric`]). `false` from [`Self::new`].
    pub mirror: bool,
}

impl CircularPlateSpec {
    /// Validates the parameters. `quad_points = None` picks [`default_quad_points`].
    pub fn new(
        edge: CircularEdge,
        nu: f64,
        n_phi: usize,
        n_psi: usize,
        quad_points: Option<usize>,
    ) -> Result<Self, ParamError> {
        check_closed("nu", nu, 0.0, 0.5)?;
        for (name, v) in [("n_phi", n_phi), ("n_psi", n_psi)] {
            if !(1..=20000).contains(&v) {
                return Err(ParamError::new(name, v, "integer in [1, 20000]"));
            }
        }
        let quad_points = match quad_points {
            Some(q) if !(16..=8192).contains(&q) => {
                return Err(ParamError::new("quad_points", q, "integer in [16, 8192]"))
            }
            Some(q) => q,
            None => default_quad_points(edge, nu, n_phi, n_psi),
        };
        Ok(Self {
            edge,
            nu,
            n_phi,
            n_psi,
            quad_points,
            mirror: false,
        })
    }

    /// The same spec restricted to modes even about θ = 0: `N_Φ` and `N_Ψ` then count `cos nθ`
    /// modes only, so the same counts reach about twice the band of the full basis.
    ///
    /// Why it is exact: if `w` is even in θ, `L(w, w)` is even, so the Airy function and the
    /// in-plane force `L(w, F)` are even too, and every coupling coefficient with an odd number
    /// of `sin` factors vanishes (the angular integral, [`super::angular::triple`], is exactly 0).
    /// A force applied on the diameter θ = 0 (rotate the frame so the strike lies there) has
    /// zero projection on the `sin` modes, so they stay exactly zero, linear or not. What it
    /// leaves out: symmetry-breaking motion (companion modes growing through an instability),
    /// which needs an imperfection or an off-diameter force to start. The default quadrature
    /// is kept from the full basis of the same band, so the tensor's entries are the full
    /// basis's entries on this subset: `quad_points` is reset to
    /// [`default_quad_points_with`] for the subset (the order the full basis of the same band
    /// gets).
    pub fn mirror_symmetric(mut self) -> Self {
        self.mirror = true;
        self.quad_points =
            default_quad_points_with(self.edge, self.nu, self.n_phi, self.n_psi, true);
        self
    }

    /// Re-checks a spec whose public fields may have been edited after [`Self::new`].
    pub fn validate(&self) -> Result<(), ParamError> {
        Self::new(
            self.edge,
            self.nu,
            self.n_phi,
            self.n_psi,
            Some(self.quad_points),
        )
        .map(|_| ())
    }
}

/// Default radial quadrature order: the integrands oscillate and grow (boundary layers of the
/// `I_n` terms) with rate up to `κ = 2 λ_max + ζ_max`; we take `Q = 40 + 0.75 κ`, rounded up to
/// a multiple of 8 (160 for the 1000/300 gong, κ ≈ 160). Measured margin: for that basis
/// `Q = 96` already agrees with `Q = 480` to 1e-14 of max|H|; the doubling test in
/// `tests/plates/modal_circular.rs` checks `Q` against `2Q`.
pub fn default_quad_points(edge: CircularEdge, nu: f64, n_phi: usize, n_psi: usize) -> usize {
    default_quad_points_with(edge, nu, n_phi, n_psi, false)
}

/// [`default_quad_points`] for the bases of [`circular_modes_with`] (`even_only`): the rule
/// depends only on the largest `λ` and `ζ`, so a mirror basis gets the order of the full basis
/// covering the same band.
pub fn default_quad_points_with(
    edge: CircularEdge,
    nu: f64,
    n_phi: usize,
    n_psi: usize,
    even_only: bool,
) -> usize {
    let lam = circular_modes_with(edge, nu, n_phi, even_only)
        .last()
        .map_or(0.0, |m| m.radial.lambda);
    let zeta = circular_modes_with(CircularEdge::Clamped, nu, n_psi, even_only)
        .last()
        .map_or(0.0, |m| m.radial.lambda);
    let q = 40.0 + 0.75 * (2.0 * lam + zeta);
    (q.ceil() as usize).div_ceil(8) * 8
}

/// Physical scale of the transverse pulsations: `ω_phys = λ² · omega_scale` with
/// `omega_scale = √(D/(ρh))/a²` in rad/s, `D = E h³/(12(1-ν²))`. Arguments in SI units:
/// radius `a` (m), thickness `h` (m), Young's modulus `E` (Pa), density `ρ` (kg/m³), ν.
pub fn omega_scale(
    radius: f64,
    thickness: f64,
    young: f64,
    density: f64,
    nu: f64,
) -> Result<f64, ParamError> {
    check_positive("radius", radius)?;
    check_positive("thickness", thickness)?;
    check_positive("young", young)?;
    check_positive("density", density)?;
    check_closed("nu", nu, 0.0, 0.5)?;
    let d = crate::modal::scaling::flexural_rigidity(young, thickness, nu);
    Ok(crate::modal::scaling::pulsation_scale(
        d,
        density * thickness,
        radius,
    ))
}

/// The modal basis of a circular plate and its coupling tensor.
///
/// Built on a worker thread ([`PlateModes::build`] or `load_or_build`); read-only afterwards,
/// shared with the audio thread.
#[derive(Debug, Clone, PartialEq)]
pub struct PlateModes {
    /// What was built.
    pub spec: CircularPlateSpec,
    /// Transverse modes Φ, sorted by frequency (length `N_Φ`).
    pub phi: Vec<Mode>,
    /// In-plane modes Ψ, sorted by `ζ` (length `N_Ψ`).
    pub psi: Vec<Mode>,
    /// Transverse eigenvalues `λ_i²` of the unit plate, the dimensionless pulsations
    /// (length `N_Φ`; physical `ω_i = λ_i² · omega_scale`, see [`omega_scale`]).
    pub lambda2: Vec<f64>,
    /// In-plane eigenvalues `ζ_l⁴` (length `N_Ψ`, dimensionless).
    pub zeta4: Vec<f64>,
    /// `H^l_{ij} = ∫ Ψ_l L(Φ_i, Φ_j) dS` (dimensionless); `E^s_{i,j} = H^j_{s,i}`.
    pub coupling: CouplingTensor,
}

impl PlateModes {
    /// Computes the modes (only, no tensor): `(phi, psi)`. Worker thread.
    pub fn modes(spec: &CircularPlateSpec) -> (Vec<Mode>, Vec<Mode>) {
        let phi = circular_modes_with(spec.edge, spec.nu, spec.n_phi, spec.mirror);
        let psi = circular_modes_with(CircularEdge::Clamped, spec.nu, spec.n_psi, spec.mirror);
        (phi, psi)
    }

    /// Builds modes and tensor (no cache). Worker thread; uses every core.
    pub fn build(spec: &CircularPlateSpec) -> Result<Self, ParamError> {
        spec.validate()?;
        let (phi, psi) = Self::modes(spec);
        let coupling = assemble(&phi, &psi, spec.quad_points)?;
        Ok(Self::from_parts(*spec, phi, psi, coupling))
    }

    /// Assembles the struct from modes and a tensor of matching sizes.
    pub(crate) fn from_parts(
        spec: CircularPlateSpec,
        phi: Vec<Mode>,
        psi: Vec<Mode>,
        coupling: CouplingTensor,
    ) -> Self {
        let lambda2 = phi.iter().map(|m| m.radial.lambda.powi(2)).collect();
        let zeta4 = psi.iter().map(|m| m.radial.lambda.powi(4)).collect();
        Self {
            spec,
            phi,
            psi,
            lambda2,
            zeta4,
            coupling,
        }
    }

    /// Value of transverse mode `mode` at `(r, theta)` (dimensionless radius in `[0, 1]`,
    /// radians), e.g. for strike and pickup positions. Allocation-free (any thread).
    /// Panics if `mode >= N_Φ`.
    pub fn phi_at(&self, mode: usize, r: f64, theta: f64) -> f64 {
        self.phi[mode].eval(r, theta)
    }
}

impl ModalBasis for PlateModes {
    fn lambda2(&self) -> &[f64] {
        &self.lambda2
    }

    fn zeta4(&self) -> &[f64] {
        &self.zeta4
    }

    fn coordinates(&self) -> Coordinates {
        Coordinates::Polar
    }

    /// `Φ_mode(r, θ)` with `p = UnitPoint::polar(r, θ)`.
    fn phi_at(&self, mode: usize, p: UnitPoint) -> f64 {
        self.phi[mode].eval(p.u, p.v)
    }

    fn coupling(&self) -> &CouplingTensor {
        &self.coupling
    }

    fn cosine_order(&self, mode: usize) -> Option<u32> {
        let m = &self.phi[mode];
        (m.parity == Parity::Cos).then_some(m.n)
    }
}
