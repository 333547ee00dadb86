//! Exact solutions the one-oscillator schemes are checked against (SEED.md sections 1.1-1.3).
//!
//! - [`damped_linear`]: `ü + 2ξω0 u̇ + ω0² u = 0` for every `ξ ≥ 0` (under-, critically and
//!   over-damped), in a single closed form without `0/0` at `ξ = 1`; the exact scheme's
//!   starting values come from it, so it is defined beside the schemes in
//!   [`crate::schemes::closed_form`] and re-exported here.
//! - [`DuffingFree`]: the hardening Duffing oscillator `ü + ω0² u + γ u³ = 0` released from rest,
//!   `u(t) = u0 cn(Ω t, m)`, `Ω² = ω0² + γ u0²`, `m = γ u0² / (2 Ω²)`, period `T = 4 K(m) / Ω`
//!   (see e.g. A. H. Nayfeh, D. T. Mook, *Nonlinear Oscillations*, Wiley 1979, section 2.1;
//!   it follows from `cn'' = -(1 - 2m) cn - 2m cn³`).
//! - [`jacobi_sn_cn_dn`]: Jacobi elliptic functions by the arithmetic-geometric mean and
//!   descending Landen transformation (M. Abramowitz, I. A. Stegun, *Handbook of Mathematical
//!   Functions*, 1964, section 16.4); `K(m)` comes from the `ellip` crate.
//! - [`theta_frequency`], [`theta_stability_limit`]: closed forms of the θ-family (SEED.md 1.1),
//!   defined next to the scheme in [`crate::schemes::linear`] and re-exported here.
//!
//! Everything here is a pure function of its arguments, callable from any thread.

use crate::error::{check_finite, check_non_negative, check_positive, ParamError};
use std::f64::consts::PI;

pub use crate::schemes::closed_form::damped_linear;
pub use crate::schemes::linear::{
    numerical_frequency as theta_frequency, stability_limit as theta_stability_limit,
};

/// Jacobi elliptic functions `(sn, cn, dn)(x | m)` for parameter `m` in `[0, 1)`.
///
/// Method: arithmetic-geometric mean `a_0 = 1`, `b_0 = √(1-m)`, `c_0 = √m`, iterated until
/// `c_N < 1e-17 a_N`, then `φ_N = 2^N a_N x` and the descending recurrence
/// `φ_{n-1} = ½ (φ_n + asin(c_n sin φ_n / a_n))`; `sn = sin φ_0`, `cn = cos φ_0`,
/// `dn = cos φ_0 / cos(φ_1 - φ_0)` (Abramowitz and Stegun 16.4). The argument is first reduced
/// modulo the real period `4K(m)`, so the absolute error stays near machine precision for large
/// `x`. `m = 0` gives `(sin x, cos x, 1)`. Returns NaNs for `m` outside `[0, 1)`.
pub fn jacobi_sn_cn_dn(x: f64, m: f64) -> (f64, f64, f64) {
    if !(0.0..1.0).contains(&m) || !x.is_finite() {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    if m == 0.0 {
        return (x.sin(), x.cos(), 1.0);
    }
    let quarter = ellip::ellipk(m).unwrap_or(f64::NAN);
    let period = 4.0 * quarter;
    let x = x - period * (x / period).round();
    const LEVELS: usize = 16;
    let mut a = [0.0; LEVELS];
    let mut c = [0.0; LEVELS];
    a[0] = 1.0;
    c[0] = m.sqrt();
    let mut b = (1.0 - m).sqrt();
    let mut n = 0;
    while n + 1 < LEVELS && c[n] > 1e-17 * a[n] {
        let (an, bn) = (a[n], b);
        a[n + 1] = 0.5 * (an + bn);
        c[n + 1] = 0.5 * (an - bn);
        b = (an * bn).sqrt();
        n += 1;
    }
    let mut phi = (1u64 << n) as f64 * a[n] * x;
    let mut phi_prev = phi;
    for k in (1..=n).rev() {
        phi_prev = phi;
        phi = 0.5 * (phi + (c[k] * phi.sin() / a[k]).asin());
    }
    let (sn, cn) = phi.sin_cos();
    let dn = if n == 0 {
        1.0
    } else {
        cn / (phi_prev - phi).cos()
    };
    (sn, cn, dn)
}

/// The hardening Duffing oscillator `ü + ω0² u + γ u³ = 0` released from rest at `u0`.
///
/// Plain parameter holder built once (any thread), then evaluated anywhere.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DuffingFree {
    /// Initial (and maximal) displacement `u0`, displacement units.
    pub u0: f64,
    /// Angular rate `Ω = √(ω0² + γ u0²)` of the `cn` argument, rad per time unit.
    pub omega: f64,
    /// Elliptic parameter `m = γ u0² / (2 Ω²)`, in `[0, ½)` for `γ ≥ 0`.
    pub m: f64,
    /// Exact period `T = 4 K(m) / Ω`, time units.
    pub period: f64,
}

