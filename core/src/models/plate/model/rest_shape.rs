//! The plate's static rest shape `w0 = Σ_k a_k Φ_k` (an "imperfection"): a curved plate, i.e. a
//! shallow shell (gongs with a dome or a boss, cymbals).
//!
//! # Model
//!
//! Camier, Touzé & Thomas (Eur. J. Mech. A/Solids 28, 2009, eqs. (1)-(2)); Thomas, Touzé &
//! Chaigne (Int. J. Solids Struct. 42, 2005): `ρh ẅ + DΔΔw = L(w + w0, F)`,
//! `ΔΔF = -(Eh/2)[L(w + w0, w + w0) - L(w0, w0)]`. In the modal form of [`super::super`] the
//! displacement inside `L` becomes `r = q + a` and the Airy source loses the rest shape's own
//! part, `c_l = Ĥ(a, a)_l` (the rest shape is stress-free):
//!
//! ```text
//! q̈_s + ω_s² q_s + c_s q̇_s = (κ/ρh) Σ_{k,l} Ĥ^l_{s,k} r_k η_l + p_s,
//! η_l = -(Eh κ / 2ζ_l⁴) (Ĥ(r, r)_l - c_l) = -(Eh κ / 2ζ_l⁴) (Ĥ(q, q)_l + 2 Ĥ(a, q)_l).
//! ```
//!
//! The potential `U = Σ_l u_l (Ĥ(r,r)_l - c_l)²` now has a quadratic part (the curvature's
//! linear stiffness, which raises the modes with nodal circles: `crate::modal::shell`), a cubic
//! part (the quadratic forces `L(w0, F(q,q))` and `L(q, F(q, w0))` that make a shell soften)
//! and the flat plate's quartic part; it is still a sum of squares, `U ≥ 0`.
//!
//! # Schemes
//!
//! Every scheme of [`super::super`] carries over with `q → r` inside the coupling and
//! `Ĥ(·,·) → Ĥ(·,·) - c`: the conservative schemes take `b_l(n) = Ĥ(r(n), r(n-1))_l - c_l`,
//! and since `r(n+1) - r(n-1) = q(n+1) - q(n-1)`,
//! `b_l(n+1) - b_l(n) = Ĥ(r(n), q(n+1) - q(n-1))_l = 2h Σ_s G_{s,l} δ_{t.}q_s` with
//! `G_{s,l} = Σ_k Ĥ^l_{s,k} r_k(n)`: the energy proof of the flat plate holds word for word
//! (the same `t + v + u`, `u = Σ u_l b_l²`). The update keeps its matrix `A + h² G D Gᵀ`
//! (with `G` from `r`); `b(n+1) = Gᵀ q(n+1) + σ` with the shift `σ = Gᵀ a - c`, so the
//! right-hand side takes `b(n) + σ` where the flat plate has `b(n)`. Störmer-Verlet uses
//! `η(n) ∝ Gᵀ q(n) + σ`; SAV takes `U` and `∇U_s = Σ_l 4 u_l (Ĥ(r,r)_l - c_l) Σ_k Ĥ^l_{s,k} r_k`.
//! The curvature's stiffness is then integrated like the nonlinearity: implicitly by the
//! conservative schemes (a trapezoid-like `O(h²)` frequency warping of the shell's linear
//! modes, measured in the tests), explicitly by Störmer-Verlet (whose stability limit the
//! shell's highest linear frequency now sets) and by SAV.
//!
//! Threads: [`PlateModel::set_rest_shape`] runs on the thread that owns the model (three
//! tensor passes, no allocation); the per-step helpers run on the audio thread.

use super::PlateModel;
use crate::error::{check_finite, ParamError};
use crate::models::plate::coupling::ModalCoupling;

