//! The interface between a simulated model and the offline renderer.

use serde::Serialize;

/// Energy terms of a model at one instant, in joules.
///
/// `total() = kinetic + linear + nonlinear + above` is the model's discrete energy; with losses and
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
    /// Energy held by a plate's band above the simulation (stored in its modes, or received
    /// from the closure and not yet given to them; [`crate::models::plate::extension`]); 0
    /// for every other model.
    pub above: f64,
    /// Energy removed by damping since the start (≥ 0).
    pub dissipated: f64,
    /// Work done by external forces since the start.
    pub work: f64,
}

impl EnergyTerms {
    /// The discrete energy `kinetic + linear + nonlinear + above`.
    pub fn total(&self) -> f64 {
        self.kinetic + self.linear + self.nonlinear + self.above
    }

    /// The power-balance invariant `total + dissipated - work`.
    pub fn balance(&self) -> f64 {
        self.total() + self.dissipated - self.work
    }
}

/// The displacement of a one-dimensional model along its length at one instant, with the
/// obstacle it may touch (for the shape plot). Built by the render thread (allocates).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ShapeSnapshot {
    /// Simulated time of the snapshot (s).
    pub time: f64,
    /// Abscissae along the model (m), ends included.
    pub x: Vec<f64>,
    /// Displacement at `x` (m).
    pub u: Vec<f64>,
    /// Obstacle nodes `(x, g)` in m (empty without obstacle).
    pub obstacle: Vec<(f64, f64)>,
}

/// Counters of a contact solver over a run, for the report.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct ContactSummary {
    /// Largest penetration `η = g - u` seen (m; 0 if never in contact).
    pub max_penetration: f64,
    /// Largest Newton iteration count of any node-step.
    pub newton_max_iterations: usize,
    /// Node-steps that hit the iteration cap (solved by the stated fallback).
    pub newton_failures: u64,
    /// `newton_histogram[k]`: node-steps that took `k` iterations (`k = 0`: no contact
    /// possible, closed form), up to the largest count seen.
    pub newton_histogram: Vec<u64>,
    /// Mean iterations over node-steps that needed at least one.
    pub newton_mean_iterations: f64,
    /// Iteration cap of the solver.
    pub newton_cap: usize,
    /// Relative step tolerance of the solver.
    pub newton_tolerance: f64,
    /// Steps with a non-zero contact force.
    pub contact_steps: u64,
    /// Grid nodes carrying an obstacle.
    pub obstacle_nodes: usize,
}

/// What a plate voice was built from, for reports (built once, read by any thread).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlateDetails {
    /// Transverse modes kept.
    pub n_phi: usize,
    /// In-plane modes kept (0: linear plate).
    pub n_psi: usize,
    /// Highest transverse frequency (Hz).
    pub f_max: f64,
    /// Lowest transverse frequency (Hz).
    pub f_min: f64,
    /// Non-zero stored tensor entries.
    pub tensor_nonzeros: usize,
    /// What the modal cache did (`computed`, `loaded`, `memory`, ...).
    pub cache: String,
    /// Seconds spent computing or loading the modal data.
    pub modal_seconds: f64,
    /// Scheme identifier, as spelled in scenes (`sav`, `conservative-exact`, ...).
    pub scheme: String,
    /// Modal subspace, as spelled in scenes (`full` or `strike-mirror`).
    pub symmetry: String,
    /// The rest shape's parts as the scene gave them (`plate.imperfection`; empty: flat, and
    /// left out of the report).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub imperfection: Vec<crate::models::plate::rest_shape::ShapePart>,
}

