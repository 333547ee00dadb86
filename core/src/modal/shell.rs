//! Linear modes of a shallow spherical shell with a free edge (a curved circular plate: gongs,
//! cymbals), by projection on the flat plate's modal basis.
//!
//! # Model
//!
//! A static rest shape `w0` turns the von Kármán plate into a shallow shell (Camier, Touzé &
//! Thomas, Eur. J. Mech. A/Solids 28, 2009, eqs. (1)-(2); Thomas, Touzé & Chaigne, Int. J.
//! Solids Struct. 42, 2005, eqs. (1)-(2)):
//!
//! ```text
//! ρh ẅ + D ΔΔw = L(w + w0, F),      ΔΔF = -(Eh/2) [L(w + w0, w + w0) - L(w0, w0)] = -(Eh/2) L(w + 2 w0, w).
//! ```
//!
//! # Derivation of the linear stiffness
//!
//! Start from the crate's modal equations (`crate::models::plate`, Ducceschi & Touzé, JSV 344,
//! 2015, eqs. (13)-(14)), `H = κ_c Ĥ`, `E^s_{k,l} = H^l_{s,k}`:
//! `q̈_s + ω_s² q_s = (1/ρh) Σ_{k,l} H^l_{s,k} q_k η_l`,
//! `η_l = -(Eh/2ζ_l⁴) Σ_{i,j} H^l_{i,j} q_i q_j`. With `w0 = Σ_k a_k Φ_k`, the transverse
//! displacement inside `L` becomes `q + a`: in the Airy source, `(q+a)ᵀH(q+a) - aᵀHa
//! = qᵀHq + 2 qᵀH a`, and in the force `q_k → q_k + a_k`. The terms linear in `q` are
//! `η_l ⊃ -(Eh/ζ_l⁴) g_l·q` and the force `(1/ρh) Σ_l g_l[s] η_l`, with
//! `g_l[s] = Σ_k H^l_{s,k} a_k`; moved to the left-hand side they give the linear stiffness
//!
//! ```text
//! K = diag(ω_s²) + (Eh/ρh) Σ_l ζ_l⁻⁴ g_l g_lᵀ      (symmetric, positive definite).
//! ```
//!
//! (The constant term `(1/ρh) Σ_l g_l[s] η_l(0)` vanishes because `η` has no `q`-free part: the
//! rest shape is stress-free.) Nondimensionalisation, radius `a`: each unit-norm mode brings
//! `1/a`, so `Ĥ_phys = Ĥ/a⁵` (`κ_c = a⁻⁵`), `ζ_phys⁴ = ζ⁴/a⁴`, and the projection of `w0` is
//! `a_k,phys = a · h · ã_k` where `ã_k = ∫_disc (w0/h) Φ_k dS` on the unit disc. Then
//! `K_phys = (D/(ρh a⁴)) [diag(λ_s⁴) + (Eh h²/D) Σ_l ζ_l⁻⁴ g̃_l g̃_lᵀ]`, `g̃_l = Ĥ^l ã`, and
//! `Eh h²/D = 12(1-ν²)`. In the crate's units (`a = D = ρh = 1`, `ω = λ²` flat):
//!
//! ```text
//! K = diag(λ_s⁴) + c Σ_l ζ_l⁻⁴ g̃_l g̃_lᵀ,    c = 12(1-ν²),    ω_shell = sqrt(eig K).
//! ```
//!
//! # The spherical cap
//!
//! A cap of rise `H` over the base radius `a` has curvature radius `R = a²/(2H)` and, in the
//! shallow approximation, `w0 = H(1 - r²/a²)`, i.e. `w0/h = (κ/2)(1 - r²)` on the unit disc with
//! the curvature parameter `κ = a²/(R h) = 2H/h`. `L(w, c r²) = 2c Δw`, which recovers the
//! Donnell-Mushtari-Vlasov shallow shell `D ΔΔw + ΔF/R + ρh ẅ = 0`, `ΔΔF = Eh Δw/R` (up to the
//! sign of `F`) of `scripts/shallow-shell-roots.py`, with `μ = Eh a⁴/(R² D) = 12(1-ν²)κ²`.
//!
//! **Constant and rigid-body parts.** The free plate's basis has no rigid-body modes (1,
//! `r cos θ`, `r sin θ`); every elastic mode is orthogonal to them (`ΔΔ` with free-edge
//! conditions is self-adjoint and they span its kernel). The projection
//! `ã_k = ∫ (w0/h) Φ_k dS` therefore keeps `w0` minus its rigid-body part, which is exact for
//! the coupling: `L(·,·)` involves second derivatives only, so it annihilates affine functions.
//! The constant `κ/2` projects to zero up to quadrature round-off (tested); only the
//! `n = 0` modes receive a nonzero `ã_k` (the cap is axisymmetric).
//!
//! **Convergence.** `r²` does not satisfy the free-edge conditions the modes satisfy
//! (`M_r ∝ w'' + ν w'/r = 2(1+ν) ≠ 0` at `r = 1`), so its modal series converges
//! algebraically, not spectrally. [`CapCoupling::Direct`] computes
//! `g̃_l[s] = ∫ Ψ_l L(Φ_s, w0/h) dS = -κ ∫ Ψ_l ΔΦ_s dS` directly (no truncation of `w0`), which
//! separates the truncation of `w0` from that of the Airy basis, and
//! [`CapCoupling::InPlaneExact`] removes the Airy truncation too (closed-form in-plane solve,
//! `shell_condensed.rs`); measured rates in `docs/models.md` ("Curved plates: linear modes").
//!
//! Threads: everything here runs on a worker thread (allocates, solves eigenproblems).

