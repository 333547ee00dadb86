//! Modal data of the simply supported rectangular von Kármán plate whose edges are free of
//! in-plane stress (the case of Ducceschi & Touzé, "Modal approach for nonlinear vibrations of
//! damped impacted plates: application to sound synthesis of gongs and cymbals", JSV 344,
//! 313-331, 2015; `shared/docs/SEED.md` sec. 3.1).
//!
//! # Conventions
//! - Dimensionless plate `[0, 1] × [0, aspect]`: lengths in units of `Lx`, `aspect = Ly/Lx`;
//!   `D = ρh = 1`, so the transverse pulsation is `ω̃ = λ² = ω Lx² sqrt(ρh/D)`.
//! - Transverse modes, closed form: `Φ_{m,n} = (2/sqrt(aspect)) sin(mπx) sin(nπy/aspect)`,
//!   `λ²_{m,n} = π²(m² + n²/aspect²)`, `∫Φ² dS = 1`; the first `N_Φ` sorted by the computed
//!   `λ²` (f64 total order), equal values broken by increasing `m`. A mathematically degenerate
//!   pair whose computed values differ in the last bits keeps that order (deterministic on any
//!   IEEE-754 machine), and a degenerate pair may be split by the truncation at `N_Φ`.
//! - In-plane (Airy) modes: `ΔΔΨ = ζ⁴Ψ`, `Ψ = ∂_nΨ = 0` on the edges (edges free of in-plane
//!   stress, "Facts from the cited papers" in SEED.md; *not* immovable or straight edges),
//!   computed by Rayleigh-Ritz (see `airy.rs`), `∫Ψ² dS = 1`.
//! - Coupling: `H^l_{ij} = ∫ Ψ_l L(Φ_i, Φ_j) dS`, `L(f,g) = f_xx g_yy + f_yy g_xx - 2 f_xy g_xy`
//!   ([`RectModes::coupling`], a [`CouplingTensor`]; [`RectModes::triplets`] lists it). The other tensor of the modal equations,
//!   `E^s_{ij} = ∫ Φ_s L(Φ_i, Ψ_j) dS`, equals `H^j_{si}`: integrating by parts twice moves
//!   the derivatives off Ψ, the boundary terms carry Ψ or ∇Ψ and vanish because
//!   `Ψ = ∂_nΨ = 0` (hence ∇Ψ = 0) on the edge, and
//!   `(fg_xx)_yy + (fg_yy)_xx - 2(fg_xy)_xy = L(f, g)` (Bilbao, Thomas, Touzé & Ducceschi,
//!   Num. Meth. PDE 31(6), 2015, sec. 2: the triple self-adjointness of `L`).
//! - Positions passed to [`RectModes::phi_at`] and [`RectModes::psi_derivs_at`] are fractions
//!   of the sides: `xi = x/Lx ∈ [0,1]`, `eta = y/Ly ∈ [0,1]` (for [`ModalBasis::phi_at`],
//!   `UnitPoint::sides(xi, eta)`).
//!
//! # Dimensional scaling
//! For a physical plate `Lx × (aspect·Lx)` with modes normalised on the physical area:
//! `Φ_phys(X, Y) = Φ̃(X/Lx, Y/Lx) / Lx` (so `∫Φ_phys² dX dY = 1`), likewise `Ψ`. Each
//! derivative brings `1/Lx`, so `ΔΔ_phys = ΔΔ̃/Lx⁴` and
//! - `ζ⁴_phys = ζ̃⁴ / Lx⁴`;
//! - `H_phys = ∫ Ψ_phys L_phys(Φ_phys, Φ_phys) dX dY = H̃ · Lx⁻¹ · Lx⁻² · Lx⁻⁴ · Lx² = H̃ / Lx⁵`;
//! - from `ρh ω² = D k⁴` with `k⁴ = λ̃⁴/Lx⁴`: `ω = λ̃² sqrt(D/ρh) / Lx²` (rad/s).
//!
//! # Threading
//! [`RectModes::build`] runs on a worker thread (it uses rayon for the four eigenproblems and
//! the tensor); the result is plain read-only data that a stepper copies or owns. Nothing here
//! is meant to run on the audio thread.

mod airy;
mod beam;
mod coupling;
mod legendre;
mod transverse;

pub use coupling::CouplingTriplets;
pub use transverse::{lowest_modes as transverse_modes, phi_value as transverse_phi};

use crate::error::{check_closed, ParamError};
use crate::modal::basis::{Coordinates, ModalBasis, UnitPoint};
use crate::modal::tensor::CouplingTensor;

