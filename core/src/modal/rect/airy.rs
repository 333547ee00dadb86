//! In-plane (Airy stress function) modes of the rectangle with edges free of in-plane stress:
//! `ΔΔΨ = ζ⁴ Ψ` on `[0, 1] × [0, aspect]`, `Ψ = ∂Ψ/∂n = 0` on the four edges (the
//! clamped-plate eigenproblem; Ducceschi & Touzé, JSV 344, 2015, sec. 2; no closed form).
//!
//! Rayleigh-Ritz (Galerkin) on the tensor basis `X_p(x) Y_q(y)` of 1D clamped functions
//! ([`super::beam`]), weak form `∫ ΔΨ Δv dS = ζ⁴ ∫ Ψ v dS` for all admissible `v`. With
//! `L²`-orthonormal 1D bases the mass matrix is the identity and the stiffness is
//! `K = Kx ⊗ I + I ⊗ Ky + 2 Cx ⊗ Cy` (`Kx = ∫X''X''`, `Cx = ∫X'X'`; the cross terms follow from
//! `∫X X'' = -∫X'X'` since `X' = 0` at the ends), a standard symmetric eigenproblem solved with
//! faer's self-adjoint eigensolver. The operator commutes with the reflections about the
//! centre lines, so the problem splits into four parity classes (even/odd in x, even/odd in y),
//! each an independent eigenproblem a quarter of the size.
//!
//! Built on a worker thread (classes solved in parallel with rayon), never on the audio thread.

use super::beam::{ClampedBasis1d, Scratch};
use crate::error::ParamError;
use crate::modal::error::ModalError;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_upper_triangular_in_place,
};
use faer::{Mat, Side};
use rayon::prelude::*;

/// One computed Airy mode: its parity class and coefficients in that class's tensor basis.
#[derive(Debug, Clone)]
pub(crate) struct AiryMode {
    /// `ζ⁴` (dimensionless).
    pub zeta4: f64,
    /// Parity class `2 px + py` (0: even-even ... 3: odd-odd about the centre lines).
    pub class: usize,
    /// Coefficients `c[p ny + q]` of `X_p(x) Y_q(y)`, `ny` = y basis size of parity `py`.
    pub coef: Vec<f64>,
}

/// The 1D bases (by parity) and the selected 2D modes.
#[derive(Debug, Clone)]
pub(crate) struct AiryModes {
    /// `bx[px]`: x basis of parity px on `[0, 1]`.
    pub bx: [ClampedBasis1d; 2],
    /// `by[py]`: y basis of parity py on `[0, aspect]`.
    pub by: [ClampedBasis1d; 2],
    /// Modes sorted by `ζ⁴` (ties by class).
    pub modes: Vec<AiryMode>,
}

/// Solves the four parity classes with `nx` (resp. `ny`) 1D functions per direction (split as
/// evenly as possible between the two parities) and keeps the lowest `n_psi` modes.
pub(crate) fn solve(
    aspect: f64,
    nx: usize,
    ny: usize,
    n_psi: usize,
) -> Result<AiryModes, ModalError> {
    let split = |n: usize| [n.div_ceil(2), n / 2];
    let (sx, sy) = (split(nx), split(ny));
    let bx = [
        ClampedBasis1d::new(1.0, 0, sx[0])?,
        ClampedBasis1d::new(1.0, 1, sx[1])?,
    ];
    let by = [
        ClampedBasis1d::new(aspect, 0, sy[0])?,
        ClampedBasis1d::new(aspect, 1, sy[1])?,
    ];
    let classes: Vec<Result<Vec<AiryMode>, ModalError>> = (0..4usize)
        .into_par_iter()
        .map(|class| solve_class(&bx[class / 2], &by[class % 2], class))
        .collect();
    let mut modes = Vec::new();
    for c in classes {
        modes.extend(c?);
    }
    if modes.len() < n_psi {
        return Err(ParamError::new(
            "n_psi",
            n_psi,
            format!(
                "at most {} Airy modes with the basis {nx} x {ny} (basis_x x basis_y)",
                modes.len()
            ),
        )
        .into());
    }
    modes.sort_by(|a, b| a.zeta4.total_cmp(&b.zeta4).then(a.class.cmp(&b.class)));
    modes.truncate(n_psi);
    Ok(AiryModes { bx, by, modes })
}

