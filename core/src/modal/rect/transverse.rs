//! Transverse modes of the simply supported rectangle, closed form.
//!
//! Dimensionless plate `[0, 1] × [0, aspect]` (`Lx = 1`, `Ly = aspect`), `D = ρh = 1`:
//! `Φ_{m,n}(x, y) = (2/sqrt(aspect)) sin(mπx) sin(nπy/aspect)`, `∫Φ² dS = 1`, and
//! `ω_{m,n} = λ²_{m,n} = π² (m² + n²/aspect²)` (Leissa, "Vibration of Plates", NASA SP-160,
//! 1969, eq. 4.23 with `a = 1`, `b = aspect`).
//!
//! Built on a worker thread; [`phi_value`] is cheap and allocation-free, so a stepper may call
//! it when placing excitation and pick-up points (not per sample).

use std::f64::consts::PI;

/// The first `n_phi` mode labels `(m, n)` and `λ² = ω` sorted by increasing frequency, ties
/// broken by increasing `m` (so the order is deterministic; a degenerate pair can be split by
/// the truncation at `n_phi`).
pub fn lowest_modes(aspect: f64, n_phi: usize) -> (Vec<(u32, u32)>, Vec<f64>) {
    let omega = |m: u32, n: u32| {
        let (m, n) = (f64::from(m), f64::from(n) / aspect);
        PI * PI * (m * m + n * n)
    };
    // Grow the search radius until the disc of radius r holds n_phi modes; every mode with
    // ω ≤ π² r² is then enumerated, so the lowest n_phi are exact.
    let mut r = (4.0 * n_phi as f64 / (PI * aspect)).sqrt() + 2.0;
    loop {
        let mut modes = Vec::new();
        let m_max = r.floor() as u32;
        for m in 1..=m_max {
            let rest = r * r - f64::from(m * m);
            let n_max = (rest.max(0.0).sqrt() * aspect).floor() as u32;
            for n in 1..=n_max {
                modes.push((omega(m, n), m, n));
            }
        }
        if modes.len() >= n_phi {
            modes.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            modes.truncate(n_phi);
            let labels = modes.iter().map(|&(_, m, n)| (m, n)).collect();
            let lambda2 = modes.iter().map(|&(w, _, _)| w).collect();
            return (labels, lambda2);
        }
        r *= 1.25;
    }
}

/// `Φ_{m,n}` at fractional position `(xi, eta) ∈ [0, 1]²` (`x = xi`, `y = eta · aspect`).
pub fn phi_value(aspect: f64, (m, n): (u32, u32), xi: f64, eta: f64) -> f64 {
    2.0 / aspect.sqrt() * (f64::from(m) * PI * xi).sin() * (f64::from(n) * PI * eta).sin()
}
