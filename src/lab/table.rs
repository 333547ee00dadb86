//! The θ-family table (SEED.md 1.1): stability limit, numerical frequency and cents for a list
//! of θ at one time step.

use crate::analysis::{analytic, frequency::cents};
use crate::error::{check_closed, check_positive, ParamError};
use serde::Serialize;

/// One row of the θ table.
#[derive(Debug, Clone, Serialize)]
pub struct ThetaRow {
    /// θ in [0, 1].
    pub theta: f64,
    /// Stability limit on `h ω0`: `2/√(2θ-1)` for θ > ½, `null` (unconditionally stable) otherwise.
    pub h_omega0_limit: Option<f64>,
    /// Largest stable time step `limit / ω0`, `null` when unconditionally stable.
    pub h_max: Option<f64>,
    /// Whether the given `h` is stable.
    pub stable: bool,
    /// Closed-form numerical angular frequency `ω_d`, `null` when unstable.
    pub omega_d: Option<f64>,
    /// `1200 log2(ω_d/ω0)`, `null` when unstable.
    pub cents: Option<f64>,
}

/// Computes the table for time step `h`, natural frequency `omega0` and the given θ values.
pub fn theta_table(h: f64, omega0: f64, thetas: &[f64]) -> Result<Vec<ThetaRow>, ParamError> {
    check_positive("h", h)?;
    check_positive("omega0", omega0)?;
    thetas
        .iter()
        .map(|&theta| {
            check_closed("theta", theta, 0.0, 1.0)?;
            let limit = analytic::theta_stability_limit(theta);
            let omega_d = analytic::theta_frequency(theta, h, omega0);
            Ok(ThetaRow {
                theta,
                h_omega0_limit: limit.is_finite().then_some(limit),
                h_max: limit.is_finite().then_some(limit / omega0),
                stable: omega_d.is_some(),
                omega_d,
                cents: omega_d.map(|w| cents(w, omega0)),
            })
        })
        .collect()
}

/// Renders rows as an aligned text table.
pub fn format_table(h: f64, omega0: f64, rows: &[ThetaRow]) -> String {
    let mut s = format!(
        "theta-scheme at h = {h}, omega0 = {omega0} (h*omega0 = {:.6}, {:.2} points per period)\n",
        h * omega0,
        std::f64::consts::TAU / (h * omega0)
    );
    s += &format!(
        "{:>8} {:>16} {:>14} {:>8} {:>18} {:>14}\n",
        "theta", "limit h*omega0", "h_max", "stable", "omega_d", "cents"
    );
    let opt = |v: Option<f64>, p: usize| v.map_or("unbounded".to_string(), |x| format!("{x:.p$}"));
    for r in rows {
        s += &format!(
            "{:>8.4} {:>16} {:>14} {:>8} {:>18} {:>14}\n",
            r.theta,
            opt(r.h_omega0_limit, 6),
            opt(r.h_max, 6),
            if r.stable { "yes" } else { "NO" },
            r.omega_d.map_or("-".into(), |w| format!("{w:.12}")),
            r.cents.map_or("-".into(), |c| format!("{c:+.6}")),
        );
    }
    s
}