/// What to build: geometry, mode counts and (optionally) discretisation overrides.
///
/// Plain data, built and validated on any non-audio thread.
#[derive(Debug, Clone, PartialEq)]
pub struct RectSpec {
    /// `Ly / Lx` (dimensionless), in `[0.05, 20]`.
    pub aspect: f64,
    /// Number of transverse modes `N_Φ`, in `[1, 5000]`.
    pub n_phi: usize,
    /// Number of Airy modes `N_Ψ`, in `[1, 1000]`.
    pub n_psi: usize,
    /// Number of 1D clamped functions along x (both parities together) for the Airy
    /// Rayleigh-Ritz basis, in `[4, 400]`; `None`: chosen from `n_psi` (see [`RectSpec::basis`]).
    pub basis_x: Option<usize>,
    /// Same along y.
    pub basis_y: Option<usize>,
    /// Gauss-Legendre points per direction for the 1D cosine integrals of the tensor, in
    /// `[8, 4000]`; `None`: chosen from the basis size and the highest `m`, `n`.
    pub quad_points: Option<usize>,
}

impl RectSpec {
    /// Spec with automatic discretisation.
    pub fn new(aspect: f64, n_phi: usize, n_psi: usize) -> Self {
        Self {
            aspect,
            n_phi,
            n_psi,
            basis_x: None,
            basis_y: None,
            quad_points: None,
        }
    }

    /// Checks ranges; errors name the field, value and allowed range.
    pub fn validate(&self) -> Result<(), ParamError> {
        check_closed("aspect", self.aspect, 0.05, 20.0)?;
        check_count("n_phi", self.n_phi, 1, 5000)?;
        check_count("n_psi", self.n_psi, 1, 1000)?;
        if let Some(b) = self.basis_x {
            check_count("basis_x", b, 4, 400)?;
        }
        if let Some(b) = self.basis_y {
            check_count("basis_y", b, 4, 400)?;
        }
        if let Some(q) = self.quad_points {
            check_count("quad_points", q, 8, 4000)?;
        }
        Ok(())
    }

    /// The 1D basis sizes `(nx, ny)` used: the overrides, or the automatic rule. The rule
    /// estimates the largest Airy wavenumber from Weyl's law, `ζ ≈ 1.25 sqrt(4π N_Ψ / aspect) + 6`,
    /// and takes `ζ L/2 + 24` polynomials along a side of length `L` (the wavenumber in the
    /// Legendre variable `t ∈ [-1,1]` plus a margin for spectral convergence; validated by the
    /// doubling tests in `tests/plates/modal_rect.rs`).
    pub fn basis(&self) -> (usize, usize) {
        let zeta =
            1.25 * (4.0 * std::f64::consts::PI * self.n_psi as f64 / self.aspect).sqrt() + 6.0;
        let auto = |len: f64| ((zeta * len / 2.0).ceil() as usize + 24).min(400);
        (
            self.basis_x.unwrap_or_else(|| auto(1.0)),
            self.basis_y.unwrap_or_else(|| auto(self.aspect)),
        )
    }
}

fn check_count(field: &str, v: usize, lo: usize, hi: usize) -> Result<usize, ParamError> {
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(ParamError::new(
            field,
            v,
            format!("integer in [{lo}, {hi}]"),
        ))
    }
}

/// Modal data of the simply supported rectangle (in-plane edges free of stress), dimensionless.
///
/// Built on a worker thread by [`RectModes::build`]; afterwards read-only.
#[derive(Debug, Clone)]
pub struct RectModes {
    /// `Ly / Lx` (dimensionless).
    pub aspect: f64,
    /// Transverse `λ² = ω Lx² sqrt(ρh/D)` of each Φ mode, increasing (dimensionless).
    pub lambda2: Vec<f64>,
    /// `(m, n)` half-wave numbers along x and y of each Φ mode.
    pub labels: Vec<(u32, u32)>,
    /// `ζ⁴ Lx⁴` of each Ψ mode, increasing (dimensionless).
    pub zeta4: Vec<f64>,
    /// Parity class of each Ψ mode about the centre lines: `(px, py)`, 0 = even, 1 = odd.
    pub psi_parity: Vec<(u8, u8)>,
    /// Nonzero `H^l_{ij}`, `j ≤ i` (dimensionless; physical `/ Lx⁵`).
    pub coupling: CouplingTensor,
    /// 1D basis sizes `(nx, ny)` used for Ψ.
    pub basis: (usize, usize),
    /// Gauss-Legendre points per direction used for the tensor's 1D integrals.
    pub quad_points: usize,
    airy: airy::AiryModes,
    tables: coupling::CosineTables,
}

