//! In-place retuning of a built [`PlateModel`]: new physical scalars (size, thickness,
//! material, damping) without a new basis or tensor and without allocating, so the engine can
//! retune a voice on the audio thread (a note's pitch, a size or damping change).
//!
//! The per-mode coefficients are those of [`PlateModel::new`] (same formulas, see
//! [`super::super`]); only the values change, the sizes and the coupling stay.

use super::PlateModel;
use crate::models::plate::coupling::ModalCoupling;
use crate::models::plate::params::linear_coefficients;
use std::fmt;

/// A retune was refused because the new coefficients would make the scheme unstable or its
/// energy degenerate (θ = 1 with `h ω_max ≥ 2`, or an exact-scheme mode with `ω h` on a
/// multiple of `π`). The model is unchanged. Plain `Copy` data (audio thread).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unstable {
    /// Index of the offending mode (`usize::MAX` for a non-finite scalar).
    pub mode: usize,
    /// Its `ω_s h`.
    pub omega_h: f64,
}

impl fmt::Display for Unstable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "retune refused: mode {} would have omega h = {} (unstable or degenerate)",
            self.mode, self.omega_h
        )
    }
}

impl std::error::Error for Unstable {}

impl<C: ModalCoupling + ?Sized> PlateModel<C> {
    /// Replaces the physical coefficients: `omega[s]` (rad/s), `damping[s]` (1/s), `zeta4[l]`
    /// (1/m⁴), `rho_h` (kg/m²), `e_h` (N/m) and the tensor factor `kappa` (see
    /// [`crate::models::plate::PlateParams`]); lengths `N_Φ`, `N_Φ`, `N_Ψ`.
    ///
    /// All checks run before anything is written, so on `Err` the model is unchanged. The
    /// state `q` is kept; the energy accumulators are not rewritten (the discrete energy
    /// changes with the coefficients, so the power balance holds from a retune on, not across
    /// it). Audio thread: no allocation, O(N_Φ + N_Ψ) transcendental evaluations.
    ///
    /// # Panics
    /// If a slice has the wrong length (a programming error of the caller).
    pub fn retune(
        &mut self,
        omega: &[f64],
        damping: &[f64],
        zeta4: &[f64],
        rho_h: f64,
        e_h: f64,
        kappa: f64,
    ) -> Result<(), Unstable> {
        assert_eq!(omega.len(), self.q.len());
        assert_eq!(damping.len(), self.q.len());
        assert_eq!(zeta4.len(), self.b_half.len());
        let h = self.h;
        let bad_scalar = Unstable {
            mode: usize::MAX,
            omega_h: f64::NAN,
        };
        let pos = |x: f64| x.is_finite() && x > 0.0;
        if !(pos(rho_h) && pos(e_h) && kappa.is_finite() && kappa >= 0.0) {
            return Err(bad_scalar);
        }
        if zeta4.iter().any(|&z| !pos(z)) {
            return Err(bad_scalar);
        }
        let exact = self.scheme.exact_linear_part();
        for (s, (&w, &c)) in omega.iter().zip(damping).enumerate() {
            let refuse = Unstable {
                mode: s,
                omega_h: w * h,
            };
            if !(pos(w) && c.is_finite() && c >= 0.0) {
                return Err(refuse);
            }
            if !exact && w * h >= 2.0 {
                return Err(refuse);
            }
            if exact {
                let lc = linear_coefficients(w, c, h, true);
                let x = lc.omega_sq * h * h / 4.0;
                if !x.is_finite() || x >= 1.0 - 1e-12 || (w * h > 3.0 && x < 1e-12) {
                    return Err(refuse);
                }
            }
        }
        self.rho_h = rho_h;
        for s in 0..omega.len() {
            let lc = linear_coefficients(omega[s], damping[s], h, exact);
            self.omega[s] = omega[s];
            self.damping[s] = damping[s];
            self.omega_sq[s] = lc.omega_sq;
            self.c_eff[s] = lc.damping;
            self.a[s] = 1.0 + 0.5 * lc.damping * h;
            self.inv_a[s] = 1.0 / self.a[s];
            self.b[s] = 2.0 - h * h * lc.omega_sq;
            self.d[s] = 1.0 - 0.5 * lc.damping * h;
        }
        self.closure
            .retune(&self.omega, &self.omega_sq, &self.damping, h);
        self.write_closure_coefficients();
        let mut potential_changed = false;
        for (l, &z) in zeta4.iter().enumerate() {
            let dl = kappa * kappa * e_h / (4.0 * rho_h * z);
            self.dh2[l] = h * h * dl;
            self.e_sqrt[l] = h * dl.sqrt();
            let u = e_h * kappa * kappa / (8.0 * z);
            potential_changed |= u != self.u_coef[l];
            self.u_coef[l] = u;
        }
        // The SAV relaxation's target uses the previous step's gradient of `U`: stale once
        // `U` changed (a retune to the same coefficients changes nothing).
        if let Some(sav) = self.sav.as_mut().filter(|_| potential_changed) {
            sav.forget_target();
        }
        Ok(())
    }

    /// The excitation weights `Φ_s(x₀)` (1/m), writable in place (no validation: keep them
    /// finite). Audio thread.
    pub fn force_weights_mut(&mut self) -> &mut [f64] {
        &mut self.force_weights
    }

