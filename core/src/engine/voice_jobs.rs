//! The voices' jobs on the pool's workers, as the engine keeps them: the pool, the board where
//! large plate voices offer their steps' second halves, the bank a late job still holds and the
//! events that wait for it (`engine/mix.rs` shares a chunk's voices; `engine/pool.rs` runs the
//! workers).
//!
//! Threads: owned by the audio thread's [`super::audio::Engine`]; the pool and the board are
//! shared with the workers (and the board with the builder thread's banks).

use super::bank::Bank;
use super::events::EventKind;
use super::pool::Pool;
use crate::models::plate::StepBoard;
use std::sync::Arc;
use std::time::Duration;

/// Events kept while the bank is held by a late voice job (applied when it returns).
pub(super) const DEFERRED: usize = 256;

/// The engine's part that shares its voices with the pool (module doc).
pub(super) struct VoiceJobs {
    /// The voice pool's workers (started by `activate`).
    pub pool: Option<Pool>,
    /// Where the bank's large plate voices offer their steps' second halves and the pool's
    /// workers take them (shared by the pool, the builder thread's banks and this engine).
    pub board: Arc<StepBoard>,
    /// The current bank while a late voice job still runs on a worker: nothing but the
    /// chunk loop touches it, events wait in `deferred` (see `render`).
    pub held: Option<Box<Bank>>,
    /// Events that arrived while `held` was out, in order (the first `deferred_len`).
    pub deferred: [EventKind; DEFERRED],
    /// How many of `deferred` are waiting.
    pub deferred_len: usize,
    /// A reset arrived while `held` was out: its voices are reset when it returns.
    pub reset_pending: bool,
    /// Longest wait for the workers' jobs per chunk (`None`: the chunk's duration).
    pub job_wait: Option<Duration>,
    /// Threads allowed to share the last chunk's voices (the audio thread included).
    pub threads_used: u8,
}

impl VoiceJobs {
    /// No pool yet (the activation starts it), an empty board, nothing held. Main thread;
    /// allocates the board.
    pub fn new() -> Self {
        Self {
            pool: None,
            board: Arc::new(StepBoard::new()),
            held: None,
            deferred: [EventKind::AllNotesOff; DEFERRED],
            deferred_len: 0,
            reset_pending: false,
            job_wait: None,
            threads_used: 1,
        }
    }
}
