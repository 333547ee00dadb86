//! The Legendre-Galerkin basis for fourth-order problems with clamped ends (Shen's basis), and
//! the Gauss-Legendre rule it is integrated with (shared with the circular plate).
//!
//! J. Shen, "Efficient spectral-Galerkin method I. Direct solvers of second- and fourth-order
//! equations using Legendre polynomials", SIAM J. Sci. Comput. 15(6), 1994, eq. (2.11)-(2.13):
//! `φ_k(t) = d_k (L_k(t) - 2(2k+5)/(2k+7) L_{k+2}(t) + (2k+3)/(2k+7) L_{k+4}(t))` on `[-1, 1]`,
//! with `φ_k(±1) = φ_k'(±1) = 0` and `d_k = 1 / sqrt(2 (2k+3)² (2k+5))`, which makes
//! `∫ φ_j'' φ_k'' dt = δ_jk`. `φ_k` has the parity of `k` under `t -> -t`.
//!
//! Everything here is called while building modal data on a worker thread, never on the audio
//! thread.

pub use crate::modal::quadrature::gauss_legendre_symmetric as gauss_legendre;

/// Values, first and second derivatives of `L_0 .. L_{n-1}` at `t`, written into the three
/// slices (each of length `n`). Derivatives use `L_{k+1}' = L_{k-1}' + (2k+1) L_k` and
/// `L_{k+1}'' = L_{k-1}'' + (2k+1) L_k'`, which stay accurate up to `t = ±1`.
fn legendre_all(t: f64, p: &mut [f64], dp: &mut [f64], ddp: &mut [f64]) {
    let n = p.len();
    if n == 0 {
        return;
    }
    p[0] = 1.0;
    dp[0] = 0.0;
    ddp[0] = 0.0;
    if n == 1 {
        return;
    }
    p[1] = t;
    dp[1] = 1.0;
    ddp[1] = 0.0;
    for k in 1..n - 1 {
        let kf = k as f64;
        p[k + 1] = ((2.0 * kf + 1.0) * t * p[k] - kf * p[k - 1]) / (kf + 1.0);
        dp[k + 1] = dp[k - 1] + (2.0 * kf + 1.0) * p[k];
        ddp[k + 1] = ddp[k - 1] + (2.0 * kf + 1.0) * dp[k];
    }
}

/// Shen's clamped basis `φ_k`, `k = 0 .. count-1`, with its first two derivatives, evaluated
/// at `t ∈ [-1, 1]`. Output slices have length `count`. Worker thread only.
pub struct ShenBasis {
    count: usize,
    p: Vec<f64>,
    dp: Vec<f64>,
    ddp: Vec<f64>,
}

impl ShenBasis {
    /// A basis with `count` functions (Legendre polynomials up to degree `count + 3`).
    pub fn new(count: usize) -> Self {
        Self {
            count,
            p: vec![0.0; count + 4],
            dp: vec![0.0; count + 4],
            ddp: vec![0.0; count + 4],
        }
    }

    /// Writes `φ_k(t)`, `φ_k'(t)`, `φ_k''(t)` (derivatives in `t`) for all `k < count`.
    pub fn eval(&mut self, t: f64, f: &mut [f64], df: &mut [f64], ddf: &mut [f64]) {
        legendre_all(t, &mut self.p, &mut self.dp, &mut self.ddp);
        for k in 0..self.count {
            let kf = k as f64;
            let a = 2.0 * (2.0 * kf + 5.0) / (2.0 * kf + 7.0);
            let b = (2.0 * kf + 3.0) / (2.0 * kf + 7.0);
            let d = 1.0 / (2.0 * (2.0 * kf + 3.0).powi(2) * (2.0 * kf + 5.0)).sqrt();
            f[k] = d * (self.p[k] - a * self.p[k + 2] + b * self.p[k + 4]);
            df[k] = d * (self.dp[k] - a * self.dp[k + 2] + b * self.dp[k + 4]);
            ddf[k] = d * (self.ddp[k] - a * self.ddp[k + 2] + b * self.ddp[k + 4]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadrature_is_exact_for_polynomials() {
        // ∫ t^{2j} dt = 2/(2j+1); exact up to degree 2n-1 (tolerance: roundoff of a sum of
        // n positive terms of size ≤ 2).
        let (x, w) = gauss_legendre(17);
        for j in 0..17i32 {
            let s: f64 = x.iter().zip(&w).map(|(t, w)| w * t.powi(2 * j)).sum();
            assert!((s - 2.0 / (2 * j + 1) as f64).abs() < 1e-14, "j={j} s={s}");
        }
        let (x, w) = gauss_legendre(200);
        assert!((w.iter().sum::<f64>() - 2.0).abs() < 1e-13);
        assert!(x.windows(2).all(|p| p[0] < p[1]));
    }

    #[test]
    fn shen_basis_is_clamped_and_stiffness_orthonormal() {
        let n = 40;
        let mut b = ShenBasis::new(n);
        let (mut f, mut df, mut ddf) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        for t in [-1.0, 1.0] {
            b.eval(t, &mut f, &mut df, &mut ddf);
            for k in 0..n {
                // Boundary values vanish up to roundoff of the O(k²) derivative terms.
                assert!(f[k].abs() < 1e-14 && df[k].abs() < 1e-12, "k={k}");
            }
        }
        let (x, w) = gauss_legendre(n + 6);
        let mut a = vec![0.0; n * n];
        for (t, wq) in x.iter().zip(&w) {
            b.eval(*t, &mut f, &mut df, &mut ddf);
            for j in 0..n {
                for k in 0..n {
                    a[j * n + k] += wq * ddf[j] * ddf[k];
                }
            }
        }
        for j in 0..n {
            for k in 0..n {
                let e = if j == k { 1.0 } else { 0.0 };
                assert!(
                    (a[j * n + k] - e).abs() < 1e-12,
                    "A[{j},{k}]={}",
                    a[j * n + k]
                );
            }
        }
    }
}