    /// The excitation weights `Φ_s(x₀)` (1/m). Any thread owning the model.
    pub fn force_weights(&self) -> &[f64] {
        &self.force_weights
    }

    /// The weights of pickup `index` (1/m). Any thread owning the model.
    ///
    /// # Panics
    /// If `index` is not below the number of pickups.
    pub fn pickup_weights(&self, index: usize) -> &[f64] {
        &self.pickups[index].weights
    }

    /// The weights of pickup `index` (1/m), writable in place (keep them finite).
    ///
    /// # Panics
    /// If `index` is not below the number of pickups.
    pub fn pickup_weights_mut(&mut self, index: usize) -> &mut [f64] {
        &mut self.pickups[index].weights
    }

    /// Each mode's continuous damped frequency `√(ω² - c²/4)` against the frequency of the
    /// scheme's linear recursion `q⁺ - (b/a) q + (d/a) q⁻` (Hz; [`crate::analysis::dispersion`]):
    /// identical for the exact linear part, warped for θ = 1. Modes that do not oscillate in
    /// either are left out. Any thread owning the model; allocates.
    pub fn linear_partials(&self) -> Vec<crate::analysis::dispersion::LinearPartial> {
        use crate::analysis::dispersion::{damped_frequency, two_step_frequency, LinearPartial};
        (0..self.q.len())
            .filter_map(|s| {
                let exact = damped_frequency(self.omega[s], 0.5 * self.damping[s])?;
                let sim = two_step_frequency(self.b[s] / self.a[s], self.d[s] / self.a[s], self.h)?;
                Some(LinearPartial {
                    exact_hz: exact / std::f64::consts::TAU,
                    simulated_hz: sim / std::f64::consts::TAU,
                })
            })
            .collect()
    }

    /// The effective linear-part coefficients `(ω̃_s², c̃_s)` (rad²/s², 1/s) of mode `s`.
    pub fn linear_coefficients(&self, s: usize) -> (f64, f64) {
        (self.omega_sq[s], self.c_eff[s])
    }

    /// Physical damping coefficients `c_s` (1/s) in use.
    pub fn damping(&self) -> &[f64] {
        &self.damping
    }

    /// Physical modal angular frequencies `ω_s` (rad/s) in use.
    pub fn omega(&self) -> &[f64] {
        &self.omega
    }
}

#[cfg(test)]
mod tests {
    use crate::models::plate::{DenseCoupling, LinearSolve, PlateModel, PlateParams, PlateScheme};
    use std::sync::Arc;

    fn params(scheme: PlateScheme, scale: f64) -> PlateParams {
        PlateParams {
            omega: vec![1000.0 * scale, 2500.0 * scale, 4000.0 * scale],
            zeta4: vec![50.0, 90.0],
            rho_h: 7.8 * scale,
            e_h: 2e8 * scale,
            coupling_scale: 1.0,
            fs: 44100.0,
            damping: vec![0.5, 1.0, 2.0],
            scheme,
            solve: LinearSolve::Auto,
        }
    }

    fn coupling() -> Arc<DenseCoupling> {
        Arc::new(
            DenseCoupling::from_fn(3, 2, |l, i, j| {
                0.1 * (1 + l + i + j) as f64 / (1 + (i as i64 - j as i64).unsigned_abs()) as f64
            })
            .unwrap(),
        )
    }

    /// A model retuned to parameters P must step exactly (bit for bit) like a model built with
    /// P: the retune writes the same coefficients as `new`.
    #[test]
    fn retune_equals_rebuild() {
        for scheme in [
            PlateScheme::ConservativeTheta1,
            PlateScheme::ConservativeExact,
            PlateScheme::StormerVerletExact,
        ] {
            let c = coupling();
            let target = params(scheme, 1.7);
            let mut built =
                PlateModel::new(&target, c.clone(), vec![1.0, 0.5, 0.2], vec![]).unwrap();
            let mut tuned =
                PlateModel::new(&params(scheme, 1.0), c, vec![1.0, 0.5, 0.2], vec![]).unwrap();
            tuned
                .retune(
                    &target.omega,
                    &target.damping,
                    &target.zeta4,
                    target.rho_h,
                    target.e_h,
                    target.coupling_scale,
                )
                .unwrap();
            for n in 0..200 {
                let f = if n < 20 { 30.0 } else { 0.0 };
                built.step(f).unwrap();
                tuned.step(f).unwrap();
            }
            assert_eq!(built.q(), tuned.q(), "{scheme:?}");
        }
    }

    #[test]
    fn retune_refuses_unstable_theta1() {
        let mut m = PlateModel::new(
            &params(PlateScheme::ConservativeTheta1, 1.0),
            coupling(),
            vec![1.0; 3],
            vec![],
        )
        .unwrap();
        // h ω = 2 · 44100 · 2 / 44100 ≥ 2: refused, model unchanged.
        let e = m
            .retune(
                &[1.0, 2.0, 88200.0],
                &[0.0; 3],
                &[50.0, 90.0],
                1.0,
                1.0,
                1.0,
            )
            .unwrap_err();
        assert_eq!(e.mode, 2);
        assert_eq!(m.omega()[2], 4000.0);
    }
}