use super::circular::Parity;
use super::circular::{CircularEdge, PlateModes};
use super::error::ModalError;
use super::quadrature::GaussLegendre;
use crate::error::{check_closed, check_positive, ParamError};
use faer::{Mat, Side};

/// A static rest shape `w0` of a free-edge circular plate (the "imperfection" that makes it a
/// shallow shell).
///
/// Plain data, built from user input on any thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Imperfection {
    /// Spherical cap `w0/h = (κ/2)(1 - r²)` on the unit disc, `κ = a²/(R h) = 2H/h`
    /// (dimensionless curvature parameter, in `[0, 1000]`).
    SphericalCap {
        /// Curvature parameter `κ = a²/(R h)` (dimensionless).
        kappa: f64,
    },
}

/// Largest accepted curvature parameter `κ` (a cap rising 500 thicknesses: far outside the
/// shallow-shell range of real gongs, `κ` of a few tens).
pub const MAX_KAPPA: f64 = 1000.0;

impl Imperfection {
    /// A spherical cap of curvature parameter `kappa = a²/(R h)` (dimensionless, in
    /// `[0, MAX_KAPPA]`; 0 is the flat plate).
    pub fn spherical_cap(kappa: f64) -> Result<Self, ParamError> {
        check_closed("kappa", kappa, 0.0, MAX_KAPPA)?;
        Ok(Self::SphericalCap { kappa })
    }

    /// A spherical cap of rise `rise` (m, ≥ 0) over a plate of radius `radius` (m, > 0) and
    /// thickness `thickness` (m, > 0): `κ = 2 rise / thickness`.
    pub fn from_rise(rise: f64, radius: f64, thickness: f64) -> Result<Self, ParamError> {
        check_positive("radius", radius)?;
        check_positive("thickness", thickness)?;
        check_closed("rise", rise, 0.0, 0.5 * MAX_KAPPA * thickness)?;
        Self::spherical_cap(2.0 * rise / thickness)
    }

    /// A spherical cap of curvature radius `curvature_radius` (m, > 0) over a plate of radius
    /// `radius` (m, > 0) and thickness `thickness` (m, > 0): `κ = a²/(R h)`, rise `a²/(2R)`.
    pub fn from_curvature_radius(
        curvature_radius: f64,
        radius: f64,
        thickness: f64,
    ) -> Result<Self, ParamError> {
        check_positive("curvature_radius", curvature_radius)?;
        check_positive("radius", radius)?;
        check_positive("thickness", thickness)?;
        let kappa = radius * radius / (curvature_radius * thickness);
        if kappa > MAX_KAPPA {
            return Err(ParamError::new(
                "curvature_radius",
                curvature_radius,
                format!(
                    "at least radius²/({MAX_KAPPA} thickness) = {}",
                    radius * radius / (MAX_KAPPA * thickness)
                ),
            ));
        }
        Self::spherical_cap(kappa)
    }

    /// The curvature parameter `κ = a²/(R h)` (dimensionless).
    pub fn kappa(&self) -> f64 {
        match *self {
            Self::SphericalCap { kappa } => kappa,
        }
    }

    /// The rest shape in thickness units, `w0(r)/h` at the dimensionless radius `r ∈ [0, 1]`.
    pub fn profile(&self, r: f64) -> f64 {
        0.5 * self.kappa() * (1.0 - r * r)
    }

