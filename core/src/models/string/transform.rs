//! The grid map `u = S q` between modal coordinates and interior grid values.
//!
//! `S_ij = √(2/L) sin(jπi/N)`, `i, j = 1..N-1` (SEED.md 3.2). `S` is symmetric and the discrete
//! orthogonality `Σ_{i=1}^{N-1} sin(jπi/N) sin(kπi/N) = (N/2) δ_jk` gives
//! `SᵀS = S² = (2/L)(N/2) I = I/Δx`, hence the exact inverse
//! `S⁻¹ = Δx Sᵀ = Δx S`.
//! Consequences used by the model: the modal force of a nodal force density `f`,
//! `F_j = ∫ f φ_j dx ≈ Δx Σ_i f_i φ_j(x_i) = (Δx Sᵀ f)_j = (S⁻¹ f)_j`, and the inner products
//! agree, `Σ_j q_j p_j = Δx Σ_i u_i v_i` for `u = Sq`, `v = Sp`.
//!
//! `S` is `√(2/L)` times the unnormalised DST-I of length `N - 1`
//! (`X_k = Σ_n x_n sin(π(n+1)(k+1)/N)`), computed by `rustdct` in `O(N log N)`; plans and
//! scratch are built with the map, so [`ModalMap::synthesis`] and [`ModalMap::analysis`] never
//! allocate. [`ModalMap::dense`] is the `O(N²)` route kept for checking.
//!
//! Built on the control thread; the transforms run on the audio thread.

use rustdct::{DctPlanner, Dst1};
use std::f64::consts::PI;
use std::sync::Arc;

/// Fast `u = S q` and `q = S⁻¹ u` for one grid, with preallocated scratch.
///
/// Built on the control thread (plans the DST, allocates scratch); `synthesis` / `analysis` run
/// on the audio thread without allocating.
#[derive(Clone)]
pub struct ModalMap {
    /// The DST-I plan of length `N - 1`.
    dst: Arc<dyn Dst1<f64>>,
    /// Scratch the DST needs (length fixed at build).
    scratch: Vec<f64>,
    /// `√(2/L)` in m^-1/2.
    norm: f64,
    /// `Δx = L/N` in m.
    dx: f64,
}

impl std::fmt::Debug for ModalMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ModalMap")
            .field("len", &self.dst.len())
            .field("norm", &self.norm)
            .field("dx", &self.dx)
            .finish()
    }
}

impl ModalMap {
    /// Plans the map for a string of length `length` (m) with `intervals = N ≥ 2` intervals.
    pub fn new(length: f64, intervals: usize) -> Self {
        let mut planner = DctPlanner::new();
        let dst = planner.plan_dst1(intervals - 1);
        let scratch = vec![0.0; dst.get_scratch_len()];
        Self {
            dst,
            scratch,
            norm: (2.0 / length).sqrt(),
            dx: length / intervals as f64,
        }
    }

    /// Number of modes = number of interior nodes, `N - 1`.
    pub fn len(&self) -> usize {
        self.dst.len()
    }

    /// Always false (`N ≥ 2` gives at least one mode); present for API symmetry with `len`.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Unnormalised DST-I in place.
    ///
    /// rustdct 0.7.1's FFT-based DST-I copies the input into the scratch's FFT buffer but never
    /// writes the two zero entries of the odd extension (indices 0 and N), relying on a zeroed
    /// scratch; the FFT leaves data there, so a reused scratch corrupts the next transform.
    /// Zeroing the scratch first (O(N), no allocation) makes every call independent
    /// (regression test `repeated_transforms_are_identical`).
    fn dst(&mut self, buf: &mut [f64]) {
        self.scratch.fill(0.0);
        self.dst.process_dst1_with_scratch(buf, &mut self.scratch);
    }

    /// In place: `buf ← S buf` (modal coordinates in m^3/2 → grid displacements in m).
    pub fn synthesis(&mut self, buf: &mut [f64]) {
        self.dst(buf);
        let k = self.norm;
        buf.iter_mut().for_each(|x| *x *= k);
    }

    /// `S q` into a new vector, with its own scratch (allocates; for snapshots and views off
    /// the hot path, where the map's scratch is not available through `&self`).
    pub fn synthesized(&self, q: &[f64]) -> Vec<f64> {
        let mut buf = q.to_vec();
        let mut scratch = vec![0.0; self.dst.get_scratch_len()];
        self.dst.process_dst1_with_scratch(&mut buf, &mut scratch);
        let k = self.norm;
        buf.iter_mut().for_each(|x| *x *= k);
        buf
    }

    /// In place: `buf ← S⁻¹ buf = Δx S buf` (grid values → modal coordinates).
    pub fn analysis(&mut self, buf: &mut [f64]) {
        self.dst(buf);
        let k = self.norm * self.dx;
        buf.iter_mut().for_each(|x| *x *= k);
    }

    /// The dense matrix `S` (row-major, `(N-1) × (N-1)`, row `i-1` = node `i`), for checking.
    /// Allocates; control thread only.
    pub fn dense(length: f64, intervals: usize) -> Vec<f64> {
        let m = intervals - 1;
        let norm = (2.0 / length).sqrt();
        let mut s = vec![0.0; m * m];
        for i in 1..=m {
            for j in 1..=m {
                // Reduce i·j mod 2N exactly in integers so the sine argument stays small.
                let k = (i * j) % (2 * intervals);
                s[(i - 1) * m + (j - 1)] = norm * (PI * k as f64 / intervals as f64).sin();
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn repeated_transforms_are_identical() {
        // The same input must give bit-identical output however often the scratch is reused.
        for n in [10, 64, 300] {
            let mut map = ModalMap::new(1.0, n);
            let x: Vec<f64> = (0..n - 1).map(|i| (i as f64 * 0.37).sin()).collect();
            let mut first = x.clone();
            map.synthesis(&mut first);
            for _ in 0..3 {
                let mut again = x.clone();
                map.synthesis(&mut again);
                assert_eq!(first, again, "N = {n}");
            }
        }
    }

    #[test]
    fn inverse_is_dx_times_s() {
        // S (Δx S) = I: the fast analysis undoes the fast synthesis to round-off.
        let (l, n) = (0.7, 37);
        let mut map = ModalMap::new(l, n);
        let x: Vec<f64> = (0..n - 1)
            .map(|i| ((i * 7 + 3) % 11) as f64 - 5.0)
            .collect();
        let mut y = x.clone();
        map.synthesis(&mut y);
        map.analysis(&mut y);
        for (a, b) in x.iter().zip(&y) {
            assert!((a - b).abs() < 1e-13 * 5.0, "{a} {b}");
        }
    }
}
