//! Energy-drift statistics over a run.

/// Largest relative deviation `max_n |E_n - E_0| / |E_0|` of an energy series.
///
/// When `E_0` is zero the absolute deviation is returned instead (there is no scale to divide
/// by). Returns 0 for an empty series.
pub fn max_relative_drift(energies: &[f64]) -> f64 {
    let Some(&e0) = energies.first() else {
        return 0.0;
    };
    let scale = if e0 != 0.0 { e0.abs() } else { 1.0 };
    energies
        .iter()
        .map(|&e| (e - e0).abs() / scale)
        .fold(0.0, f64::max)
}

/// Running tracker of [`max_relative_drift`] for long runs that do not keep the series.
///
/// Owned by the thread running the simulation.
#[derive(Debug, Clone, Copy)]
pub struct DriftTracker {
    /// Reference energy `E_0` (first value seen).
    pub initial: f64,
    /// Largest `|E_n - E_0|` seen so far.
    pub max_abs_deviation: f64,
    /// Number of values seen.
    pub count: u64,
}

impl Default for DriftTracker {
    fn default() -> Self {
        Self {
            initial: f64::NAN,
            max_abs_deviation: 0.0,
            count: 0,
        }
    }
}

impl DriftTracker {
    /// Records one energy value.
    pub fn push(&mut self, e: f64) {
        if self.count == 0 {
            self.initial = e;
        }
        let d = (e - self.initial).abs();
        // NaN deviations must not be hidden by `max`.
        if d > self.max_abs_deviation || d.is_nan() {
            self.max_abs_deviation = d;
        }
        self.count += 1;
    }

    /// Largest relative deviation seen (absolute if `E_0 = 0`).
    pub fn max_relative(&self) -> f64 {
        if self.initial != 0.0 {
            self.max_abs_deviation / self.initial.abs()
        } else {
            self.max_abs_deviation
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn drift_of_a_series() {
        let e = [2.0, 2.0 + 1e-3, 2.0 - 4e-3, 2.0];
        assert!((max_relative_drift(&e) - 2e-3).abs() < 1e-15);
        let mut t = DriftTracker::default();
        e.iter().for_each(|&x| t.push(x));
        assert_eq!(t.max_relative(), max_relative_drift(&e));
        t.push(f64::NAN);
        assert!(t.max_relative().is_nan());
    }
}