fn solve_class(
    bx: &ClampedBasis1d,
    by: &ClampedBasis1d,
    class: usize,
) -> Result<Vec<AiryMode>, ModalError> {
    let (nx, ny) = (bx.len_basis(), by.len_basis());
    let n = nx * ny;
    let kfn = |r: usize, c: usize| {
        let (p, q) = (r / ny, r % ny);
        let (pp, qq) = (c / ny, c % ny);
        let mut v = 2.0 * bx.grad[p * nx + pp] * by.grad[q * ny + qq];
        if q == qq {
            v += bx.stiff[p * nx + pp];
        }
        if p == pp {
            v += by.stiff[q * ny + qq];
        }
        v
    };
    // K spans ζ⁴ from ~10³ to ~10¹³ (the top polynomial modes), so a direct eigensolve would
    // give the low modes only an absolute accuracy eps·|K|. Instead: scale K by its diagonal,
    // D = diag(K)^(-1/2), K̃ = D K D (well conditioned), K̃ = L̃ L̃ᵀ, and solve the inverse
    // problem S y = μ y with S = L̃⁻¹ D² L̃⁻ᵀ, μ = 1/ζ⁴, c = D L̃⁻ᵀ y / sqrt(μ). The wanted low
    // modes are the largest μ, accurate relative to |S| = μ_max.
    let dsc: Vec<f64> = (0..n).map(|r| 1.0 / kfn(r, r).sqrt()).collect();
    let kt = Mat::<f64>::from_fn(n, n, |r, c| kfn(r, c) * dsc[r] * dsc[c]);
    let llt = kt
        .llt(Side::Lower)
        .map_err(|_| ModalError::NotPositiveDefinite {
            matrix: "Airy stiffness",
            class: Some(class),
        })?;
    let l = llt.L();
    let par = faer::get_global_parallelism();
    let mut z = Mat::<f64>::from_fn(n, n, |r, c| if r == c { dsc[r] } else { 0.0 });
    solve_lower_triangular_in_place(l, z.as_mut(), par);
    let s = &z * z.transpose();
    let evd = s
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| ModalError::Eigensolver {
            problem: "Airy",
            class: Some(class),
            detail: format!("{e:?}"),
        })?;
    let mu = evd.S().column_vector();
    let mut x = evd.U().to_owned();
    solve_upper_triangular_in_place(l.transpose(), x.as_mut(), par);
    let mu_max = mu[n - 1];
    let mut out = Vec::with_capacity(n);
    for col in (0..n).rev() {
        // Eigenvalues below 1e-12 μ_max carry no correct digit (spurious top modes): drop.
        if mu[col].partial_cmp(&(1e-12 * mu_max)) != Some(std::cmp::Ordering::Greater) {
            break;
        }
        let mut coef: Vec<f64> = (0..n).map(|r| x[(r, col)] * dsc[r]).collect();
        let norm = coef.iter().map(|c| c * c).sum::<f64>().sqrt();
        // Sign convention: the largest coefficient is positive (first one on ties).
        let mut big = 0.0f64;
        for &c in &coef {
            if c.abs() > big.abs() {
                big = c;
            }
        }
        let scale = big.signum() / norm;
        coef.iter_mut().for_each(|c| *c *= scale);
        out.push(AiryMode {
            zeta4: 1.0 / mu[col],
            class,
            coef,
        });
    }
    Ok(out)
}

/// Scratch buffers to evaluate Airy modes at points.
pub(crate) struct AiryScratch {
    sx: [Scratch; 2],
    sy: [Scratch; 2],
    fx: [[Vec<f64>; 3]; 2],
    fy: [[Vec<f64>; 3]; 2],
}

impl AiryModes {
    /// Scratch for [`Self::derivs`].
    pub fn scratch(&self) -> AiryScratch {
        let v = |b: &ClampedBasis1d| {
            let n = b.len_basis();
            [vec![0.0; n], vec![0.0; n], vec![0.0; n]]
        };
        AiryScratch {
            sx: [self.bx[0].scratch(), self.bx[1].scratch()],
            sy: [self.by[0].scratch(), self.by[1].scratch()],
            fx: [v(&self.bx[0]), v(&self.bx[1])],
            fy: [v(&self.by[0]), v(&self.by[1])],
        }
    }

    /// `[Ψ, Ψ_x, Ψ_y, Ψ_xx, Ψ_yy, Ψ_xy]` of mode `l` at dimensionless `(x, y)`.
    pub fn derivs(&self, l: usize, x: f64, y: f64, s: &mut AiryScratch) -> [f64; 6] {
        let mode = &self.modes[l];
        let (px, py) = (mode.class / 2, mode.class % 2);
        let [f, df, ddf] = &mut s.fx[px];
        self.bx[px].eval(x, &mut s.sx[px], f, df, ddf);
        let [g, dg, ddg] = &mut s.fy[py];
        self.by[py].eval(y, &mut s.sy[py], g, dg, ddg);
        let ny = g.len();
        let mut out = [0.0; 6];
        for p in 0..f.len() {
            let row = &mode.coef[p * ny..(p + 1) * ny];
            let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
            for q in 0..ny {
                a += row[q] * g[q];
                b += row[q] * dg[q];
                c += row[q] * ddg[q];
            }
            out[0] += f[p] * a;
            out[1] += df[p] * a;
            out[2] += f[p] * b;
            out[3] += ddf[p] * a;
            out[4] += f[p] * c;
            out[5] += df[p] * b;
        }
        out
    }
}
