//! Parameters of the modal plate model, their validation, and the per-mode coefficients of the
//! linear part of each scheme (θ = 1 or exact, see the derivation in [`super`]).
//!
//! Threads: parameters are built and validated on a worker thread (or the thread parsing a
//! scene); nothing here runs on the audio thread.

use crate::error::{check_non_negative, check_positive, ParamError};
use crate::schemes::two_step::DampedTwoStep;

/// Time scheme of the plate model (see the module documentation of [`super`]).
///
/// Plain `Copy` data, chosen on the control/worker thread at build time.
/// Spelled in scenes and presets as `conservative`, `conservative-exact`, `stormer-verlet` and
/// `sav` ([`PlateScheme::name`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum PlateScheme {
    /// Conservative linearly implicit scheme with the θ = 1 linear part
    /// `δ_tt q_s + ω_s² q_s + c_s δ_{t.} q_s` (Bilbao, Thomas, Touzé, Ducceschi, NMPDE 2015;
    /// SEED 3.1). Energy conserved to round-off; stable iff `h ω_max < 2`.
    #[serde(rename = "conservative")]
    ConservativeTheta1,
    /// Conservative linearly implicit scheme with the exact (damped) modal linear part
    /// (SEED 1.2 / 3.2), written as a θ = 1 scheme with effective `ω̃_s`, `c̃_s`. Modified energy
    /// conserved to round-off; no stability limit on `h` from the linear part.
    #[serde(rename = "conservative-exact")]
    ConservativeExact,
    /// Explicit Störmer-Verlet treatment of the nonlinearity (in-plane amplitudes from `q(n)`
    /// only) with the exact linear part, as in the lecture's gong code. NOT energy conserving.
    #[serde(rename = "stormer-verlet")]
    StormerVerletExact,
    /// Explicit energy-quadratised (scalar auxiliary variable) scheme with the exact linear part
    /// (Bilbao, Ducceschi, Zama, J. Comput. Phys. 2023; see `sav.rs`): a rank-one
    /// (Sherman-Morrison) update per step, no linear solve. Modified energy
    /// `t + v + ψ²/2` conserved to round-off; stable for every `h` (away from `ω_s h = kπ`).
    #[serde(rename = "sav")]
    SavExact,
}

impl PlateScheme {
    /// Every scheme, in the order of the engine's `scheme` parameter.
    pub const ALL: [PlateScheme; 4] = [
        Self::ConservativeTheta1,
        Self::ConservativeExact,
        Self::StormerVerletExact,
        Self::SavExact,
    ];

    /// The scheme's name in scenes, presets and reports.
    pub const fn name(self) -> &'static str {
        match self {
            Self::ConservativeTheta1 => "conservative",
            Self::ConservativeExact => "conservative-exact",
            Self::StormerVerletExact => "stormer-verlet",
            Self::SavExact => "sav",
        }
    }

    /// Whether the linear part is the exact modal scheme (`ω̃_s`, `c̃_s`) rather than θ = 1.
    pub fn exact_linear_part(self) -> bool {
        !matches!(self, Self::ConservativeTheta1)
    }

    /// Whether the scheme conserves its discrete energy exactly (without losses and forcing).
    pub fn is_conservative(self) -> bool {
        !matches!(self, Self::StormerVerletExact)
    }

    /// Whether each step solves the `N_Φ`-dimensional linear system (Woodbury or direct);
    /// false for the explicit schemes (Störmer-Verlet, SAV).
    pub fn solves_linear_system(self) -> bool {
        matches!(self, Self::ConservativeTheta1 | Self::ConservativeExact)
    }
}

/// How the conservative schemes solve their linear system each step (chosen at build time,
/// used on the audio thread). Plain `Copy` data.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinearSolve {
    /// Woodbury when `N_Ψ < N_Φ`, direct otherwise.
    Auto,
    /// Always the Woodbury identity (`N_Ψ × N_Ψ` Cholesky).
    Woodbury,
    /// Always the direct `N_Φ × N_Φ` Cholesky.
    Direct,
}

