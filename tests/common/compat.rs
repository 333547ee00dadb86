//! Shared by the plate tests: the axisymmetric compatibility equation solved directly (no
//! in-plane modes), an independent reference for the single-mode cubic coefficient.

use noether::modal::Mode;
use std::f64::consts::PI;

/// `G = ∫ Φ L(Φ, F) dS` for an axisymmetric Φ = R(r), where F solves the compatibility
/// equation `ΔΔF = -½ L(Φ, Φ)` with `F = F' = 0` at r = 1, by direct integration of the radial
/// ODE (no modes): with `L(Φ, Φ) = (R'²)'/r`, `u = ΔF` obeys `u' = -R'²/(2r)`,
/// `F'(r) = (1/r)∫_0^r s u ds`, the constant of `u` fixed by `F'(1) = 0`, and
/// `G = ∫ F L(Φ, Φ) dS = -2π ∫_0^1 F' R'² dr`. Trapezoid rule on `m` uniform intervals.
pub fn compatibility_direct(m: &Mode, steps: usize) -> f64 {
    let h = 1.0 / steps as f64;
    let r: Vec<f64> = (0..=steps).map(|k| k as f64 * h).collect();
    let dr2: Vec<f64> = r.iter().map(|&x| m.radial.eval(x)[1].powi(2)).collect();
    // u' = -R'^2/(2r) (→ -R''(0)²·r/2 → 0 at r = 0)
    let du: Vec<f64> = (0..=steps)
        .map(|k| if k == 0 { 0.0 } else { -dr2[k] / (2.0 * r[k]) })
        .collect();
    let cum = |f: &[f64]| -> Vec<f64> {
        let mut c = vec![0.0; f.len()];
        for k in 1..f.len() {
            c[k] = c[k - 1] + 0.5 * h * (f[k - 1] + f[k]);
        }
        c
    };
    let big_u = cum(&du);
    let su: Vec<f64> = (0..=steps).map(|k| r[k] * big_u[k]).collect();
    let int_su = cum(&su);
    let u0 = -2.0 * int_su[steps];
    let fp: Vec<f64> = (0..=steps)
        .map(|k| {
            if k == 0 {
                0.0
            } else {
                (u0 * r[k] * r[k] / 2.0 + int_su[k]) / r[k]
            }
        })
        .collect();
    let integrand: Vec<f64> = (0..=steps).map(|k| fp[k] * dr2[k]).collect();
    -2.0 * PI * cum(&integrand)[steps]
}