    /// The modal coordinates `ã_k = ∫_disc (w0/h) Φ_k dS` on the transverse basis of `modes`
    /// (dimensionless; length `N_Φ`; zero except for the `n = 0` modes), by a Gauss-Legendre
    /// radial quadrature of `32 + 2⌈λ_max⌉` points (the integrand is a quadratic times a
    /// profile oscillating at `λ_max`; doubling it changes `ã` by round-off, tested).
    /// Worker thread.
    pub fn project(&self, modes: &PlateModes) -> Vec<f64> {
        let lam_max = modes
            .phi
            .iter()
            .map(|m| m.radial.lambda)
            .fold(0.0, f64::max);
        self.project_with(modes, 32 + 2 * lam_max.ceil() as usize)
    }

    /// [`Self::project`] with an explicit number of radial quadrature points (in `[1, 65536]`;
    /// larger values are clamped). Worker thread.
    pub fn project_with(&self, modes: &PlateModes, points: usize) -> Vec<f64> {
        let rule = GaussLegendre::new(points.clamp(1, GaussLegendre::MAX_POINTS))
            .expect("clamped to the valid range");
        modes
            .phi
            .iter()
            .map(|m| {
                if m.n != 0 || m.parity != Parity::Cos {
                    return 0.0; // ∫ cos nθ dθ = ∫ sin nθ dθ = 0 for n ≥ 1
                }
                let radial: f64 = rule
                    .nodes
                    .iter()
                    .zip(&rule.weights)
                    .map(|(&r, &w)| w * self.profile(r) * m.radial.eval(r)[0] * r)
                    .sum();
                2.0 * std::f64::consts::PI * radial
            })
            .collect()
    }
}

/// How the coupling vectors `g̃_l` of a spherical cap are computed.
///
/// Plain data, any thread.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CapCoupling {
    /// `g̃_l[s] = Σ_k Ĥ^l_{s,k} ã_k` from the coupling tensor and the projection of `w0` on the
    /// `N_Φ` transverse modes (the route any rest shape can take).
    ModalProjection,
    /// `g̃_l[s] = ∫ Ψ_l L(Φ_s, w0/h) dS = -κ ∫ Ψ_l ΔΦ_s dS` by radial quadrature (exact for the
    /// cap: no truncation of `w0`; a diagnostic of the projection's convergence).
    Direct,
    /// The cap with the in-plane problem solved in closed form (the `N_Ψ → ∞` limit of
    /// [`Self::Direct`]): `K = diag(λ_s⁴) + μ(I - p pᵀ)` per angular block, `μ = 12(1-ν²)κ²`,
    /// `p_s` the overlap of `Φ_s` with the unit harmonic `rⁿ cos nθ` (zero for `n ≤ 1`); only
    /// `N_Φ` is truncated (derivation in `shell_condensed.rs`).
    InPlaneExact,
}

/// One linear mode of the shell.
///
/// Plain data, any thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShellMode {
    /// Angular order `n` (nodal diameters).
    pub n: u32,
    /// Angular factor of the block (`cos nθ` or `sin nθ`).
    pub parity: Parity,
    /// Label `k`: position in its `(n, parity)` block, counted as the flat plate's nodal
    /// circles (the free plate's `n = 0, 1` start at 1).
    pub k: u32,
    /// Dimensionless pulsation `ω a² √(ρh/D)` (`λ²` of the flat plate at `κ = 0`).
    pub lambda2: f64,
}

/// The linear stiffness `K` (row-major `N_Φ × N_Φ`, dimensionless, units of `D/(ρh a⁴)`) of
/// the shell `imperfection` on the transverse and in-plane bases of `modes` (free edge):
/// `K = diag(λ_s⁴) + 12(1-ν²) Σ_l ζ_l⁻⁴ g̃_l g̃_lᵀ` (module docs; with
/// [`CapCoupling::InPlaneExact`], its `N_Ψ → ∞` limit). Worker thread.
pub fn shell_stiffness(
    modes: &PlateModes,
    imperfection: &Imperfection,
    how: CapCoupling,
) -> Result<Vec<f64>, ParamError> {
    if modes.spec.edge != CircularEdge::Free {
        return Err(ParamError::new(
            "spec.edge",
            modes.spec.edge.name(),
            "free (the shell model assumes a free edge)",
        ));
    }
    let (n_phi, n_psi) = (modes.phi.len(), modes.psi.len());
    let g = match how {
        CapCoupling::ModalProjection => {
            let a = imperfection.project(modes);
            let mut g = vec![0.0; n_phi * n_psi];
            modes.coupling.coupling_matrix(&a, &mut g);
            g
        }
        CapCoupling::Direct => direct_coupling(modes, imperfection),
        CapCoupling::InPlaneExact => {
            return Ok(condensed::in_plane_exact_stiffness(
                modes,
                imperfection.kappa(),
            ))
        }
    };
    let c = 12.0 * (1.0 - modes.spec.nu * modes.spec.nu);
    let mut k = vec![0.0; n_phi * n_phi];
    for s in 0..n_phi {
        k[s * n_phi + s] = modes.lambda2[s] * modes.lambda2[s];
    }
    for (l, &z4) in modes.zeta4.iter().enumerate() {
        let w = c / z4;
        for s in 0..n_phi {
            let gs = g[s * n_psi + l];
            if gs == 0.0 {
                continue;
            }
            for t in 0..n_phi {
                k[s * n_phi + t] += w * gs * g[t * n_psi + l];
            }
        }
    }
    Ok(k)
}

