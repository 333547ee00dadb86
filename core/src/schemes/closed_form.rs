//! Closed forms the one-oscillator schemes are built from (SEED.md section 1.2).
//!
//! - [`damped_linear`]: the exact solution of `ü + 2ξω0 u̇ + ω0² u = 0` for every `ξ ≥ 0`
//!   (under-, critically and over-damped), in a single closed form without `0/0` at `ξ = 1`.
//!   The exact scheme ([`super::exact`]) takes its first step and its history from it;
//!   [`crate::analysis::analytic`] re-exports it with the other exact solutions.
//!
//! Pure functions of their arguments, callable from any thread.

/// Exact state `(u(t), u̇(t))` of `ü + 2ξω0 u̇ + ω0² u = 0` with `u(0) = u0`, `u̇(0) = v0`.
///
/// Units: `omega0` in rad per time unit, `t` in time units (any sign), `u0` in displacement
/// units, `v0` in displacement per time unit. Written as
/// `u = e^{-σt} [u0 C(t) + (v0 + σ u0) S(t)]`, `u̇ = e^{-σt} [v0 C(t) - (ω0² u0 + σ v0) S(t)]`
/// with `σ = ξω0` and `(C, S) = (cos ωd t, sin(ωd t)/ωd)`, `ωd = ω0 √(1-ξ²)` for `ξ < 1`;
/// `(1, t)` for `ξ = 1`; `(cosh κt, sinh(κt)/κ)`, `κ = ω0 √(ξ²-1)` for `ξ > 1`. For `ξ > 1` and
/// `κ|t| ≥ ½` the products `e^{-σt} cosh κt` and `e^{-σt} sinh κt` are formed from `e^{λ1 t}`,
/// `e^{λ2 t}` (`λ1 = -ω0 / (ξ + √(ξ²-1))` without cancellation) so nothing overflows.
/// Inputs are not validated (callers validate); NaN in gives NaN out.
pub fn damped_linear(omega0: f64, xi: f64, u0: f64, v0: f64, t: f64) -> (f64, f64) {
    let sigma = xi * omega0;
    let (decay_c, decay_s) = if xi < 1.0 {
        let wd = omega0 * ((1.0 - xi) * (1.0 + xi)).sqrt();
        let e = (-sigma * t).exp();
        (e * (wd * t).cos(), e * (wd * t).sin() / wd)
    } else if xi == 1.0 {
        let e = (-sigma * t).exp();
        (e, e * t)
    } else {
        let root = ((xi - 1.0) * (xi + 1.0)).sqrt();
        let kappa = omega0 * root;
        if kappa * t.abs() < 0.5 {
            let e = (-sigma * t).exp();
            (e * (kappa * t).cosh(), e * (kappa * t).sinh() / kappa)
        } else {
            let l1 = -omega0 / (xi + root);
            let l2 = -sigma - kappa;
            let (e1, e2) = ((l1 * t).exp(), (l2 * t).exp());
            (0.5 * (e1 + e2), 0.5 * (e1 - e2) / kappa)
        }
    };
    let u = u0 * decay_c + (v0 + sigma * u0) * decay_s;
    let v = v0 * decay_c - (omega0 * omega0 * u0 + sigma * v0) * decay_s;
    (u, v)
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
    fn damped_linear_solves_the_ode_for_every_regime() {
        // Residual of the ODE by a 4th-order difference with step e = 2e-3 / (ω0 (1 + ξ)):
        // truncation ~(2e-3)^4 / 90 ≈ 2e-13 relative to the size of the terms (ξ = 50 at
        // t = -0.7 is ~1e51), plus the difference's round-off 64 ε |u| / (12 e²) < 1e-14 |u|/e²;
        // bound: 1e-8 relative + that round-off term. Initial values reproduced to 1e-15.
        for &xi in &[0.0, 0.1, 1.0 - 1e-12, 1.0, 1.0 + 1e-12, 2.0, 50.0] {
            let (w, u0, v0) = (1.7, 0.8, -0.3);
            let (a, b) = damped_linear(w, xi, u0, v0, 0.0);
            assert!((a - u0).abs() < 1e-15 && (b - v0).abs() < 1e-15, "xi {xi}");
            let e = 2e-3 / (w * (1.0 + xi));
            for &t in &[-0.7, 0.3, 1.1, 4.0] {
                let u = |s| damped_linear(w, xi, u0, v0, s).0;
                let (ut, vt) = damped_linear(w, xi, u0, v0, t);
                let acc = second_derivative(u, t, e);
                let scale = acc.abs() + (2.0 * xi * w * vt).abs() + (w * w * ut).abs();
                let res = acc + 2.0 * xi * w * vt + w * w * ut;
                let bound = 1e-8 * scale + 1e-14 * ut.abs() / (e * e);
                assert!(res.abs() < bound, "xi {xi} t {t} residual {res}");
                let dudt = (u(t + 1e-3 * e) - u(t - 1e-3 * e)) / (2e-3 * e);
                assert!(
                    (dudt - vt).abs() < 1e-7 * (vt.abs() + w * ut.abs()),
                    "xi {xi} t {t}"
                );
            }
        }
    }
}