impl<C: ModalCoupling + ?Sized> PlateModel<C> {
    /// Sets the static rest shape `w0 = Σ_k a_k Φ_k` (`a` in units of `q`, m², length `N_Φ`;
    /// all zeros for the flat plate, which then runs exactly the flat plate's arithmetic).
    /// The state `q` (the motion about the rest shape) is kept and the stored energy
    /// recomputed; the accumulators are not rewritten, so, as with a retune, the power
    /// balance holds from the change on. Errors: length or a non-finite entry (field
    /// `rest_shape`); on error the model is unchanged. The thread that owns the model: three
    /// passes over the coupling tensor (`c`, `G(a)` and the state's `b`), no allocation.
    pub fn set_rest_shape(&mut self, a: &[f64]) -> Result<(), ParamError> {
        let nf = self.q.len();
        if a.len() != nf {
            return Err(ParamError::new(
                "rest_shape.len",
                a.len(),
                format!("n_phi = {nf}"),
            ));
        }
        // The field name is formatted on the error path only (the success path allocates
        // nothing: the engine calls this on the audio thread).
        if let Some(k) = a.iter().position(|x| !x.is_finite()) {
            check_finite(&format!("rest_shape[{k}]"), a[k])?;
        }
        let rest = &mut self.rest;
        rest.a.copy_from_slice(a);
        rest.on = a.iter().any(|&x| x != 0.0) && !rest.c.is_empty();
        if rest.on {
            self.coupling.contract_eta_with_scratch(
                &rest.a,
                &rest.a,
                &mut rest.c,
                &mut self.kscratch,
            );
            self.coupling
                .coupling_matrix_with_scratch(&rest.a, &mut rest.g_a, &mut self.kscratch);
        } else {
            rest.c.fill(0.0);
            rest.g_a.fill(0.0);
        }
        rest.shift.fill(0.0);
        self.closure.set_gated(self.rest.on);
        self.refresh_b_half();
        if let Some(sav) = self.sav.as_mut() {
            sav.restart(super::SavStep::psi_from(&self.u_coef, &self.b_half));
        }
        if self.track_energy {
            self.update_stored_energy(false);
        }
        Ok(())
    }

    /// The rest shape's modal coordinates `a_k` (m²), `None` for a flat plate. Any thread
    /// owning the model.
    pub fn rest_shape(&self) -> Option<&[f64]> {
        self.rest.on.then_some(&self.rest.a[..])
    }

    /// `out = Ĥ(q(n) + a, q(n-1) + a) - c` (or `Ĥ(q(n), q(n-1))` flat): the conservative
    /// schemes' `b(n)` from the state, into `b_half`. Uses `f` as scratch.
    pub(super) fn refresh_b_half(&mut self) {
        if !self.rest.on {
            self.coupling.contract_eta_with_scratch(
                &self.q,
                &self.q_prev,
                &mut self.b_half,
                &mut self.kscratch,
            );
            return;
        }
        self.rest.fill_r(&self.q);
        for ((f, &q), &a) in self.f.iter_mut().zip(&self.q_prev).zip(&self.rest.a) {
            *f = q + a;
        }
        self.coupling.contract_eta_with_scratch(
            &self.rest.r,
            &self.f,
            &mut self.b_half,
            &mut self.kscratch,
        );
        for (b, &c) in self.b_half.iter_mut().zip(&self.rest.c) {
            *b -= c;
        }
    }

    /// `self.f = scale · h² Σ_l G_{s,l}(r) (-2 D_l) (Ĥ(r,r)_l - c_l)` at `r = q(n) + a`: the
    /// Störmer-Verlet nonlinear acceleration times `h² · scale` (used by [`Self::set_state`];
    /// `step` goes through `G` instead).
    pub(super) fn nonlinear_force(&mut self, scale: f64) {
        if self.w.is_empty() {
            self.f.fill(0.0);
            return;
        }
        let point: &[f64] = if self.rest.on {
            self.rest.fill_r(&self.q);
            &self.rest.r
        } else {
            &self.q
        };
        self.coupling
            .contract_eta_with_scratch(point, point, &mut self.w, &mut self.kscratch);
        for ((w, &d), &c) in self.w.iter_mut().zip(&self.dh2).zip(&self.rest.c) {
            *w = (*w - c) * (-2.0 * d * scale);
        }
        self.coupling
            .apply_force_with_scratch(point, &self.w, &mut self.f, &mut self.kscratch);
    }
}