/// `g[s * N_Ψ + l] = -κ ∫ Ψ_l ΔΦ_s dS` (nonzero only for equal `n` and parity), by a
/// Gauss-Legendre radial quadrature of `64 + 2⌈λ_max + ζ_max⌉` points.
fn direct_coupling(modes: &PlateModes, imperfection: &Imperfection) -> Vec<f64> {
    let (n_phi, n_psi) = (modes.phi.len(), modes.psi.len());
    let top = |v: &[super::circular::Mode]| v.iter().map(|m| m.radial.lambda).fold(0.0, f64::max);
    let points = 64 + 2 * (top(&modes.phi) + top(&modes.psi)).ceil() as usize;
    let rule = GaussLegendre::new(points.min(GaussLegendre::MAX_POINTS)).expect("valid size");
    let kappa = imperfection.kappa();
    let mut g = vec![0.0; n_phi * n_psi];
    for (s, ms) in modes.phi.iter().enumerate() {
        let nf = ms.n as f64;
        for (l, ml) in modes.psi.iter().enumerate() {
            if ml.n != ms.n || ml.parity != ms.parity {
                continue;
            }
            let radial: f64 = rule
                .nodes
                .iter()
                .zip(&rule.weights)
                .map(|(&r, &w)| {
                    let [f, f1, f2] = ms.radial.eval(r);
                    let lap = f2 + f1 / r - nf * nf * f / (r * r);
                    w * ml.radial.eval(r)[0] * lap * r
                })
                .sum();
            let angular = if ms.n == 0 {
                2.0 * std::f64::consts::PI
            } else {
                std::f64::consts::PI
            };
            g[s * n_psi + l] = -kappa * angular * radial;
        }
    }
    g
}

/// The shell's linear modes: the eigenvalues of [`shell_stiffness`] block by block (`K` couples
/// only modes of equal `n` and parity: the cap is axisymmetric, and the coupling tensor's
/// selection rules make every other entry exactly zero), `λ² = sqrt(eig)`, sorted by `(n,
/// parity, k)`. A block whose off-diagonal entries are all zero (every block at `κ = 0`) is
/// read off its diagonal. Worker thread.
pub fn shell_modes(
    modes: &PlateModes,
    imperfection: &Imperfection,
    how: CapCoupling,
) -> Result<Vec<ShellMode>, ModalError> {
    let k = shell_stiffness(modes, imperfection, how)?;
    let n_phi = modes.phi.len();
    let mut keys: Vec<(u32, Parity)> = modes.phi.iter().map(|m| (m.n, m.parity)).collect();
    keys.sort();
    keys.dedup();
    let mut out = Vec::with_capacity(n_phi);
    for (n, parity) in keys {
        let idx: Vec<usize> = (0..n_phi)
            .filter(|&s| modes.phi[s].n == n && modes.phi[s].parity == parity)
            .collect();
        let m = idx.len();
        let block = Mat::<f64>::from_fn(m, m, |r, c| k[idx[r] * n_phi + idx[c]]);
        let diagonal = (0..m).all(|r| (0..m).all(|c| r == c || block[(r, c)] == 0.0));
        let mut eig: Vec<f64> = if diagonal {
            (0..m).map(|r| block[(r, r)]).collect()
        } else {
            let evd =
                block
                    .self_adjoint_eigen(Side::Lower)
                    .map_err(|e| ModalError::Eigensolver {
                        problem: "shell stiffness",
                        class: None,
                        detail: format!("{e:?}"),
                    })?;
            let s = evd.S().column_vector();
            (0..m).map(|r| s[r]).collect()
        };
        eig.sort_by(f64::total_cmp);
        let offset = u32::from(n <= 1);
        for (j, e) in eig.into_iter().enumerate() {
            out.push(ShellMode {
                n,
                parity,
                k: j as u32 + offset,
                lambda2: e.max(0.0).sqrt(),
            });
        }
    }
    Ok(out)
}

#[path = "shell_condensed.rs"]
mod condensed;

#[cfg(test)]
#[path = "shell_tests.rs"]
mod tests;
