//! The interface between a simulated model and the offline renderer.

/// Energy terms of a model at one instant, in joules.
///
/// `total() = kinetic + linear + nonlinear` is the model's discrete energy; with losses and
/// forcing, `balance() = total + dissipated - work` is constant up to round-off for
/// energy-conserving schemes.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct EnergyTerms {
    /// Kinetic energy.
    pub kinetic: f64,
    /// Linear (bending / tension) potential energy.
    pub linear: f64,
    /// Nonlinear potential energy (in-plane energy of a plate, contact energy of a string).
    pub nonlinear: f64,
    /// Energy removed by damping since the start (≥ 0).
    pub dissipated: f64,
    /// Work done by external forces since the start.
    pub work: f64,
}

impl EnergyTerms {
    /// The discrete energy `kinetic + linear + nonlinear`.
    pub fn total(&self) -> f64 {
        self.kinetic + self.linear + self.nonlinear
    }

    /// The power-balance invariant `total + dissipated - work`.
    pub fn balance(&self) -> f64 {
        self.total() + self.dissipated - self.work
    }
}

/// A model the offline renderer can run: it advances at its own simulation rate and writes
/// one value per output channel per step.
///
/// Driven by the thread that renders (offline) or by the audio thread (real time): `process`
/// must not allocate.
pub trait RenderSource {
    /// Simulation rate in Hz.
    fn sim_rate(&self) -> f64;
    /// Number of output channels.
    fn channels(&self) -> usize;
    /// Advances `frames` steps, writing channel `c` of step `i` to `out[c][i]`
    /// (`out[c].len() >= frames`).
    fn process(&mut self, out: &mut [Vec<f64>], frames: usize);
    /// The energy terms at the current step.
    fn energy(&self) -> EnergyTerms;
    /// Whether the scheme conserves its discrete energy (so drift is an error to report).
    fn is_conservative(&self) -> bool;
    /// Model-specific figures for the report (solver counters, mode counts, ...).
    fn report_extras(&self) -> serde_json::Map<String, serde_json::Value> {
        serde_json::Map::new()
    }
}
