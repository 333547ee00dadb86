//! Gauss-Legendre quadrature on `[0, 1]`.
//!
//! Nodes are the roots of the Legendre polynomial `P_Q`, found by Newton's method from the
//! Tricomi initial guess `cos(π(k - 1/4)/(Q + 1/2))` with `P_Q` and `P_Q'` from the three-term
//! recurrence (Abramowitz & Stegun 1964, 25.4.29; Golub & Welsch 1969 give the same rule by
//! eigenvalues). Weights `2/((1-x²) P_Q'(x)²)`. A `Q`-point rule integrates polynomials of
//! degree `2Q - 1` exactly. Built on the modal-basis worker thread; allocates.

use crate::error::ParamError;

/// A Gauss-Legendre rule mapped to `[0, 1]` (`∫_0^1 f(r) dr ≈ Σ_q w_q f(r_q)`).
///
/// Built and read on the worker thread that builds a modal basis; plain data.
#[derive(Debug, Clone, PartialEq)]
pub struct GaussLegendre {
    /// Nodes `r_q` in `(0, 1)`, increasing (dimensionless).
    pub nodes: Vec<f64>,
    /// Weights `w_q > 0`, summing to 1 (dimensionless).
    pub weights: Vec<f64>,
}

impl GaussLegendre {
    /// Largest supported number of points.
    pub const MAX_POINTS: usize = 1 << 16;

    /// Builds the `points`-point rule on `[0, 1]`; `points` must be in `[1, 65536]`.
    pub fn new(points: usize) -> Result<Self, ParamError> {
        if points == 0 || points > Self::MAX_POINTS {
            return Err(ParamError::new(
                "quadrature_points",
                points,
                format!("integer in [1, {}]", Self::MAX_POINTS),
            ));
        }
        let (t, w) = gauss_legendre_symmetric(points);
        // map [-1, 1] -> [0, 1]
        let nodes = t.iter().map(|t| 0.5 * (1.0 + t)).collect();
        let weights = w.iter().map(|w| 0.5 * w).collect();
        Ok(Self { nodes, weights })
    }

    /// Number of points `Q`.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// `true` when the rule has no points (never, for a rule built by [`GaussLegendre::new`]).
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }
}

/// Gauss-Legendre nodes (increasing) and weights on `[-1, 1]` with `n` points, exact for
/// polynomials of degree `2n - 1`: Newton on `P_n` from Tricomi's initial guesses
/// (Abramowitz & Stegun 25.4.29), symmetric by construction, middle node exactly 0 for odd `n`.
///
/// The one Gauss-Legendre rule of the crate: [`GaussLegendre`] maps it to `[0, 1]` for the
/// circular plate, the rectangular plate's Galerkin integrals use it directly. Worker thread;
/// allocates.
pub fn gauss_legendre_symmetric(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = vec![0.0; n];
    let mut weights = vec![0.0; n];
    let nf = n as f64;
    for k in 0..n.div_ceil(2) {
        // k-th root from the top
        let mut x = (std::f64::consts::PI * (k as f64 + 0.75) / (nf + 0.5)).cos();
        for _ in 0..100 {
            let (p, d) = legendre(n, x);
            let dx = p / d;
            x -= dx;
            if dx.abs() <= 1e-16 * x.abs().max(1e-3) {
                break;
            }
        }
        if n % 2 == 1 && k == n / 2 {
            x = 0.0;
        }
        let (_, dp) = legendre(n, x);
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        nodes[n - 1 - k] = x;
        nodes[k] = -x;
        weights[n - 1 - k] = w;
        weights[k] = w;
    }
    (nodes, weights)
}

/// `(P_q(x), P_q'(x))` by the three-term recurrence.
fn legendre(q: usize, x: f64) -> (f64, f64) {
    let (mut p0, mut p1) = (1.0, x);
    for k in 2..=q {
        let kf = k as f64;
        let p2 = ((2.0 * kf - 1.0) * x * p1 - (kf - 1.0) * p0) / kf;
        p0 = p1;
        p1 = p2;
    }
    let p = if q == 0 { p0 } else { p1 };
    let pm = if q == 0 { 0.0 } else { p0 };
    (p, q as f64 * (x * p - pm) / (x * x - 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn integrates_polynomials_and_exponentials() {
        // Degree 2Q-1 monomials exactly (up to rounding, 1e-14), and ∫_0^1 e^{40 r} dr to 1e-13
        // relative with 64 points (entire integrand: super-geometric convergence).
        for q in [1usize, 2, 5, 17, 64, 300, 1024] {
            let g = GaussLegendre::new(q).unwrap();
            let deg = 2 * q - 1;
            let s: f64 = g
                .nodes
                .iter()
                .zip(&g.weights)
                .map(|(r, w)| w * r.powi(deg as i32))
                .sum();
            assert!((s - 1.0 / (deg as f64 + 1.0)).abs() < 1e-14, "q={q}: {s}");
            let sw: f64 = g.weights.iter().sum();
            assert!((sw - 1.0).abs() < 1e-14, "q={q}: {sw}");
            assert!(g.nodes.windows(2).all(|w| w[0] < w[1]));
        }
        let g = GaussLegendre::new(64).unwrap();
        let s: f64 = g
            .nodes
            .iter()
            .zip(&g.weights)
            .map(|(r, w)| w * (40.0 * r).exp())
            .sum();
        let exact = ((40.0f64).exp() - 1.0) / 40.0;
        assert!((s / exact - 1.0).abs() < 1e-13);
        assert!(GaussLegendre::new(0).is_err());
    }
}
