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
use super::radial::{CircularEdge, RadialFunction, RootScan};
use std::sync::Mutex;

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
///
/// The root scans of each edge and Poisson ratio are kept for the process ([`SCANS`]) and
/// continued by the next enumeration, so a plate's band above (thousands of modes, seconds of
/// scanning) is scanned once, not at every bank build. The result does not depend on what was
/// scanned before: it is made of the complete set of roots below a bound, and each root's
/// value comes from the same bracket of the same grid ([`RootScan`]).
pub fn circular_modes_with(
    edge: CircularEdge,
    nu: f64,
    count: usize,
    even_only: bool,
) -> Vec<Mode> {
    if count == 0 {
        return Vec::new();
    }
    let mut kept = SCANS.lock().unwrap_or_else(|p| p.into_inner());
    let at = kept
        .iter()
        .position(|s| s.edge == edge && s.nu_bits == nu.to_bits());
    let mut scans = match at {
        Some(i) => kept.remove(i),
        None => Scans {
            edge,
            nu_bits: nu.to_bits(),
            orders: Vec::new(),
        },
    };
    // Weyl's law for the biharmonic on a disc of area π: N(λ) ≈ λ²/4 (half of it with cos
    // modes only); start just above it.
    let share = if even_only { 2.0 } else { 1.0 };
    let mut hi = 2.0 * (share * count as f64).sqrt() + 8.0;
    let modes = loop {
        // Roots of order n exceed about 0.99 n (edge-wave limit), so n < hi/0.9 + 2 suffices:
        // after this, every root below `hi` is known.
        let n_max = (hi / 0.9) as u32 + 2;
        while scans.orders.len() <= n_max as usize {
            let n = scans.orders.len() as u32;
            scans.orders.push(RootScan::new(edge, nu, n));
        }
        for scan in &mut scans.orders[..=n_max as usize] {
            scan.scan_to(hi);
        }
        let below = |scan: &RootScan| scan.roots().iter().take_while(|&&r| r < hi).count();
        let found: usize = scans.orders[..=n_max as usize]
            .iter()
            .enumerate()
            .map(|(n, scan)| below(scan) * if n > 0 && !even_only { 2 } else { 1 })
            .sum();
        if found >= count {
            break modes_below(
                edge,
                nu,
                &scans.orders[..=n_max as usize],
                hi,
                count,
                even_only,
            );
        }
        hi *= 1.25;
    };
    kept.push(scans);
    if kept.len() > KEPT_SCANS {
        kept.remove(0);
    }
    modes
}

/// The first `count` modes among the roots of `orders` below `hi` (which must hold every
/// root below it), sorted by `λ`, then `n`, `k`, cos first.
fn modes_below(
    edge: CircularEdge,
    nu: f64,
    orders: &[RootScan],
    hi: f64,
    count: usize,
    even_only: bool,
) -> Vec<Mode> {
    let mut all: Vec<(f64, u32, u32, Parity)> = Vec::new();
    for (n, scan) in orders.iter().enumerate() {
        let n = n as u32;
        let offset = u32::from(edge == CircularEdge::Free && n <= 1);
        for (idx, &lam) in scan.roots().iter().take_while(|&&r| r < hi).enumerate() {
            let k = idx as u32 + offset;
            all.push((lam, n, k, Parity::Cos));
            if n > 0 && !even_only {
                all.push((lam, n, k, Parity::Sin));
            }
        }
    }
    all.sort_by(|a, b| {
        a.0.total_cmp(&b.0)
            .then((a.1, a.2, a.3).cmp(&(b.1, b.2, b.3)))
    });
    all.truncate(count);
    all.into_iter()
        .map(|(lam, n, k, parity)| Mode {
            n,
            k,
            parity,
            radial: RadialFunction::new(edge, nu, n, lam),
        })
        .collect()
}

/// The root scans of one edge and Poisson ratio, one per angular order.
struct Scans {
    edge: CircularEdge,
    nu_bits: u64,
    orders: Vec<RootScan>,
}

/// Edges and Poisson ratios whose scans the process keeps (a few kilobytes each).
const KEPT_SCANS: usize = 8;

/// The scans kept for the process, the most recently used last. Locked by the enumerations
/// only (worker threads; never the audio thread).
static SCANS: Mutex<Vec<Scans>> = Mutex::new(Vec::new());

#[cfg(test)]
mod tests {
    use super::super::radial::roots;
    use super::*;

    /// The kept scans change nothing: an enumeration after a longer one (which scanned further)
    /// and one before it give the same modes, bit for bit, and both match an enumeration from
    /// fresh scans ([`roots`]) of every order to a bound past the last mode. A Poisson ratio
    /// no other test uses, so the first enumeration starts from nothing.
    #[test]
    fn kept_scans_give_the_same_modes_as_fresh_ones() {
        for (edge, even_only) in [(CircularEdge::Free, true), (CircularEdge::Clamped, false)] {
            let nu = 0.3123;
            let first = circular_modes_with(edge, nu, 300, even_only);
            let longer = circular_modes_with(edge, nu, 1200, even_only);
            let again = circular_modes_with(edge, nu, 300, even_only);
            assert_eq!(first, again);
            assert_eq!(first[..], longer[..300]);
            let hi = longer[1199].radial.lambda + 1.0;
            let mut fresh: Vec<(f64, u32)> = (0..=(hi / 0.9) as u32 + 2)
                .flat_map(|n| {
                    let copies = if n > 0 && !even_only { 2 } else { 1 };
                    roots(edge, nu, n, hi)
                        .into_iter()
                        .flat_map(move |r| std::iter::repeat_n((r, n), copies))
                })
                .collect();
            fresh.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            for (m, (lam, n)) in longer.iter().zip(&fresh) {
                assert_eq!((m.radial.lambda.to_bits(), m.n), (lam.to_bits(), *n));
            }
        }
    }
}
