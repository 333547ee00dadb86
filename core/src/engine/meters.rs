//! What the engine counts and measures on the audio thread, apart from its sound: event
//! counters since the engine was created ([`Counts`], reported by `readout.rs`) and the
//! accumulators of the telemetry frame in progress ([`Meters`]).
//!
//! Threads: written by the audio thread (the engine's `process`); read by the engine's owner.

/// Counters since the engine was created (never reset: an hour of playing is summed).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Counts {
    /// Contact Newton solves that hit their iteration cap (their fallback was used).
    pub newton_cap_hits: u64,
    /// Mallet contacts begun.
    pub mallet_impacts: u64,
    /// Voices silenced because their state became non-finite or their output passed
    /// [`super::VOICE_CEILING`].
    pub diverged: u64,
    /// Notes refused (or ended at a retune) because their coefficients would be unstable (θ = 1 scheme above its
    /// limit, or an exact-scheme mode on a multiple of π).
    pub refused: u64,
    /// Voice jobs that finished after their chunk's wait (late jobs).
    pub late: u64,
    /// Events dropped while a late job held the bank (the deferred queue was full).
    pub deferred_lost: u64,
    /// Jobs run by the workers of pools already stopped (earlier activations).
    pub worker_jobs_past: u64,
    /// Samples the guards of output stages already replaced (earlier activations) changed.
    pub guarded_past: u64,
}

/// Accumulators of the telemetry frame in progress (reset when a frame is sent).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Meters {
    /// Engine frame (host samples since creation) at which the next telemetry frame is due.
    pub next: u64,
    /// Output peak per channel since the last frame.
    pub peak: [f32; 2],
    /// Sum of squared output samples per channel since the last frame.
    pub sumsq: [f64; 2],
    /// Host samples since the last frame.
    pub samples: u64,
    /// Audio-thread time spent in `process` since the last frame (s).
    pub busy: f64,
    /// Largest `process` time over its block's duration since the last frame.
    pub cpu_peak: f32,
}