/// Physical and numerical parameters of a modal von Kármán plate (SEED 3.1).
///
/// Built and validated on a worker thread by [`super::PlateModel::new`].
#[derive(Debug, Clone, PartialEq)]
pub struct PlateParams {
    /// Transverse modal angular frequencies `ω_s` (rad/s), one per mode, each > 0; length `N_Φ`.
    pub omega: Vec<f64>,
    /// In-plane eigenvalues `ζ_l⁴` (1/m⁴, `ΔΔΨ_l = ζ_l⁴ Ψ_l`), each > 0; length `N_Ψ`.
    pub zeta4: Vec<f64>,
    /// Surface density `ρh` (kg/m²), > 0.
    pub rho_h: f64,
    /// Membrane stiffness `Eh` (N/m), > 0.
    pub e_h: f64,
    /// Factor `κ` multiplying every entry of the coupling tensor given to the model
    /// (`H = κ Ĥ`, `E = κ Ê`), ≥ 0 (0 switches the nonlinearity off). With modes normalised to
    /// `∫_S Φ² dS = ∫_S Ψ² dS = 1` on a plate scaled to unit size (radius or side 1), the tensor of
    /// the same shape at size `a` is `Ĥ / a⁵` (each normalised mode brings `1/a`, each second
    /// derivative `1/a²`, `dS` brings `a²`): pass `κ = a⁻⁵` (m⁻⁵) together with `ω_s`, `ζ_l⁴`
    /// of the size-`a` plate.
    pub coupling_scale: f64,
    /// Sampling rate `fs = 1/h` (Hz), > 0.
    pub fs: f64,
    /// Modal damping coefficients `c_s` (1/s) of the term `c_s q̇_s` (`c_s = 2 ξ_s ω_s`), each
    /// ≥ 0; length `N_Φ`. See [`super::excitation::damping_law`] and
    /// [`super::excitation::t60_to_damping`].
    pub damping: Vec<f64>,
    /// Time scheme.
    pub scheme: PlateScheme,
    /// Linear-solver route of the conservative schemes.
    pub solve: LinearSolve,
}

/// Per-mode coefficients of the linear part written as
/// `δ_tt q + ω̃² q + c̃ δ_{t.} q`, i.e. after multiplying by `h²`:
/// `(1 + c̃h/2) q⁺ - (2 - h²ω̃²) q + (1 - c̃h/2) q⁻`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LinearCoefficients {
    /// `ω̃²` (rad²/s²): `ω²` for θ = 1, the exact-scheme value otherwise.
    pub omega_sq: f64,
    /// `c̃` (1/s): `c` for θ = 1, `(2/h) tanh(ch/2)` for the exact scheme.
    pub damping: f64,
}

/// Linear-part coefficients of one mode (`omega` rad/s, `c` 1/s, step `h` s).
///
/// Exact scheme (SEED 1.2, 3.2, with `σ = c/2`): `q⁺ - C q + C̃ q⁻ = 0`. Matching
/// `(1 + c̃h/2) q⁺ - (2 - h²ω̃²) q + (1 - c̃h/2) q⁻ = 0` gives `c̃h/2 = tanh(σh)` and
/// `h²ω̃² = 2 (cosh(σh) - K) / cosh(σh)`: the equivalent centred form `c̃ = 2σ̃`, `ω̃² = Ω̃²` of
/// the shared kernel [`DampedTwoStep`] (evaluated there without cancellation or overflow).
pub(crate) fn linear_coefficients(omega: f64, c: f64, h: f64, exact: bool) -> LinearCoefficients {
    if !exact {
        return LinearCoefficients {
            omega_sq: omega * omega,
            damping: c,
        };
    }
    let k = DampedTwoStep::new(omega, 0.5 * c, h);
    LinearCoefficients {
        omega_sq: k.omega_tilde_sq(),
        damping: 2.0 * k.sigma_tilde(),
    }
}

/// Validated sizes and per-mode linear coefficients of a parameter set.
#[derive(Debug, Clone)]
pub(crate) struct Validated {
    pub h: f64,
    pub linear: Vec<LinearCoefficients>,
}

