//! The one linear solve per step of the conservative plate schemes, on preallocated buffers.
//!
//! The system is `(A + U Uᵀ) x = r` with `A = diag(a)` (`a_s > 0`) and `U` the `N_Φ × N_Ψ`
//! matrix `U_{s,l} = G_{s,l} e_l` (see [`super::model`]): symmetric positive definite. Two
//! routes, chosen at build time:
//!
//! - Woodbury (Sherman-Morrison-Woodbury identity), for `N_Ψ < N_Φ`:
//!   `(A + U Uᵀ)⁻¹ = A⁻¹ - A⁻¹ U (I + Uᵀ A⁻¹ U)⁻¹ Uᵀ A⁻¹`; the capacitance matrix
//!   `S = I + Uᵀ A⁻¹ U` is `N_Ψ × N_Ψ` SPD (eigenvalues ≥ 1), factored by Cholesky. Cost
//!   `N_Φ N_Ψ²/2 + N_Ψ³/6` flops.
//! - Direct: form `M = A + U Uᵀ` (`N_Φ² N_Ψ/2`) and factor it (`N_Φ³/6`).
//!
//! The Cholesky factorisation is hand-written, in place on the lower triangle of a row-major
//! buffer allocated at build time. Why not `faer`: the matrices are small (tens to a few hundred
//! rows) where blocked/SIMD kernels gain little; the hand-written loops make the "no allocation,
//! bounded work on the audio thread" property evident by inspection; and it keeps a heavy
//! dependency out of a crate built on two shared cores. Both factored matrices have eigenvalues
//! bounded below by `min(a_s)` or 1, so the unpivoted factorisation is backward stable.
//!
//! Threads: built on a worker thread (allocates); `solve` runs on the audio thread.

/// Which factorisation the solver uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Route {
    Woodbury,
    Direct,
}

/// Solver for `(diag(a) + U Uᵀ) x = r` with all scratch preallocated.
#[derive(Debug, Clone)]
pub(crate) struct SpdSolver {
    route: Route,
    n_phi: usize,
    n_psi: usize,
    /// `U`, row-major `N_Φ × N_Ψ`.
    u: Vec<f64>,
    /// Factored matrix: `S` (`N_Ψ²`) or `M` (`N_Φ²`), row-major, lower triangle used.
    mat: Vec<f64>,
    /// `N_Ψ` scratch (Woodbury right-hand side / solution).
    z: Vec<f64>,
}

/// Returned when a pivot is not positive (only possible with non-finite input).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct NotPositiveDefinite;

impl SpdSolver {
    /// Allocates every buffer for the given sizes and route.
    pub(crate) fn new(route: Route, n_phi: usize, n_psi: usize) -> Self {
        let dim = match route {
            Route::Woodbury => n_psi,
            Route::Direct => n_phi,
        };
        Self {
            route,
            n_phi,
            n_psi,
            u: vec![0.0; n_phi * n_psi],
            mat: vec![0.0; dim * dim],
            z: vec![0.0; n_psi],
        }
    }

    /// The route chosen at build time.
    pub(crate) fn route(&self) -> Route {
        self.route
    }

