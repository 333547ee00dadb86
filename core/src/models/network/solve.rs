//! The bridge's implicit solve: one Newton iteration on the bridge's `y^{n+1}` over the
//! strings' scalar responses (module doc of [`crate::models::network`]).
//!
//! Unknown `y ∈ R^B` (the bridge's modes at `n+1`). Each string `s` answers, for its lift
//! `λ_s = Σ_k Φ_{k,s} y_k`, with its force `F_s(λ_s)` and `F_s'(λ_s) ≥ 0`
//! ([`StiffString::coupling_response`]); the bridge's scheme asks
//! `R(y) = y - y_free + D Σ_s Φ_s F_s(λ_s) = 0`, `D = diag(h²/M_k)`. The Jacobian
//! `J = I + D Σ_s Φ_s Φ_sᵀ F_s'` is `D` times a symmetric positive definite matrix, so `R` has
//! one root and Newton's steps are well defined. `D F'` is at most the mass of string in
//! contact over the bridge's mass (a string node's response `F'` is at most `μΔx/h²` per node),
//! a small number, so `R` is a strong contraction's residual and Newton converges in two or
//! three iterations (one when only the linear seats act). Stop: the largest correction at or
//! below [`NETWORK_STOP`] times the bridge's scale, and the corrected iterate is used without
//! another evaluation: Newton's error after a correction `δ` is of order `c δ²` (`c` the
//! relative curvature of the strings' responses, small), so a correction of 1e-7 leaves an
//! error near 1e-14, below the strings' own solve tolerance [`NETWORK_TOL`]. After
//! [`NETWORK_NEWTON_CAP`] iterations the last iterate is used and the cap hit counted.
//!
//! Audio thread: fixed-size arrays on the stack, scratch allocated at build.

use super::bridge::{BridgeBody, MAX_BRIDGE_MODES};
use crate::models::string::StiffString;

/// Iteration cap of the bridge's Newton solve.
pub const NETWORK_NEWTON_CAP: usize = 20;

/// Relative accuracy the bridge's Newton solve aims at: the strings' contact forces are
/// themselves solved to `NEWTON_TOL = 1e-13` ([`crate::models::string::NEWTON_TOL`]), so the
/// bridge cannot be resolved more finely than that.
pub const NETWORK_TOL: f64 = 1e-13;

/// Relative correction at which the solve stops and keeps the corrected iterate (module doc:
/// Newton's quadratic convergence leaves an error of order its square, ~1e-14).
pub const NETWORK_STOP: f64 = 1e-7;

/// Counters of the bridge solve over a run.
///
/// Updated by the stepping thread; read by any thread (copy).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct NetworkStats {
    /// Steps taken.
    pub steps: u64,
    /// Newton iterations over all steps.
    pub iterations: u64,
    /// Largest iteration count of one step.
    pub max_iterations: usize,
    /// Steps that hit [`NETWORK_NEWTON_CAP`].
    pub cap_hits: u64,
}

/// The solve's data and scratch (struct of arrays over strings).
#[derive(Debug, Clone)]
pub(super) struct BridgeSolve {
    /// `Φ_{k,s}` at `s · B + k`.
    shape: Vec<f64>,
    /// Number of bridge modes `B`.
    modes: usize,
    /// Per string: its force `F_s` (N) at the current iterate.
    force: Vec<f64>,
    /// Per string: `F_s'` (N/m).
    slope: Vec<f64>,
    /// Per string: `(Σ f_i, active obstacle nodes)` of the committed solve.
    pub(super) committed: Vec<(f64, usize)>,
    /// Counters.
    pub(super) stats: NetworkStats,
}

impl BridgeSolve {
    /// The solve for `strings` strings on a bridge of `modes` modes with shapes `shape`.
    pub(super) fn new(shape: Vec<f64>, strings: usize, modes: usize) -> Self {
        debug_assert_eq!(shape.len(), strings * modes);
        Self {
            shape,
            modes,
            force: vec![0.0; strings],
            slope: vec![0.0; strings],
            committed: vec![(0.0, 0); strings],
            stats: NetworkStats::default(),
        }
    }

    /// String `s`'s lift at the bridge state `y` (m).
    fn lift(&self, s: usize, y: &[f64; MAX_BRIDGE_MODES]) -> f64 {
        let b = self.modes;
        self.shape[s * b..(s + 1) * b]
            .iter()
            .zip(y)
            .map(|(p, y)| p * y)
            .sum()
    }

