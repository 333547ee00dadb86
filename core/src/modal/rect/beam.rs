//! One-dimensional clamped-clamped basis on `[0, L]` of one parity about the centre: the
//! discrete clamped-beam functions `X_p` (`X'''' = β⁴ X`, `X = X' = 0` at both ends) computed
//! by Galerkin on Shen's Legendre basis ([`super::legendre`]), then re-orthonormalised in
//! `L²(0, L)` so that the 2D mass matrix is the identity to roundoff.
//!
//! Polynomials instead of the closed-form `cosh - cos` beam functions avoid the cancellation of
//! those forms for large index and give exact Gauss-Legendre integrals. The functions span the
//! same space as the Shen basis, so the 2D Rayleigh-Ritz approximation is that of a tensor
//! polynomial space of degree `count + 3` per direction, converging spectrally.
//!
//! Built on a worker thread, never on the audio thread.

use super::legendre::{gauss_legendre, ShenBasis};
use crate::modal::error::ModalError;
use faer::{Mat, Side};

/// `n` clamped basis functions of one parity on `[0, len]`, `L²`-orthonormal.
#[derive(Debug, Clone)]
pub(crate) struct ClampedBasis1d {
    /// Interval length (dimensionless, `Lx = 1`).
    len: f64,
    /// 0: even about the centre (Shen indices 0, 2, 4, ...), 1: odd (1, 3, 5, ...).
    parity: usize,
    /// Number of functions.
    n: usize,
    /// Coefficients in the Shen basis, row-major `n × n`: `X_p = sqrt(2/L) Σ_j coef[j n + p] φ_{parity+2j}(t)`.
    coef: Vec<f64>,
    /// `∫ X_p'' X_q'' dx`, row-major `n × n` (close to `diag(β_p⁴)`).
    pub stiff: Vec<f64>,
    /// `∫ X_p' X_q' dx`, row-major `n × n`.
    pub grad: Vec<f64>,
}

impl ClampedBasis1d {
    /// Builds `n ≥ 1` functions of the given parity on `[0, len]`.
    pub fn new(len: f64, parity: usize, n: usize) -> Result<Self, ModalError> {
        let idx: Vec<usize> = (0..n).map(|j| parity + 2 * j).collect();
        let count = parity + 2 * n - 1; // Shen functions 0..count
        let (t, w) = gauss_legendre(count + 6);
        let mut shen = ShenBasis::new(count);
        let (mut f, mut df, mut ddf) = (vec![0.0; count], vec![0.0; count], vec![0.0; count]);
        let (mut mt, mut at, mut bt) = (vec![0.0; n * n], vec![0.0; n * n], vec![0.0; n * n]);
        for (tq, wq) in t.iter().zip(&w) {
            shen.eval(*tq, &mut f, &mut df, &mut ddf);
            for (a, &ka) in idx.iter().enumerate() {
                for (b, &kb) in idx.iter().enumerate() {
                    mt[a * n + b] += wq * f[ka] * f[kb];
                    at[a * n + b] += wq * ddf[ka] * ddf[kb];
                    bt[a * n + b] += wq * df[ka] * df[kb];
                }
            }
        }
        // With A ≈ I (Shen's normalisation), A v = β⁴ M v is M v = μ v with μ = 1/β⁴; the
        // largest μ are the lowest beam modes.
        let m = Mat::<f64>::from_fn(n, n, |i, j| mt[i * n + j]);
        let evd = m
            .self_adjoint_eigen(Side::Lower)
            .map_err(|e| ModalError::Eigensolver {
                problem: "1D beam mass",
                class: None,
                detail: format!("{e:?}"),
            })?;
        let s = evd.S().column_vector();
        let u = evd.U();
        let mut q = vec![0.0; n * n];
        for p in 0..n {
            let col = n - 1 - p;
            let mu = s[col];
            if mu.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                return Err(ModalError::NotPositiveDefinite {
                    matrix: "1D beam mass",
                    class: None,
                });
            }
            let mut big = 0.0f64;
            for j in 0..n {
                if u[(j, col)].abs() > big.abs() {
                    big = u[(j, col)];
                }
            }
            let scale = big.signum() / mu.sqrt();
            for j in 0..n {
                q[j * n + p] = u[(j, col)] * scale;
            }
        }
        // Re-orthonormalise exactly in the quadrature-computed mass: G = Qᵀ M Q = R Rᵀ,
        // Q ← Q R⁻ᵀ.
        let g = congruence(&q, &mt, n);
        let r = cholesky(&g, n).ok_or(ModalError::NotPositiveDefinite {
            matrix: "1D beam Gram",
            class: None,
        })?;
        for row in 0..n {
            // Solve R x = q_row (forward substitution), q_row ← x.
            for p in 0..n {
                let mut v = q[row * n + p];
                for k in 0..p {
                    v -= r[p * n + k] * q[row * n + k];
                }
                q[row * n + p] = v / r[p * n + p];
            }
        }
        let (s2, s1) = ((2.0 / len).powi(4), (2.0 / len).powi(2));
        let stiff = congruence(&q, &at, n).iter().map(|v| v * s2).collect();
        let grad = congruence(&q, &bt, n).iter().map(|v| v * s1).collect();
        Ok(Self {
            len,
            parity,
            n,
            coef: q,
            stiff,
            grad,
        })
    }

    /// Number of functions.
    pub fn len_basis(&self) -> usize {
        self.n
    }

    /// Evaluates `X_p(x)`, `X_p'(x)`, `X_p''(x)` for all `p` (derivatives in `x`) at
    /// `x ∈ [0, len]`. `scratch` must come from [`Self::scratch`].
    pub fn eval(&self, x: f64, s: &mut Scratch, f: &mut [f64], df: &mut [f64], ddf: &mut [f64]) {
        let t = 2.0 * x / self.len - 1.0;
        s.shen.eval(t, &mut s.f, &mut s.df, &mut s.ddf);
        let n = self.n;
        let c0 = (2.0 / self.len).sqrt();
        let (c1, c2) = (c0 * 2.0 / self.len, c0 * (2.0 / self.len).powi(2));
        f[..n].fill(0.0);
        df[..n].fill(0.0);
        ddf[..n].fill(0.0);
        for j in 0..n {
            let k = self.parity + 2 * j;
            let (a, b, c) = (s.f[k] * c0, s.df[k] * c1, s.ddf[k] * c2);
            let row = &self.coef[j * n..(j + 1) * n];
            for p in 0..n {
                f[p] += row[p] * a;
                df[p] += row[p] * b;
                ddf[p] += row[p] * c;
            }
        }
    }

    /// Scratch buffers for [`Self::eval`].
    pub fn scratch(&self) -> Scratch {
        let count = self.parity + 2 * self.n - 1;
        Scratch {
            shen: ShenBasis::new(count),
            f: vec![0.0; count],
            df: vec![0.0; count],
            ddf: vec![0.0; count],
        }
    }
}