    /// Solves `(diag(a) + U Uᵀ) x = r` with `U_{s,l} = g[s * N_Ψ + l] * e[l]`; `inv_a[s] = 1/a[s]`.
    /// Writes `x` (length `N_Φ`). No allocation; `O(N_Φ N_Ψ²)` or `O(N_Φ³)` bounded work.
    pub(crate) fn solve(
        &mut self,
        a: &[f64],
        inv_a: &[f64],
        g: &[f64],
        e: &[f64],
        r: &[f64],
        x: &mut [f64],
    ) -> Result<(), NotPositiveDefinite> {
        let (nf, np) = (self.n_phi, self.n_psi);
        if np == 0 {
            // No in-plane modes: the system is diagonal.
            for ((xs, &ia), &rs) in x.iter_mut().zip(inv_a).zip(r) {
                *xs = ia * rs;
            }
            return Ok(());
        }
        for (urow, grow) in self.u.chunks_exact_mut(np).zip(g.chunks_exact(np)) {
            for ((u, &gv), &ev) in urow.iter_mut().zip(grow).zip(e) {
                *u = gv * ev;
            }
        }
        match self.route {
            Route::Woodbury => {
                // S = I + Uᵀ A⁻¹ U (lower triangle), z = Uᵀ A⁻¹ r.
                let s = &mut self.mat;
                s.fill(0.0);
                self.z.fill(0.0);
                for ((urow, &ia), &rs) in self.u.chunks_exact(np).zip(inv_a).zip(r) {
                    let ys = ia * rs;
                    for l in 0..np {
                        let t = urow[l] * ia;
                        let srow = &mut s[l * np..l * np + l + 1];
                        for (sv, &um) in srow.iter_mut().zip(&urow[..=l]) {
                            *sv += t * um;
                        }
                        self.z[l] += urow[l] * ys;
                    }
                }
                for l in 0..np {
                    s[l * np + l] += 1.0;
                }
                cholesky_in_place(s, np)?;
                cholesky_solve_in_place(s, np, &mut self.z);
                // x = A⁻¹ (r - U w).
                for (((xs, urow), &ia), &rs) in
                    x.iter_mut().zip(self.u.chunks_exact(np)).zip(inv_a).zip(r)
                {
                    *xs = ia * (rs - dot(urow, &self.z));
                }
            }
            Route::Direct => {
                let m = &mut self.mat;
                for sidx in 0..nf {
                    let us = &self.u[sidx * np..(sidx + 1) * np];
                    for t in 0..=sidx {
                        let ut = &self.u[t * np..(t + 1) * np];
                        m[sidx * nf + t] = dot(us, ut);
                    }
                    m[sidx * nf + sidx] += a[sidx];
                }
                cholesky_in_place(m, nf)?;
                x[..nf].copy_from_slice(&r[..nf]);
                cholesky_solve_in_place(m, nf, x);
            }
        }
        Ok(())
    }

    /// Solves the system factored by the last successful [`Self::solve`] (same `A`, `U`) for a
    /// new right-hand side `r`: one more back-substitution, no refactorisation. Used for the
    /// plate's response to a unit strike force. No allocation; `O(N_Φ N_Ψ)` or `O(N_Φ²)` work.
    pub(crate) fn solve_factored(&mut self, inv_a: &[f64], r: &[f64], x: &mut [f64]) {
        let (nf, np) = (self.n_phi, self.n_psi);
        if np == 0 {
            for ((xs, &ia), &rs) in x.iter_mut().zip(inv_a).zip(r) {
                *xs = ia * rs;
            }
            return;
        }
        match self.route {
            Route::Woodbury => {
                self.z.fill(0.0);
                for ((urow, &ia), &rs) in self.u.chunks_exact(np).zip(inv_a).zip(r) {
                    let ys = ia * rs;
                    for (zl, &ul) in self.z.iter_mut().zip(urow) {
                        *zl += ul * ys;
                    }
                }
                cholesky_solve_in_place(&self.mat, np, &mut self.z);
                for (((xs, urow), &ia), &rs) in
                    x.iter_mut().zip(self.u.chunks_exact(np)).zip(inv_a).zip(r)
                {
                    *xs = ia * (rs - dot(urow, &self.z));
                }
            }
            Route::Direct => {
                x[..nf].copy_from_slice(&r[..nf]);
                cholesky_solve_in_place(&self.mat, nf, x);
            }
        }
    }
}

/// In-place Cholesky `M = L Lᵀ` of the `n × n` row-major matrix `m` (lower triangle read and
/// overwritten by `L`; the strict upper triangle is ignored). Fails on a non-positive or NaN
/// pivot.
pub(crate) fn cholesky_in_place(m: &mut [f64], n: usize) -> Result<(), NotPositiveDefinite> {
    for j in 0..n {
        let (done, rest) = m.split_at_mut((j + 1) * n);
        let rowj = &mut done[j * n..];
        let d = rowj[j] - dot(&rowj[..j], &rowj[..j]);
        if d.is_nan() || d <= 0.0 || d.is_infinite() {
            return Err(NotPositiveDefinite);
        }
        let ljj = d.sqrt();
        rowj[j] = ljj;
        let rowj = &done[j * n..j * n + j];
        for rowi in rest.chunks_exact_mut(n) {
            rowi[j] = (rowi[j] - dot(&rowi[..j], rowj)) / ljj;
        }
    }
    Ok(())
}