    /// Newton's iteration on `y^{n+1}` after every string's free step and the bridge's
    /// ([`BridgeBody::free`]); returns `y^{n+1}`. Bounded: at most [`NETWORK_NEWTON_CAP`]
    /// iterations.
    #[allow(clippy::needless_range_loop)] // modes `k`, `l` index several arrays at once
    pub(super) fn solve(
        &mut self,
        strings: &[StiffString],
        bridge: &BridgeBody,
    ) -> [f64; MAX_BRIDGE_MODES] {
        let b = self.modes;
        let mut y = [0.0; MAX_BRIDGE_MODES];
        for k in 0..b {
            y[k] = bridge.y[k] + bridge.dy_free[k];
        }
        let y_free = y;
        let mut converged = false;
        let mut iterations = 0;
        for it in 1..=NETWORK_NEWTON_CAP {
            iterations = it;
            for (s, string) in strings.iter().enumerate() {
                let (f, df) = string.coupling_response(self.lift(s, &y));
                self.force[s] = f;
                self.slope[s] = df;
            }
            let mut r = [0.0; MAX_BRIDGE_MODES];
            let mut jac = [[0.0; MAX_BRIDGE_MODES]; MAX_BRIDGE_MODES];
            for k in 0..b {
                let d = bridge.force_factor[k];
                let mut g = 0.0;
                for s in 0..strings.len() {
                    let pk = self.shape[s * b + k];
                    g += pk * self.force[s];
                    for l in 0..b {
                        jac[k][l] += d * pk * self.shape[s * b + l] * self.slope[s];
                    }
                }
                r[k] = (y[k] - y_free[k]) + d * g;
                jac[k][k] += 1.0;
            }
            let delta = solve_dense(jac, r, b);
            let (mut step, mut scale) = (0.0f64, 0.0f64);
            for k in 0..b {
                y[k] -= delta[k];
                step = step.max(delta[k].abs());
                scale = scale.max(y[k].abs()).max(y_free[k].abs());
            }
            if step <= NETWORK_STOP * scale {
                converged = true;
                break;
            }
        }
        self.stats.steps += 1;
        self.stats.iterations += iterations as u64;
        self.stats.max_iterations = self.stats.max_iterations.max(iterations);
        self.stats.cap_hits += u64::from(!converged);
        y
    }

    /// Every string's contact and seat solve at the bridge state `y` (committed into the
    /// strings, their `(Σ f_i, active)` kept for their finish); returns the bridge's modal
    /// forces `G_k = -Σ_s Φ_{k,s} F_s` (N).
    #[allow(clippy::needless_range_loop)] // mode `k` indexes the shapes and the forces
    pub(super) fn commit(
        &mut self,
        strings: &mut [StiffString],
        y: &[f64; MAX_BRIDGE_MODES],
    ) -> [f64; MAX_BRIDGE_MODES] {
        let b = self.modes;
        let mut g = [0.0; MAX_BRIDGE_MODES];
        for (s, string) in strings.iter_mut().enumerate() {
            let (total, active) = string.solve_contacts(self.lift(s, y));
            self.committed[s] = (total, active);
            let f = total * string.params().dx();
            for k in 0..b {
                g[k] -= self.shape[s * b + k] * f;
            }
        }
        g
    }
}

/// Solves `a x = r` for the leading `n × n` block by Gaussian elimination with partial
/// pivoting (`n ≤ MAX_BRIDGE_MODES`; `a` is `D` times a positive definite matrix, never
/// singular). On the stack, `O(n³)`.
#[allow(clippy::needless_range_loop)] // row and column indices of the elimination
fn solve_dense(
    mut a: [[f64; MAX_BRIDGE_MODES]; MAX_BRIDGE_MODES],
    mut r: [f64; MAX_BRIDGE_MODES],
    n: usize,
) -> [f64; MAX_BRIDGE_MODES] {
    for c in 0..n {
        let p = (c..n)
            .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
            .unwrap_or(c);
        a.swap(c, p);
        r.swap(c, p);
        for i in c + 1..n {
            let m = a[i][c] / a[c][c];
            for j in c..n {
                a[i][j] -= m * a[c][j];
            }
            r[i] -= m * r[c];
        }
    }
    let mut x = [0.0; MAX_BRIDGE_MODES];
    for i in (0..n).rev() {
        let mut v = r[i];
        for j in i + 1..n {
            v -= a[i][j] * x[j];
        }
        x[i] = v / a[i][i];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The elimination against a hand-checked 3×3 system (exact in binary: tolerance 1e-15).
    #[test]
    fn dense_solve_matches_a_known_system() {
        let mut a = [[0.0; MAX_BRIDGE_MODES]; MAX_BRIDGE_MODES];
        a[0][..3].copy_from_slice(&[0.0, 2.0, 1.0]);
        a[1][..3].copy_from_slice(&[1.0, 1.0, 0.0]);
        a[2][..3].copy_from_slice(&[2.0, 0.0, 3.0]);
        // x = (1, 2, 3): r = (7, 3, 11); the zero pivot forces a swap.
        let mut r = [0.0; MAX_BRIDGE_MODES];
        r[..3].copy_from_slice(&[7.0, 3.0, 11.0]);
        let x = solve_dense(a, r, 3);
        for (xi, want) in x.iter().zip([1.0, 2.0, 3.0]) {
            assert!((xi - want).abs() < 1e-15, "{x:?}");
        }
    }
}
