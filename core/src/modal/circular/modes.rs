//! The modes of a circular plate, enumerated: transverse modes Φ (`ΔΔw = λ⁴ w` with the
//! plate's edge) and in-plane modes Ψ (clamped conditions), each a radial function times
//! `cos nθ` or `sin nθ`, in dimensionless units (radius `a = 1`).
//!
//! Conventions (those of [`super::basis`], which builds a basis from these modes and their
//! coupling tensor):
//! - `n` nodal diameters, `k` interior nodal circles (Leissa 1969 labelling; the free plate's
//!   `n = 0, 1` elastic modes start at `k = 1` because `(0,0)` and `(1,0)` are its rigid-body
//!   modes, which are excluded);
//! - cos/sin pairs count as two modes; modes are sorted by frequency (ties: `n`, `k`, cos
//!   first); a basis of `N` modes is the first `N` of that list, so the last pair may be cut in
//!   half;
//! - every mode is normalised to `∫_disc Φ² dS = 1` (the disc has area π).
//!
//! Threads: enumeration runs on a worker thread (allocates); [`Mode::eval`] is
//! allocation-free.

use super::angular::Parity;
use super::radial::{roots, CircularEdge, RadialFunction};

/// One mode of a circular plate.
///
/// Plain data built on the worker thread; read by any thread.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mode {
    /// Number of nodal diameters `n` (angular order).
    pub n: u32,
    /// Number of interior nodal circles `k`.
    pub k: u32,
    /// Angular factor: `cos nθ` or `sin nθ`.
    pub parity: Parity,
    /// Normalised radial profile (its `lambda` is `λ` for Φ and `ζ` for Ψ).
    pub radial: RadialFunction,
}

impl Mode {
    /// Value of the mode at polar position `(r, theta)`, `0 ≤ r ≤ 1` (dimensionless radius),
    /// `theta` in radians. Allocation-free.
    pub fn eval(&self, r: f64, theta: f64) -> f64 {
        let ang = match self.parity {
            Parity::Cos => (self.n as f64 * theta).cos(),
            Parity::Sin => (self.n as f64 * theta).sin(),
        };
        self.radial.eval(r)[0] * ang
    }
}

/// The first `count` modes of `ΔΔw = λ⁴ w` on the unit disc with the given edge, sorted as in
/// the module docs (free edge: rigid-body modes excluded). Worker thread; allocates.
pub fn circular_modes(edge: CircularEdge, nu: f64, count: usize) -> Vec<Mode> {
    circular_modes_with(edge, nu, count, false)
}

/// [`circular_modes`], or with `even_only` the first `count` modes with `cos nθ` dependence
/// (the subspace of [`super::basis::CircularPlateSpec::mirror_symmetric`]). Worker thread;
/// allocates.
pub fn circular_modes_with(
    edge: CircularEdge,
    nu: f64,
    count: usize,
    even_only: bool,
) -> Vec<Mode> {
    if count == 0 {
        return Vec::new();
    }
    // Weyl's law for the biharmonic on a disc of area π: N(λ) ≈ λ²/4; start just above it.
    let mut hi = 2.0 * (count as f64).sqrt() + 8.0;
    loop {
        let mut all: Vec<Mode> = Vec::new();
        // Roots of order n exceed about 0.99 n (edge-wave limit), so n < hi/0.9 + 2 suffices.
        let n_max = (hi / 0.9) as u32 + 2;
        for n in 0..=n_max {
            let offset = u32::from(edge == CircularEdge::Free && n <= 1);
            for (idx, lam) in roots(edge, nu, n, hi).into_iter().enumerate() {
                let radial = RadialFunction::new(edge, nu, n, lam);
                let k = idx as u32 + offset;
                all.push(Mode {
                    n,
                    k,
                    parity: Parity::Cos,
                    radial,
                });
                if n > 0 && !even_only {
                    all.push(Mode {
                        n,
                        k,
                        parity: Parity::Sin,
                        radial,
                    });
                }
            }
        }
        if all.len() >= count {
            all.sort_by(|a, b| {
                a.radial
                    .lambda
                    .total_cmp(&b.radial.lambda)
                    .then((a.n, a.k, a.parity).cmp(&(b.n, b.k, b.parity)))
            });
            all.truncate(count);
            return all;
        }
        hi *= 1.25;
    }
}