impl PlateParams {
    /// Checks every field against `n_phi`, `n_psi` (the coupling's sizes) and the scheme's
    /// stability condition, and computes the per-mode linear coefficients.
    pub(crate) fn validate(&self, n_phi: usize, n_psi: usize) -> Result<Validated, ParamError> {
        let fs = check_positive("fs", self.fs)?;
        let h = 1.0 / fs;
        check_positive("rho_h", self.rho_h)?;
        check_positive("e_h", self.e_h)?;
        check_non_negative("coupling_scale", self.coupling_scale)?;
        if self.omega.len() != n_phi || n_phi == 0 {
            return Err(ParamError::new(
                "omega.len",
                self.omega.len(),
                format!("coupling.n_phi() = {n_phi} (>= 1)"),
            ));
        }
        if self.zeta4.len() != n_psi {
            return Err(ParamError::new(
                "zeta4.len",
                self.zeta4.len(),
                format!("coupling.n_psi() = {n_psi}"),
            ));
        }
        if self.damping.len() != n_phi {
            return Err(ParamError::new(
                "damping.len",
                self.damping.len(),
                format!("n_phi = {n_phi}"),
            ));
        }
        for (s, &w) in self.omega.iter().enumerate() {
            check_positive(&format!("omega[{s}]"), w)?;
        }
        for (l, &z) in self.zeta4.iter().enumerate() {
            check_positive(&format!("zeta4[{l}]"), z)?;
        }
        for (s, &c) in self.damping.iter().enumerate() {
            check_non_negative(&format!("damping[{s}]"), c)?;
        }
        let exact = self.scheme.exact_linear_part();
        if !exact {
            // θ = 1: stable (and energy positive) iff h ω_s < 2 for every mode (SEED 1.1, 3.1).
            let (s, wmax) = self
                .omega
                .iter()
                .copied()
                .enumerate()
                .fold((0, 0.0), |acc, (s, w)| if w > acc.1 { (s, w) } else { acc });
            if h * wmax >= 2.0 {
                return Err(ParamError::new(
                    "fs",
                    fs,
                    format!(
                        "fs > omega_max / 2 = {} Hz (θ = 1 stability h ω_max < 2, i.e. fs > π f_max; \
                         omega[{s}] = {wmax} rad/s)",
                        wmax / 2.0
                    ),
                ));
            }
        }
        let mut linear = Vec::with_capacity(n_phi);
        for (s, (&w, &c)) in self.omega.iter().zip(&self.damping).enumerate() {
            let lc = linear_coefficients(w, c, h, exact);
            if exact {
                // The modified energy (ρh/2)[(δ_{t-}q)² + ω̃² q e_{t-}q] is positive definite iff
                // 0 < h²ω̃² < 4; it degenerates when the mode aliases onto Nyquist
                // (cos(ω_d h) = -1, undamped) or onto DC (ω h a non-zero multiple of 2π).
                let x = lc.omega_sq * h * h / 4.0;
                if !x.is_finite() || x >= 1.0 - 1e-12 || (w * h > 3.0 && x < 1e-12) {
                    return Err(ParamError::new(
                        format!("omega[{s}]"),
                        w,
                        format!(
                            "omega * h away from multiples of π (exact scheme energy degenerate at \
                             fs = {fs} Hz: omega[{s}] h = {})",
                            w * h
                        ),
                    ));
                }
            }
            linear.push(lc);
        }
        Ok(Validated { h, linear })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_coefficients_reproduce_the_exact_recursion() {
        // C and C̃ of SEED 3.2 against the θ-form coefficients; 1e-13 relative: a few ulps of
        // transcendental evaluations.
        for &(w, c, h) in &[
            (1.0, 0.0, 0.1),
            (1.0, 0.3, 2.0),
            (5.0, 12.0, 0.05),
            (2.0, 4.0, 0.3),
        ] {
            let lc = linear_coefficients(w, c, h, true);
            let a = 1.0 + lc.damping * h / 2.0;
            let big_c = (2.0 - h * h * lc.omega_sq) / a;
            let small_c = (1.0 - lc.damping * h / 2.0) / a;
            let sigma: f64 = c / 2.0;
            let k = if w > sigma {
                ((w * w - sigma * sigma).sqrt() * h).cos()
            } else {
                ((sigma * sigma - w * w).sqrt() * h).cosh()
            };
            let want_c = 2.0 * (-sigma * h).exp() * k;
            let want_small = (-2.0 * sigma * h).exp();
            assert!(
                (big_c - want_c).abs() < 1e-13 * want_c.abs().max(1.0),
                "{big_c} {want_c}"
            );
            assert!(
                (small_c - want_small).abs() < 1e-13,
                "{small_c} {want_small}"
            );
        }
    }
}
