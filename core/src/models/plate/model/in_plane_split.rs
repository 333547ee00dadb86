//! The in-plane energy of the step just taken, split into the part that is nonlinear in the
//! motion and the whole: what the truncation closure's gate reads ([`super::super::closure`]).
//!
//! With `e_l = Ĥ(r, r)_l - c_l` the in-plane stress coordinates of a curved plate
//! (`super::rest_shape`: `e = 2 Ĥ(a, q) + Ĥ(q, q)`; flat, `e = Ĥ(q, q)`), the potential
//! `U = Σ_l u_l e_l²` holds the curvature's linear stiffness `Σ_l u_l (2 Ĥ(a, q)_l)²`, which a
//! weakly struck shell has at any amplitude, and the cubic and quartic parts that make it
//! nonlinear. Their size, `U_nl = |U - Σ_l u_l λ_l²|` with `λ = 2 Ĥ(a, q)` the linear part of
//! `e`, is the nonlinearity the closure gates on: against the plate's energy it grows as the
//! amplitude squared (flat) or as the amplitude (curved), whatever the strike's spectrum.
//!
//! The schemes hold `e` at slightly different times, which the gate's averaging does not see:
//! the conservative and Störmer-Verlet schemes `b(n+1) = Ĥ(r(n+1), r(n)) - c`, whose linear
//! part is `Ĥ(a, q(n+1) + q(n))`; SAV `Ĥ(r(n), r(n)) - c`, whose linear part is
//! `2 Ĥ(a, q(n))`. Audio thread, no allocation, `O(N_Φ N_Ψ)` for a curved plate (one product
//! with the stored `G(a)`), `O(N_Ψ)` flat.

use super::PlateModel;
use crate::models::plate::coupling::ModalCoupling;

impl<C: ModalCoupling + ?Sized> PlateModel<C> {
    /// `(U_nl, U)` (J) of the step just taken (see the module doc), from `q(n+1)`, `q(n)` and
    /// the scheme's stress coordinates. Audio thread, no allocation.
    pub(super) fn in_plane_split(&mut self) -> (f64, f64) {
        let np = self.b_next.len();
        if np == 0 {
            return (0.0, 0.0);
        }
        let stress: &[f64] = match self.sav.as_ref() {
            Some(sav) => sav.stress(),
            None => &self.b_next,
        };
        let rest = &mut self.rest;
        if rest.on {
            rest.linear_stress.fill(0.0);
            let sav = self.sav.is_some();
            for (s, grow) in rest.g_a.chunks_exact(np).enumerate() {
                let x = if sav {
                    2.0 * self.q[s]
                } else {
                    self.q_next[s] + self.q[s]
                };
                if x != 0.0 {
                    for (lin, &g) in rest.linear_stress.iter_mut().zip(grow) {
                        *lin += g * x;
                    }
                }
            }
        }
        let (mut nonlinear, mut total) = (0.0, 0.0);
        for (l, (&e, &u)) in stress.iter().zip(&self.u_coef).enumerate() {
            let lin = if rest.on { rest.linear_stress[l] } else { 0.0 };
            nonlinear += u * (e * e - lin * lin);
            total += u * e * e;
        }
        (nonlinear.abs(), total)
    }
}