impl DuffingFree {
    /// Validates `omega0 > 0`, `gamma ≥ 0`, finite `u0`, and computes `Ω`, `m`, `T`.
    pub fn new(omega0: f64, gamma: f64, u0: f64) -> Result<Self, ParamError> {
        check_positive("omega0", omega0)?;
        check_non_negative("gamma", gamma)?;
        check_finite("u0", u0)?;
        let g = gamma * u0 * u0;
        let omega = (omega0 * omega0 + g).sqrt();
        let m = g / (2.0 * omega * omega);
        let k = ellip::ellipk(m).map_err(|e| ParamError::new("u0", u0, e))?;
        Ok(Self {
            u0,
            omega,
            m,
            period: 4.0 * k / omega,
        })
    }

    /// Exact displacement `u(t) = u0 cn(Ω t, m)`.
    pub fn displacement(&self, t: f64) -> f64 {
        self.u0 * jacobi_sn_cn_dn(self.omega * t, self.m).1
    }

    /// Exact velocity `u̇(t) = -u0 Ω sn(Ω t, m) dn(Ω t, m)`.
    pub fn velocity(&self, t: f64) -> f64 {
        let (sn, _, dn) = jacobi_sn_cn_dn(self.omega * t, self.m);
        -self.u0 * self.omega * sn * dn
    }

    /// Exact angular frequency `2π / T`.
    pub fn angular_frequency(&self) -> f64 {
        2.0 * PI / self.period
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fourth-order central second difference of `f` at `t`.
    fn second_derivative(f: impl Fn(f64) -> f64, t: f64, e: f64) -> f64 {
        (-f(t + 2.0 * e) + 16.0 * f(t + e) - 30.0 * f(t) + 16.0 * f(t - e) - f(t - 2.0 * e))
            / (12.0 * e * e)
    }

    #[test]
    fn jacobi_functions_identities() {
        // Exact identities sn² + cn² = 1, dn² + m sn² = 1, limits m = 0 and cn(K) = 0.
        for &m in &[0.0, 1e-6, 0.3, 5.0 / 12.0, 0.9] {
            for &x in &[-3.0, 0.1, 1.0, 7.5, 123.4] {
                let (s, c, d) = jacobi_sn_cn_dn(x, m);
                assert!((s * s + c * c - 1.0).abs() < 1e-14);
                assert!((d * d + m * s * s - 1.0).abs() < 1e-14);
            }
            let k = ellip::ellipk(m).unwrap();
            assert!(jacobi_sn_cn_dn(k, m).1.abs() < 1e-14, "m {m}");
        }
        let (s, c, _) = jacobi_sn_cn_dn(0.4, 1e-20);
        assert!((s - 0.4f64.sin()).abs() < 1e-15 && (c - 0.4f64.cos()).abs() < 1e-15);
    }

    #[test]
    fn duffing_solution_solves_the_ode() {
        // ODE residual by a 4th-order difference (step 1e-3): truncation ~1e-12, round-off of
        // the O(1e-15) noise of cn amplified by 64/(12 e²) ≈ 5e-9 at most, so 1e-8 (absolute,
        // unit amplitude); periodicity u(t + T) = u(t) and the half-period value to 1e-13.
        let (w, g, u0) = (1.0, 5.0, 1.0);
        let d = DuffingFree::new(w, g, u0).unwrap();
        for &t in &[0.2, 1.0, 3.3] {
            let u = d.displacement(t);
            let acc = second_derivative(|s| d.displacement(s), t, 1e-3);
            let res = acc + w * w * u + g * u * u * u;
            assert!(res.abs() < 1e-8, "t {t}: {res}");
        }
        assert!((d.displacement(d.period) - u0).abs() < 1e-13);
        assert!((d.displacement(40.0 + d.period) - d.displacement(40.0)).abs() < 1e-13);
        assert!((d.displacement(0.5 * d.period) + u0).abs() < 1e-13);
        assert!(DuffingFree::new(1.0, -1.0, 1.0).is_err());
    }
}