/// Contact-solver figures of a string over a run, for reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StringDetails {
    /// Modes simulated.
    pub modes: usize,
    /// Contact scheme identifier (`newton` or `quadratised`).
    pub contact_scheme: String,
    /// The quadratised scheme's gap between its auxiliary energy and the contact potential (J);
    /// absent for the Newton scheme.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub quadratisation_gap_j: Option<f64>,
    /// Grid nodes carrying an obstacle.
    pub obstacle_nodes: usize,
    /// Steps with a non-zero contact force.
    pub contact_steps: u64,
    /// Largest Newton iteration count of any node-step.
    pub newton_max_iterations: usize,
    /// Node-steps that hit the iteration cap.
    pub newton_cap_hits: u64,
    /// Mean iterations over node-steps that needed at least one.
    pub newton_mean_iterations_in_contact: f64,
    /// Largest penetration seen (m).
    pub max_penetration_m: f64,
    /// `newton_histogram[k]`: node-steps that took `k` iterations.
    pub newton_histogram: Vec<u64>,
}

/// One string of a network, for reports: its grid and where its modes lie against the
/// simulation's Nyquist frequency.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NetworkStringDetails {
    /// Modes of its grid.
    pub modes: usize,
    /// Modes stepped: all of them, or those below its band limit (an alias-free drone's).
    pub stepped: usize,
    /// Frequency of its highest stepped mode at its present tension (Hz).
    pub top_mode_hz: f64,
    /// Stepped modes above the Nyquist frequency of the simulation: the exact scheme steps them, but
    /// the seat, jawari and bridge forces they answer are sampled, so their share of those
    /// couplings aliases (docs/models.md, "The drone's grid and rate").
    pub modes_above_nyquist: usize,
}

/// A network of strings on a bridge (the tanpura, the sitar), for reports.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NetworkDetails {
    /// The Nyquist frequency of the simulation (Hz), which `modes_above_nyquist` counts from.
    pub nyquist_hz: f64,
    /// The strings, in the network's order.
    pub strings: Vec<NetworkStringDetails>,
}

impl NetworkDetails {
    /// A warning naming the strings whose modes reach above the Nyquist frequency, or `None`
    /// when none does.
    pub fn aliasing_warning(&self) -> Option<String> {
        let aliased: Vec<String> = self
            .strings
            .iter()
            .enumerate()
            .filter(|(_, s)| s.modes_above_nyquist > 0)
            .map(|(i, s)| {
                format!(
                    "string {i} ({} of {} modes, to {:.1} kHz)",
                    s.modes_above_nyquist,
                    s.modes,
                    s.top_mode_hz / 1e3
                )
            })
            .collect();
        (!aliased.is_empty()).then(|| {
            format!(
                "modes above the {:.1} kHz Nyquist frequency of the simulation: {}; their seat, \
                 jawari and bridge forces alias (fewer modes or a higher sim_rate, see \
                 docs/models.md, \"The drone's grid and rate\")",
                self.nyquist_hz / 1e3,
                aliased.join(", ")
            )
        })
    }
}

/// Model-specific figures of a [`RenderSource`], typed; the offline report serialises them.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum ModelDetails {
    /// The model reports nothing more.
    None,
    /// A plate voice.
    Plate(PlateDetails),
    /// A string.
    String(StringDetails),
    /// A network of strings on a bridge.
    Network(NetworkDetails),
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
    /// Model-specific figures for the report (mode counts, solver counters, ...).
    fn details(&self) -> ModelDetails {
        ModelDetails::None
    }
    /// Time (s) of output sample 0 of `channel` after the start of the motion (default 0): the
    /// renderer shifts the resampled signal by it, so every WAV starts at t = 0 whatever the
    /// simulation rate (otherwise a latency of a step or two would look like an O(h) error when
    /// rates are compared).
    fn output_delay(&self, _channel: usize) -> f64 {
        0.0
    }
    /// The linear partials: each mode's continuous damped frequency and the frequency its
    /// scheme simulates (closed form, [`crate::analysis::dispersion`]); empty by default.
    /// Called once after a render (allocates).
    fn linear_partials(&self) -> Vec<crate::analysis::dispersion::LinearPartial> {
        Vec::new()
    }
    /// Contact solver counters, for models with a contact (default: none).
    fn contact(&self) -> Option<ContactSummary> {
        None
    }
    /// The current shape along a one-dimensional model, `time` stamped (default: none, for
    /// models without a 1-D shape). Called between blocks by the offline renderer; allocates.
    fn shape(&self, _time: f64) -> Option<ShapeSnapshot> {
        None
    }
}
