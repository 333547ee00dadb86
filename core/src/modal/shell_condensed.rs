//! The spherical cap's linear stiffness with the in-plane (Airy) problem solved exactly
//! ([`super::CapCoupling::InPlaneExact`]): only the transverse basis is truncated.
//!
//! # Derivation
//!
//! For the cap, `L(Φ_s, w0/h) = -κ ΔΦ_s` (the parent module, "The spherical cap"), and the
//! finite-`N_Ψ` stiffness term `c Σ_l ζ_l⁻⁴ g̃_l[s] g̃_l[t]` (`c = 12(1-ν²)`) of
//! [`super::CapCoupling::Direct`] is the truncated spectral form of
//! `μ ⟨ΔΦ_s, G ΔΦ_t⟩`, `μ = cκ²`, with `G = (ΔΔ)⁻¹` under the conditions the Ψ satisfy
//! (`F = ∂F/∂r = 0` at `r = 1`). Solve `ΔΔF_t = ΔΦ_t` in closed form, one angular order
//! `n` at a time (`Φ_t = R_t(r) cos nθ` or `sin nθ`): `F_t = F_p + (a rⁿ + b rⁿ⁺²) cos nθ` with
//! `ΔF_p = Φ_t` (for `R_t = J_n(λr) + C I_n(λr)`, `F_p = (-J_n(λr) + C I_n(λr))/λ²`, since
//! `Δ_n J_n(λr) = -λ² J_n(λr)` and `Δ_n I_n(λr) = λ² I_n(λr)`). Then
//!
//! ```text
//! ⟨ΔΦ_s, F_t⟩ = ⟨Φ_s, ΔF_t⟩ + ∮ (F_t ∂_r Φ_s - Φ_s ∂_r F_t) = ⟨Φ_s, Φ_t⟩ + 4(n+1) b_t ⟨Φ_s, rⁿ cos nθ⟩
//! ```
//!
//! (the boundary integral vanishes: `F_t = ∂_r F_t = 0`; `Δ(rⁿ⁺² cos nθ) = 4(n+1) rⁿ cos nθ`).
//! The edge conditions give `b_t = (n F_p(1) - F_p'(1))/2` (radial parts), and Green's
//! identity against the harmonic `rⁿ` gives `m_t = ∫₀¹ R_t rⁿ⁺¹ dr = F_p'(1) - n F_p(1)`, so
//! `b_t = -m_t/2`. With `Φ` orthonormal and `e_n = √(2(n+1)/π) rⁿ cos nθ` (unit norm),
//! `p_s = ⟨Φ_s, e_n⟩ = √(2π(n+1)) m_s`, and
//!
//! ```text
//! K_st = λ_s⁴ δ_st + μ (δ_st - p_s p_t)            (s, t of equal n and parity),
//! ```
//!
//! i.e. the curvature stiffens every transverse shape by `μ` except its component along the
//! harmonic `rⁿ cos nθ`, which bends without stretching. This is the Rayleigh-Ritz stiffness of
//! the shallow shell on `span(Φ_1 … Φ_N)` with the in-plane energy exact; its eigenvalues
//! decrease to the exact ones as `N_Φ` grows. `K` is the `N_Ψ → ∞` limit of the
//! [`super::CapCoupling::Direct`] stiffness at fixed `N_Φ` (tested).
//!
//! **Orders 0 and 1.** `r⁰ = 1` and `r cos θ`, `r sin θ` are the free plate's rigid-body modes,
//! to which every elastic Φ is orthogonal, so `p = 0` and `λ⁴ = λ_plate⁴ + μ` exactly (the
//! axisymmetric identity of the shallow-shell literature, here also for one nodal diameter).
//! For `n = 0` the in-plane edge condition is `∂_r F = 0` only and for `n = 1` it is
//! `∂_r F = F`; the free constant (`n = 0`) and `r cos θ` (`n = 1`) of `F` carry no stress,
//! and fixing them to `F(1) = 0` gives the clamped conditions of the Ψ, so the formula holds
//! for every `n`.
//!
//! **Rate in `N_Φ`.** From `ΔΔΦ_s = λ_s⁴ Φ_s`, the free edge and `ΔΔ rⁿ = 0`, `m_s` is
//! `λ_s⁻⁴` times edge terms of order `λ_s`: `p_s = O(λ_s⁻³)`; the shell mode's coordinates
//! decay like `p_s/λ_s⁴ = O(λ_s⁻⁷)`, so the Rayleigh-Ritz error in `λ⁴` is
//! `O(Σ_{s>N} λ_s⁴ λ_s⁻¹⁴) = O(N⁻⁹)` per angular block (`λ_s` grows like `πs`). Measured in
//! `docs/models.md` ("Curved plates: linear modes").
//!
//! `m_s` in closed form: `∫₀¹ J_n(λr) rⁿ⁺¹ dr = J_{n+1}(λ)/λ` and the same for `I` (from
//! `d/dx [xⁿ⁺¹ C_{n+1}(x)] = xⁿ⁺¹ C_n(x)`), with `J_{n+1} = (n/x) J_n - J_n'` and
//! `I_{n+1} = I_n' - (n/x) I_n` (NIST DLMF §10.6 and §10.29); checked against quadrature.
//!
//! Threads: worker thread (allocates).

