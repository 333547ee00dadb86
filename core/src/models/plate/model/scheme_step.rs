//! The scheme's own part of a step of [`PlateModel`]: `q(n+1)` from `q(n)`, `q(n-1)` and the
//! scaled force, by the SAV scheme's rank-one update ([`crate::models::plate::sav`]) or the
//! conservative / Störmer-Verlet linearly implicit solve. [`PlateModel::step`] and
//! [`PlateModel::step_with_mallet`] share [`PlateModel::scheme_step`]. Audio thread: no allocation.

use super::PlateModel;
use crate::models::plate::coupling::ModalCoupling;
use crate::models::plate::sav::SavCoefficients;

impl<C: ModalCoupling + ?Sized> PlateModel<C> {
    /// `q(n+1)` into `q_next` by the model's scheme, for `fscale = h² F(n) / ρh`. Errors when
    /// the conservative scheme's linear solve fails. Audio thread: no allocation.
    pub(super) fn scheme_step(&mut self, fscale: f64) -> Result<(), ()> {
        if self.sav_step(fscale) {
            Ok(())
        } else {
            self.linearly_implicit_step(fscale)
        }
    }

    /// The SAV scheme's `q(n+1)` into `q_next` for `fscale = h² F(n) / ρh`, when the model
    /// runs that scheme (returns `false`, doing nothing, otherwise). Audio thread: no
    /// allocation.
    fn sav_step(&mut self, fscale: f64) -> bool {
        let Some(sav) = self.sav.as_mut() else {
            return false;
        };
        let k = SavCoefficients {
            inv_a: &self.inv_a,
            b: &self.b,
            force_weights: &self.force_weights,
            u_coef: &self.u_coef,
            h2_over_rho_h: self.h * self.h / self.rho_h,
        };
        let rest = if self.rest.on {
            self.rest.fill_r(&self.q);
            Some((&self.rest.r[..], &self.rest.c[..]))
        } else {
            None
        };
        sav.step(
            &*self.coupling,
            &k,
            &self.q,
            &self.q_prev,
            rest,
            fscale,
            self.step_dissipated,
            &mut self.q_next,
        );
        true
    }

    /// `q(n+1)` of the conservative (`solver` present) or Störmer-Verlet scheme, and
    /// `Ĥ(q(n+1), q(n))` into `b_next`. `fscale = h² F(n)/ρh`. Errors when the solve fails.
    fn linearly_implicit_step(&mut self, fscale: f64) -> Result<(), ()> {
        let nf = self.q.len();
        let np = self.b_half.len();
        // One pass over the tensor per step: G_{s,l} = Σ_k Ĥ^l_{s,k} r_k(n), r = q(n) + a
        // (`rest_shape`; r = q on a flat plate), and the shift σ = Gᵀa - c.
        let curved = self.rest.on;
        if curved {
            self.rest.fill_r(&self.q);
            self.coupling.coupling_matrix_with_scratch(
                &self.rest.r,
                &mut self.g,
                &mut self.kscratch,
            );
            self.rest.update_shift(&self.g);
        } else {
            self.coupling
                .coupling_matrix_with_scratch(&self.q, &mut self.g, &mut self.kscratch);
        }
        match self.solver.as_mut() {
            None => {
                // Störmer-Verlet: a q⁺ = b q - d q⁻ + h² (p + f(q)), f from η(q(n)) only:
                // h² f_s = Σ_l G_{s,l} (-2 h² D_l) Ĥ(q, q)_l with Ĥ(q, q) = Gᵀ q
                // (curved: Ĥ(r, r) - c = Gᵀ q + σ).
                if curved {
                    self.w.copy_from_slice(&self.rest.shift);
                } else {
                    self.w.fill(0.0);
                }
                for (grow, &qs) in self.g.chunks_exact(np.max(1)).zip(&self.q) {
                    for (wl, &gv) in self.w.iter_mut().zip(grow) {
                        *wl += gv * qs;
                    }
                }
                for (wl, &d) in self.w.iter_mut().zip(&self.dh2) {
                    *wl *= -2.0 * d;
                }
                for s in 0..nf {
                    let grow = &self.g[s * np..(s + 1) * np];
                    let fs: f64 = grow.iter().zip(&self.w).map(|(g, w)| g * w).sum();
                    let rs = self.b[s] * self.q[s] - self.d[s] * self.q_prev[s]
                        + fscale * self.force_weights[s]
                        + fs;
                    self.q_next[s] = rs * self.inv_a[s];
                }
            }
            Some(solver) => {
                // Conservative: (A + h² G D Gᵀ) q⁺ = b q - d q⁻ + h² p - h² G D Ĥ(q, q⁻)
                // (curved: Ĥ(q, q⁻) becomes b(n) + σ, `rest_shape`).
                if curved {
                    for ((b, &sg), w) in self.b_half.iter().zip(&self.rest.shift).zip(&mut self.w) {
                        *w = b + sg;
                    }
                } else {
                    self.w.copy_from_slice(&self.b_half);
                }
                for s in 0..nf {
                    let grow = &self.g[s * np..(s + 1) * np];
                    let nl: f64 = grow
                        .iter()
                        .zip(&self.dh2)
                        .zip(&self.w)
                        .map(|((g, d), b)| g * d * b)
                        .sum();
                    self.r[s] = self.b[s] * self.q[s] - self.d[s] * self.q_prev[s]
                        + fscale * self.force_weights[s]
                        - nl;
                }
                if solver
                    .solve(
                        &self.a,
                        &self.inv_a,
                        &self.g,
                        &self.e_sqrt,
                        &self.r,
                        &mut self.q_next,
                    )
                    .is_err()
                {
                    return Err(());
                }
            }
        }
        // Decayed modes go to exactly zero instead of through the subnormal range (see
        // `FLUSH_TO_ZERO_BELOW`); done before Ĥ(q⁺, q) so the energy stays consistent.
        crate::models::flush_tiny(&mut self.q_next);
        self.update_b_next();
        Ok(())
    }
}