/// Scratch space for evaluating a [`ClampedBasis1d`].
pub(crate) struct Scratch {
    shen: ShenBasis,
    f: Vec<f64>,
    df: Vec<f64>,
    ddf: Vec<f64>,
}

/// `Qᵀ A Q` for row-major `n × n` matrices.
fn congruence(q: &[f64], a: &[f64], n: usize) -> Vec<f64> {
    let mut aq = vec![0.0; n * n];
    for i in 0..n {
        for k in 0..n {
            let aik = a[i * n + k];
            for j in 0..n {
                aq[i * n + j] += aik * q[k * n + j];
            }
        }
    }
    let mut out = vec![0.0; n * n];
    for k in 0..n {
        for i in 0..n {
            let qki = q[k * n + i];
            for j in 0..n {
                out[i * n + j] += qki * aq[k * n + j];
            }
        }
    }
    // Symmetrise (exact symmetry up to roundoff of the two products).
    for i in 0..n {
        for j in 0..i {
            let v = 0.5 * (out[i * n + j] + out[j * n + i]);
            out[i * n + j] = v;
            out[j * n + i] = v;
        }
    }
    out
}

/// Lower Cholesky factor of a row-major SPD matrix, `None` if not positive definite.
fn cholesky(a: &[f64], n: usize) -> Option<Vec<f64>> {
    let mut r = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..=i {
            let mut v = a[i * n + j];
            for k in 0..j {
                v -= r[i * n + k] * r[j * n + k];
            }
            if i == j {
                if v.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
                    return None;
                }
                r[i * n + i] = v.sqrt();
            } else {
                r[i * n + j] = v / r[j * n + j];
            }
        }
    }
    Some(r)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Roots of `cos β cosh β = 1` (clamped-clamped beam on `[0, 1]`) by bisection.
    fn beam_root(k: usize) -> f64 {
        let g = |b: f64| b.cos() * b.cosh() - 1.0;
        let c = (k as f64 + 0.5) * std::f64::consts::PI;
        let (mut lo, mut hi) = (c - 0.3, c + 0.3);
        assert!(g(lo) * g(hi) < 0.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if g(lo) * g(mid) <= 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        0.5 * (lo + hi)
    }

    #[test]
    fn beam_eigenvalues_match_transcendental_equation() {
        // Beam modes alternate parity: even modes are roots 1, 3, 5..., odd 2, 4, ...
        // Tolerance 1e-11 relative: 30 polynomials resolve the first 10 modes per parity to
        // near machine precision; the bisection root is exact to ~1e-15 but β⁴ amplifies by 4.
        for parity in 0..2 {
            let b = ClampedBasis1d::new(1.0, parity, 30).unwrap();
            for p in 0..10 {
                let beta = beam_root(2 * p + parity + 1);
                let got = b.stiff[p * 30 + p];
                let rel = (got - beta.powi(4)).abs() / beta.powi(4);
                assert!(
                    rel < 1e-11,
                    "parity {parity} p {p}: {got} vs {}",
                    beta.powi(4)
                );
            }
        }
    }

    #[test]
    fn basis_is_orthonormal_and_clamped() {
        let len = 1.7;
        let b = ClampedBasis1d::new(len, 1, 25).unwrap();
        let n = b.len_basis();
        let mut s = b.scratch();
        let (mut f, mut df, mut ddf) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let (t, w) = gauss_legendre(80);
        let mut m = vec![0.0; n * n];
        for (tq, wq) in t.iter().zip(&w) {
            let x = 0.5 * len * (tq + 1.0);
            b.eval(x, &mut s, &mut f, &mut df, &mut ddf);
            for i in 0..n {
                for j in 0..n {
                    m[i * n + j] += 0.5 * len * wq * f[i] * f[j];
                }
            }
        }
        // Orthonormality to 1e-12 (exact quadrature; roundoff of the re-orthonormalisation).
        for i in 0..n {
            for j in 0..n {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((m[i * n + j] - e).abs() < 1e-12, "M[{i},{j}]");
            }
        }
        for x in [0.0, len] {
            b.eval(x, &mut s, &mut f, &mut df, &mut ddf);
            for p in 0..n {
                assert!(f[p].abs() < 1e-11 && df[p].abs() < 1e-9, "p={p}");
            }
        }
    }
}
