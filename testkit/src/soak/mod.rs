//! The real-time soak (real-time safety under load): one seeded random driver
//! plays the engine as a hostile host would, for a bounded wall time, and checks it.
//!
//! Every block: every parameter that applies without a rebuild is set to a random value over
//! its whole range (its minimum and maximum exactly, one draw in five); a note storm (note-ons
//! and note-offs at [`SoakConfig::notes_per_second`] on all 128 keys, velocities 0 to 1, pitch
//! bend, mod wheel, sustain, now and then all-notes-off / all-sound-off); a block length from
//! 1 to the activation's maximum (up to 8192). Between blocks, by turns: bursts of changes to
//! the rebuild parameters (model, modes, in-plane modes, simulation rate, scheme, polyphony,
//! positions, material, contact law) that make the worker rebuild and hand over a bank, and
//! host sample-rate changes between 22.05 and 192 kHz (deactivate, activate, as a host does).
//!
//! Checks (each a [`SoakFailure`]): every output sample finite and within
//! [`LEVEL_BOUND`] times the largest output gain set since the start (a bound that holds
//! because the engine silences any voice past [`VOICE_CEILING`]); every requested rebuild
//! arrives (the engine's bank takes the requested signature) or is refused by the worker with
//! an error message, within [`SoakConfig::rebuild_timeout`]; activations succeed. The caller's
//! `process` closure wraps [`Engine::process_events`] (the test and the example put
//! `assert_no_alloc` around it, so an allocation inside `process` aborts the run). The block
//! time over the block's real-time duration is recorded, not checked (shared machines).
//!
//! Threads: [`run`] drives the engine from the calling thread (standing in for both the
//! host's main thread and its audio thread); the engine's worker thread builds banks.

mod draw;
mod driver;
mod quality;
mod summary;

pub use draw::{Draw, Storm, StormCounts, EXTREME_CHANCE};
pub use driver::run;
pub use quality::{needs_rebuild, Signature};
pub use summary::{SoakFailure, SoakSummary, WorstBlock};

use noether_core::engine::{MAX_VOICES, VOICE_CEILING};
use std::time::Duration;

/// Output bound before the output gain, in the engine's normalised units (plates: pickup
/// velocity / 1 m/s; strings: / 4 m/s), derived from the engine's structure: each voice's
/// output stays within [`VOICE_CEILING`] (past it the engine silences the voice and drops its
/// chunk), at most [`MAX_VOICES`] voices sound in a bank, two banks sound during a handover
/// (the old one faded by a factor ≤ 1), and the resampler's kernel has an ℓ1 norm below 2
/// (1.91 at the 0.9 cutoff, 1.78 at the lowest rate ratios: computed from its definition in
/// `engine::resample`). So `|out| ≤ 2 · 2 · 16 · VOICE_CEILING · g` with `g` the largest
/// output gain set since the start (the smoothed gain is a running average of the targets).
/// The soak prints the largest level it saw, so the margin is visible.
pub const LEVEL_BOUND: f64 = 2.0 * 2.0 * MAX_VOICES as f64 * VOICE_CEILING;

/// Host rates a re-activation picks from (Hz); one draw in five is uniform in
/// 8 000..384 000 instead.
pub const HOST_RATES: [f64; 10] = [
    8_000.0, 16_000.0, 22_050.0, 44_100.0, 48_000.0, 88_200.0, 96_000.0, 176_400.0, 192_000.0,
    384_000.0,
];

/// Maximum block sizes a re-activation picks from (the host's promise; blocks are drawn in
/// `1..=max`).
pub const MAX_BLOCKS: [usize; 5] = [64, 512, 1024, 4096, 8192];

/// How the soak runs. Plain data, any thread.
#[derive(Debug, Clone)]
pub struct SoakConfig {
    /// Seed of every random choice.
    pub seed: u64,
    /// Wall time after which no new burst or re-activation starts (a pending rebuild is
    /// still waited for).
    pub duration: Duration,
    /// Longest wall time a requested rebuild may take to arrive or be refused.
    pub rebuild_timeout: Duration,
    /// Mean note-ons per second of host time (as many note-offs).
    pub notes_per_second: f64,
    /// Largest `modes` a burst sets (the table allows 400).
    pub max_modes: usize,
    /// Largest `in_plane_modes` a burst sets (the table allows 200).
    pub max_in_plane: usize,
    /// Largest polyphony a burst sets (the table allows 16).
    pub max_polyphony: usize,
    /// Highest simulation rate a burst sets (Hz; the table allows 400 kHz).
    pub max_sim_rate: f64,
    /// Load budget: bursts keep `modes · polyphony · sim_rate` (mode-steps per second of
    /// audio) at most this, lowering polyphony first, then modes.
    pub budget: f64,
}

impl SoakConfig {
    /// The bounded soak of `cargo test` (`tests/robustness/soak.rs`): `duration` of wall time,
    /// up to 40 modes, 10 in-plane modes, 8 voices, simulation rates up to 400 kHz, budget 40
    /// modes × 4 voices × 48 kHz.
    pub fn quick(seed: u64, duration: Duration) -> Self {
        Self {
            seed,
            duration,
            rebuild_timeout: Duration::from_secs(30),
            notes_per_second: 300.0,
            max_modes: 40,
            max_in_plane: 10,
            max_polyphony: 8,
            max_sim_rate: 400_000.0,
            budget: 40.0 * 4.0 * 48_000.0,
        }
    }
}
