//! The real-time soak (real-time safety under load): one seeded random driver
//! plays the engine as a hostile host would, for a fixed number of blocks
//! ([`SoakConfig::blocks`]), and checks it.
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
//! The run is a fixed amount of work, not of wall time: the seed fixes every choice of the
//! main sequence of blocks (lengths, automation, storms, bursts, host rates). While a
//! requested rebuild is pending, the driver keeps playing blocks paced at real time (a host's
//! audio thread does not stop for the worker) whose choices come from a second seeded
//! sequence, so how many of those the worker's speed takes does not shift the main one; the
//! audio in between, the threads' timing and the late jobs still vary with the machine.
//!
//! Checks (each a [`SoakFailure`]): every output sample finite and within full scale (1.0),
//! and in every block played with the `limiter` parameter on, within the limiter's
//! [`CEILING`] (times [`CEILING_ROUNDING`]) with no sample changed by the output stage's guard
//! ([`Engine::guarded_samples`](noether_core::engine::Engine::guarded_samples) unchanged: the
//! limiter, not the guard's clip, keeps the level, whatever the gain up to +60 dB); every requested rebuild
//! arrives (the engine's bank takes the requested signature) or is refused by the worker with
//! an error message, within [`SoakConfig::rebuild_timeout`]; activations succeed; the whole run
//! ends within [`SoakConfig::wall_limit`] (a safety timeout: past it the soak fails). The caller's
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

pub use noether_core::engine::CEILING;
use std::time::Duration;

/// Relative slack on [`CEILING`] for the limited output: the limiter's gain is `CEILING / peak`
/// rounded to `f32` and averaged in `f64`, so a limited sample can pass the ceiling by a few
/// `f32` ulps (6e-8 each); 1e-6 is about 16 ulps and 9e-6 dB. The stage's own test uses the
/// same bound.
pub const CEILING_ROUNDING: f32 = 1.000_001;

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
    /// Blocks of the main sequence to play (blocks played while a rebuild is pending are
    /// not counted); the run ends at the first point between bursts after them.
    pub blocks: u64,
    /// Safety timeout: a run still going after this wall time fails (a hung or far too
    /// slow engine), it does not stop early.
    pub wall_limit: Duration,
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
    /// Probability that a burst's final step asks instead for a bank whose plate voices split
    /// their steps with the voice pool's workers (a `sav` gong of 800 modes with a band of
    /// about 12 kHz: a coupling tensor above `SPLIT_MIN_ENTRIES`; one voice), outside the
    /// budget.
    pub split_chance: f64,
}

impl SoakConfig {
    /// The bounded soak of `cargo test` (`tests/robustness/soak.rs`): `blocks` blocks of the
    /// main sequence, a wall limit of 10 ms a block plus 2 minutes (the test's main blocks cost
    /// 1.6 ms of CPU each on average, at most 2.4 ms over a longer run, test profile, on the
    /// two-core development machine), up to 40 modes, 10
    /// in-plane modes, 8 voices, simulation rates up to 400 kHz, budget 40 modes × 4 voices ×
    /// 48 kHz; one burst in ten asks for a bank with split steps.
    pub fn quick(seed: u64, blocks: u64) -> Self {
        Self {
            seed,
            blocks,
            wall_limit: Duration::from_secs_f64(120.0 + 1e-2 * blocks as f64),
            rebuild_timeout: Duration::from_secs(30),
            notes_per_second: 300.0,
            max_modes: 40,
            max_in_plane: 10,
            max_polyphony: 8,
            max_sim_rate: 400_000.0,
            budget: 40.0 * 4.0 * 48_000.0,
            split_chance: 0.1,
        }
    }
}