impl RectModes {
    /// Computes Φ (closed form), Ψ (Rayleigh-Ritz, four parity classes) and `H`.
    ///
    /// Worker thread only. Measured on the 2-core development machine (release build, machine
    /// shared with other builds): 0.8-1.0 s for `N_Φ = 100`, `N_Ψ = 200` (aspect 1.5) and
    /// 0.5-0.9 s for `N_Φ = 800`, `N_Ψ = 200` (aspect 4/3), mostly the four Airy
    /// eigenproblems. The tensor holds about `N_Ψ N_Φ² / 8` entries of 20 bytes: 16.0 million
    /// (320 MB) for the latter, 0.25 million (5 MB) for the former; specs beyond 4e8 entries
    /// are rejected.
    pub fn build(spec: &RectSpec) -> Result<Self, ParamError> {
        spec.validate()?;
        let aspect = spec.aspect;
        let (nx, ny) = spec.basis();
        let triplets = spec.n_psi as f64 * (spec.n_phi * (spec.n_phi + 1)) as f64 / 8.0;
        if triplets > 4e8 {
            return Err(ParamError::new(
                "n_phi",
                spec.n_phi,
                format!("N_Psi N_Phi^2 / 8 <= 4e8 stored entries (got {triplets:.3e})"),
            ));
        }
        let (labels, lambda2) = transverse::lowest_modes(aspect, spec.n_phi);
        let airy = airy::solve(aspect, nx, ny, spec.n_psi).map_err(|e| match e {
            crate::modal::error::ModalError::Param(p) => p,
            e => ParamError::new(
                "basis_x/basis_y",
                format!("{nx}x{ny}"),
                format!("a basis whose Rayleigh-Ritz problem solves ({e})"),
            ),
        })?;
        let m_max = labels.iter().map(|l| l.0).max().unwrap_or(1) as usize;
        let n_max = labels.iter().map(|l| l.1).max().unwrap_or(1) as usize;
        let quad_points = spec
            .quad_points
            .unwrap_or(nx.max(ny) + 2 * (m_max.max(n_max)) + 40);
        let (coupling, tables) = coupling::build(aspect, &labels, &airy, quad_points)?;
        Ok(Self {
            aspect,
            zeta4: airy.modes.iter().map(|m| m.zeta4).collect(),
            psi_parity: airy
                .modes
                .iter()
                .map(|m| ((m.class / 2) as u8, (m.class % 2) as u8))
                .collect(),
            lambda2,
            labels,
            coupling,
            basis: (nx, ny),
            quad_points,
            airy,
            tables,
        })
    }

    /// `Φ_mode` (dimensionless, normalised on the area `aspect`) at `xi = x/Lx`, `eta = y/Ly`
    /// (both in `[0, 1]`). Physical value: divide by `Lx`. Allocation-free; any thread.
    pub fn phi_at(&self, mode: usize, xi: f64, eta: f64) -> f64 {
        transverse::phi_value(self.aspect, self.labels[mode], xi, eta)
    }

    /// The stored `H^l_{ij}` listed with their row `l` (for inspection and tests; the
    /// schemes use [`Self::coupling`]). Worker thread; allocates.
    pub fn triplets(&self) -> CouplingTriplets {
        CouplingTriplets::from_tensor(&self.coupling)
    }

    /// `[Ψ, Ψ_x, Ψ_y, Ψ_xx, Ψ_yy, Ψ_xy]` of Airy mode `l` at `xi = x/Lx`, `eta = y/Ly`, with
    /// derivatives in the dimensionless coordinates `x = xi`, `y = eta · aspect`. Allocates
    /// scratch: worker thread / tests only.
    pub fn psi_derivs_at(&self, l: usize, xi: f64, eta: f64) -> [f64; 6] {
        let mut s = self.airy.scratch();
        self.airy.derivs(l, xi, eta * self.aspect, &mut s)
    }

    /// `H^l_{ij}` recomputed on demand for either order of `i`, `j` with the same arithmetic
    /// as the stored triplets (so `h_entry(l, i, j) == h_entry(l, j, i)` bitwise and equals
    /// the stored value); exactly 0 when the parity rule forbids the entry. Worker thread.
    pub fn h_entry(&self, l: usize, i: usize, j: usize) -> f64 {
        let (li, lj) = (self.labels[i], self.labels[j]);
        self.tables
            .entry(self.aspect, &self.airy, l, li, lj)
            .expect("labels of this RectModes always fit its tables")
    }

    /// Physical pulsations `ω_k = λ²_k sqrt(D/ρh) / Lx²` (rad/s) for side `lx` (m), bending
    /// stiffness `d` (N·m) and surface density `rho_h` (kg/m²). Any non-audio thread.
    pub fn omega_physical(&self, lx: f64, d: f64, rho_h: f64) -> Result<Vec<f64>, ParamError> {
        crate::error::check_positive("lx", lx)?;
        crate::error::check_positive("d", d)?;
        crate::error::check_positive("rho_h", rho_h)?;
        let c = crate::modal::scaling::pulsation_scale(d, rho_h, lx);
        Ok(self.lambda2.iter().map(|l| l * c).collect())
    }
}

impl ModalBasis for RectModes {
    fn lambda2(&self) -> &[f64] {
        &self.lambda2
    }

    fn zeta4(&self) -> &[f64] {
        &self.zeta4
    }

    fn coordinates(&self) -> Coordinates {
        Coordinates::Sides
    }

    /// `Φ_mode(ξ, η)` with `p = UnitPoint::sides(ξ, η)`.
    fn phi_at(&self, mode: usize, p: UnitPoint) -> f64 {
        RectModes::phi_at(self, mode, p.u, p.v)
    }

    fn coupling(&self) -> &CouplingTensor {
        &self.coupling
    }
}