use crate::modal::circular::bessel::{bessel_i_scaled, bessel_j};
use crate::modal::circular::{PlateModes, RadialFunction};

/// `p_s = ⟨Φ_s, e_n⟩` for every transverse mode of `modes`, `e_n` the unit-norm harmonic
/// `√(2(n+1)/π) rⁿ cos nθ` (or `sin nθ`) of the mode's own order and parity (dimensionless;
/// exactly 0 for `n ≤ 1`, module docs). Worker thread.
pub(super) fn harmonic_overlaps(modes: &PlateModes) -> Vec<f64> {
    modes
        .phi
        .iter()
        .map(|m| {
            if m.n <= 1 {
                0.0
            } else {
                harmonic_overlap(&m.radial)
            }
        })
        .collect()
}

/// `√(2π(n+1)) ∫₀¹ R(r) rⁿ⁺¹ dr` of one normalised radial profile, in closed form (module
/// docs); used as is for `n ≥ 2` (for `n ≤ 1` it is the overlap with a rigid-body mode, zero
/// up to round-off, tested).
pub(super) fn harmonic_overlap(radial: &RadialFunction) -> f64 {
    let (n, x) = (radial.n, radial.lambda);
    let nx = n as f64 / x;
    let (j, dj) = bessel_j(n, x);
    let (i, di) = bessel_i_scaled(n, x);
    // R = N (J_n(λr) + c I_n(λr)/I_n(λ)); I_{n+1}(λ)/I_n(λ) = I_n'/I_n - n/λ (scaling cancels).
    let m = radial.norm * ((nx * j - dj) + radial.c * (di / i - nx)) / x;
    (2.0 * std::f64::consts::PI * (n as f64 + 1.0)).sqrt() * m
}

/// The row-major `N_Φ × N_Φ` stiffness `K_st = λ_s⁴ δ_st + μ (δ_st - p_s p_t)` (entries for
/// equal `n` and parity only; `μ = 12(1-ν²)κ²`; dimensionless, units of `D/(ρh a⁴)`) of the
/// spherical cap of curvature parameter `kappa` (`a²/(R h)`). Worker thread.
pub(super) fn in_plane_exact_stiffness(modes: &PlateModes, kappa: f64) -> Vec<f64> {
    let nu = modes.spec.nu;
    let mu = 12.0 * (1.0 - nu * nu) * kappa * kappa;
    let p = harmonic_overlaps(modes);
    let n_phi = modes.phi.len();
    let mut k = vec![0.0; n_phi * n_phi];
    for (s, ms) in modes.phi.iter().enumerate() {
        k[s * n_phi + s] = modes.lambda2[s] * modes.lambda2[s] + mu;
        if p[s] == 0.0 {
            continue;
        }
        for (t, mt) in modes.phi.iter().enumerate() {
            if mt.n == ms.n && mt.parity == ms.parity {
                k[s * n_phi + t] -= mu * p[s] * p[t];
            }
        }
    }
    k
}

#[cfg(test)]
#[path = "shell_condensed_tests.rs"]
mod tests;