/// Solves `L Lᵀ x = b` in place (`b` becomes `x`) with the factor from [`cholesky_in_place`].
pub(crate) fn cholesky_solve_in_place(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let row = &l[i * n..i * n + i + 1];
        b[i] = (b[i] - dot(&row[..i], &b[..i])) / row[i];
    }
    for i in (0..n).rev() {
        let row = &l[i * n..i * n + i + 1];
        let xi = b[i] / row[i];
        b[i] = xi;
        for (bk, &lik) in b[..i].iter_mut().zip(&row[..i]) {
            *bk -= lik * xi;
        }
    }
}

/// The models' shared dot product ([`crate::models::dot`]).
pub(crate) use crate::models::dot;

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic pseudo-random numbers in [-1, 1).
    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    fn residual(
        nf: usize,
        np: usize,
        a: &[f64],
        g: &[f64],
        e: &[f64],
        r: &[f64],
        x: &[f64],
    ) -> f64 {
        let mut worst = 0.0f64;
        for s in 0..nf {
            let mut acc = a[s] * x[s];
            for t in 0..nf {
                let m: f64 = (0..np)
                    .map(|l| g[s * np + l] * g[t * np + l] * e[l] * e[l])
                    .sum();
                acc += m * x[t];
            }
            worst = worst.max((acc - r[s]).abs());
        }
        worst
    }

    #[test]
    fn woodbury_and_direct_solve_the_same_system() {
        // Tolerance 1e-11: residuals of a backward-stable solve on well-scaled entries (≤ 10)
        // are a few ulps times the matrix norm (~ N_Ψ · 100).
        for &(nf, np) in &[(12, 6), (6, 12), (1, 1), (5, 0)] {
            let mut seed = 7 + nf as u64;
            let a: Vec<f64> = (0..nf).map(|_| 1.5 + lcg(&mut seed)).collect();
            let inv_a: Vec<f64> = a.iter().map(|v| 1.0 / v).collect();
            let g: Vec<f64> = (0..nf * np).map(|_| 3.0 * lcg(&mut seed)).collect();
            let e: Vec<f64> = (0..np).map(|_| 1.0 + lcg(&mut seed).abs()).collect();
            let r: Vec<f64> = (0..nf).map(|_| lcg(&mut seed)).collect();
            let mut xw = vec![0.0; nf];
            let mut xd = vec![0.0; nf];
            let mut sw = SpdSolver::new(Route::Woodbury, nf, np);
            sw.solve(&a, &inv_a, &g, &e, &r, &mut xw).unwrap();
            let mut sd = SpdSolver::new(Route::Direct, nf, np);
            sd.solve(&a, &inv_a, &g, &e, &r, &mut xd).unwrap();
            assert!(residual(nf, np, &a, &g, &e, &r, &xw) < 1e-11);
            assert!(residual(nf, np, &a, &g, &e, &r, &xd) < 1e-11);
            for (p, q) in xw.iter().zip(&xd) {
                assert!((p - q).abs() < 1e-11, "{p} vs {q}");
            }
            // A second right-hand side through the stored factors solves the same system.
            let r2: Vec<f64> = (0..nf).map(|_| lcg(&mut seed)).collect();
            for solver in [&mut sw, &mut sd] {
                solver.solve_factored(&inv_a, &r2, &mut xw);
                assert!(residual(nf, np, &a, &g, &e, &r2, &xw) < 1e-11);
            }
        }
    }

    #[test]
    fn cholesky_rejects_indefinite_and_nan() {
        let mut m = vec![1.0, 0.0, 2.0, 1.0];
        assert!(cholesky_in_place(&mut m, 2).is_err());
        let mut m = vec![f64::NAN];
        assert!(cholesky_in_place(&mut m, 1).is_err());
    }
}
