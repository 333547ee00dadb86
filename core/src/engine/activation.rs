//! The engine's lifecycle on the main thread: activation (blocking for offline renders, or
//! returning at once for a live host while the worker builds), re-activation at a new rate,
//! deactivation, and the CPU governor's switch. See the module documentation of [`super`] and
//! `handle.rs` for the worker's generations.

use super::audio::{Engine, FADE, POLL_WAIT};
use super::bank::ModalCache;
use super::governor::voice_share;
use super::handle::{BuildRequest, Worker, WorkerSetup};
use super::memory::ModesFitted;
use super::output::OutputStage;
use super::params::ParamId;
use super::pool::Pool;
use crate::error::{check_positive, ParamError};
use crossbeam_channel::RecvTimeoutError;
use std::sync::atomic::Ordering;

impl Engine {
    /// Prepares for host rate `host_rate` (Hz, any positive finite rate; rates below the model's
    /// band give its band-limited sound, 1 Hz to 1.5 MHz are tested) and blocks of at most
    /// `max_block` samples (1 to 8192 are tested; longer blocks are split internally too), and
    /// waits for the voice bank of the current parameters: for offline renders, which must
    /// repeat bit for bit (from the modal cache the build takes milliseconds; a new large
    /// basis takes seconds). A host's real-time activation uses [`Self::activate_realtime`],
    /// which never waits. Starts the worker thread (once per engine) and the voice pool
    /// (`available_parallelism() - 1` workers; the `threads` parameter limits how many share
    /// each chunk). Main thread; allocates. Calling it again re-activates (new rate).
    ///
    /// Any parameter set within the table's ranges activates: if the current parameters
    /// cannot be built (a combination the models refuse), the worker builds the last model
    /// the engine played (the previous bank's parameters) or, with none, the table's defaults,
    /// and this returns `Ok(Some(error))` naming what was refused; the same message is the
    /// handle's [`last_error`](super::EngineHandle::last_error) for the editor. `Ok(None)`: the
    /// current parameters were built. `Err`: the host configuration itself is refused (rate
    /// not positive and finite, `max_block` 0, a thread the OS cannot start) or nothing builds.
    pub fn activate(
        &mut self,
        host_rate: f64,
        max_block: usize,
    ) -> Result<Option<ParamError>, ParamError> {
        if self.start(host_rate, max_block, false)? {
            self.wait_for_generation()
        } else {
            // The bank kept (same rate, same model) is the one asked for.
            Ok(None)
        }
    }

    /// As [`Self::activate`], but returns at once (a few milliseconds: it joins the voice
    /// pool's previous threads and starts new ones, and builds nothing): the worker builds the
    /// bank for the current parameters in the background and the audio thread takes it at a
    /// chunk boundary when it is ready. Until then the engine plays the bank it had if that was
    /// built for this host rate (the last good model of this instance), else silence;
    /// [`EngineHandle::is_rebuilding`] says a build is under way and
    /// [`Self::is_building_first`] that nothing can sound yet. A refused parameter set falls
    /// back as in [`Self::activate`] and is reported through
    /// [`last_error`](super::EngineHandle::last_error). For hosts (an activation runs on the
    /// host's main thread, which must not freeze). `Err`: the host configuration is refused.
    pub fn activate_realtime(
        &mut self,
        host_rate: f64,
        max_block: usize,
    ) -> Result<(), ParamError> {
        self.start(host_rate, max_block, true).map(|_| ())
    }

    /// Turns the CPU governor on or off (main thread, between activations, or any time
    /// through `&mut`; `engine/governor.rs`): on, a note's band comes down and voices end
    /// so that the voices' measured cost stays within the `cpu_budget` parameter. For a live
    /// host; off (the default) every note keeps its full band, as offline renders need.
    pub fn set_governor(&mut self, on: bool) {
        self.governor.on = on;
        self.governor.load = 0.0;
        self.governor.cooldown = 0;
    }

    /// What the CPU governor has done since the engine was created: `(notes started below
    /// their band, voices ended)`.
    pub fn governor_counts(&self) -> (u64, u64) {
        (self.governor.reduced, self.governor.shed)
    }

    /// How the strings of the drone bank in use were tuned (`None`: no bank, or not a drone).
    pub fn drone_tuning(&self) -> Option<super::DroneTuning> {
        self.bank.as_ref().and_then(|b| b.drone_tuning)
    }

    /// The mode count the worker lowered to fit the playing string bank's voices to the CPU
    /// budget (`engine/string_bank.rs`), if it did. Any thread that owns the engine.
    pub fn modes_fitted(&self) -> Option<ModesFitted> {
        self.bank.as_ref().and_then(|b| b.fitted)
    }

    /// Heap bytes this engine holds for its models: the coupling tensors of the banks it has
    /// (the one playing, one fading out or held by a late job) and of the worker's modal
    /// cache. Voice states, a few vectors of modes each, are not counted. Any thread that owns
    /// the engine.
    pub fn memory_bytes(&self) -> u64 {
        let banks: usize = [
            self.bank.as_ref(),
            self.jobs.held.as_ref(),
            self.handover.retiring.as_ref().map(|r| &r.0),
        ]
        .into_iter()
        .flatten()
        .map(|b| b.tensor_bytes)
        .sum();
        banks as u64 + self.status.cache_bytes.load(Ordering::Acquire)
    }

    /// Whether the bank playing is a preview (a small model of the same instrument a live host
    /// plays while the full one builds; `Bank::preview_of`). Any thread that owns the engine.
    pub fn is_preview(&self) -> bool {
        self.bank.as_ref().is_some_and(|b| b.preview)
    }

    /// Whether the engine has no bank to play yet (after [`Self::activate_realtime`], until
    /// the worker's first bank arrives): notes are silent. Any thread that owns the engine.
    pub fn is_building_first(&self) -> bool {
        self.bank.is_none() && self.jobs.held.is_none()
    }

    /// The common part of both activations: checks the configuration, stops the pool, opens a
    /// new generation, keeps the current bank when it can still play, asks the worker for the
    /// generation's bank when needed and starts the worker (once) and the pool. Returns
    /// whether the worker was asked for a bank (false: the kept bank is the one asked for).
    /// `realtime`: nothing waits for the bank, so a preview is asked for when nothing can
    /// play until the bank arrives.
    fn start(
        &mut self,
        host_rate: f64,
        max_block: usize,
        realtime: bool,
    ) -> Result<bool, ParamError> {
        check_positive("host_rate", host_rate)?;
        if max_block == 0 {
            return Err(ParamError::new("max_block", 0, "integer >= 1"));
        }
        self.deactivate();
        // The pool is stopped: no job runs, a held bank can be dropped here.
        if let Some(h) = self.jobs.held.take() {
            self.bank.get_or_insert(h);
        }
        self.jobs.deferred_len = 0;
        self.jobs.reset_pending = false;
        // Banks still queued belong to an earlier generation: drop them here (main thread).
        self.handover.drop_in_flight();
        let wanted = self.params.snapshot();
        let last_good = self.bank.as_ref().map(|b| b.values);
        // A bank built for another host rate cannot play at this one.
        if self.bank.as_ref().is_some_and(|b| b.host_rate != host_rate) {
            self.bank = None;
        }
        // A string bank fitted to another voice share (the governor switched, the budget
        // changed) is built again, and a plate or drone bank priced (or not) by trials when
        // the governor is on (off) is built again priced the other way
        // (`engine/cost_trial.rs`).
        let share = self
            .governor
            .on
            .then(|| voice_share(wanted.get(ParamId::CpuBudget), self.governor.cores));
        let first_build = self.bank.as_ref().is_none_or(|b| {
            b.values.rebuild_key() != wanted.rebuild_key()
                || (b.kind.is_string() && b.share != share)
                || (!b.kind.is_string() && b.share.is_some() != share.is_some())
        });
        self.generation += 1;
        if let Some(b) = self.bank.as_mut() {
            b.generation = self.generation;
        }
        if let Ok(mut r) = self.request.lock() {
            *r = BuildRequest {
                host_rate,
                generation: self.generation,
                active: true,
                last_good,
                preview: realtime && first_build && self.bank.is_none(),
                governed: self.governor.on,
                kept: (!first_build).then(|| wanted.rebuild_key()),
            };
        }
        self.host_rate = host_rate;
        self.max_block = max_block;
        self.fade_len = ((FADE * host_rate) as usize).max(1);
        self.counts.guarded_past += self.output.guarded();
        self.output = OutputStage::new(host_rate);
        self.values = wanted;
        self.notes.applied = (wanted, self.notes.bend);
        self.notes.tuning_applied = self.notes.tuning_seen;
        self.reset();
        if self.worker.is_none() {
            let worker = Worker::spawn(WorkerSetup {
                params: self.params.clone(),
                status: self.status.clone(),
                request: self.request.clone(),
                bank_tx: self.bank_tx.clone(),
                retire_rx: self.retire_rx.clone(),
                cache: ModalCache::default(),
                board: self.jobs.board.clone(),
                built_key: wanted.rebuild_key(),
                next_id: 1,
                cores: self.governor.cores,
            })
            .map_err(|e| ParamError::new("worker thread", e, "a thread the OS can start"))?;
            self.worker = Some(worker);
        }
        let pool = Pool::start(Pool::default_workers(), self.jobs.board.clone())
            .map_err(|e| ParamError::new("voice pool thread", e, "a thread the OS can start"))?;
        self.jobs.pool = Some(pool);
        Ok(first_build)
    }

    /// Waits (main thread) until the worker has built this generation's first bank and
    /// installs it; returns the build's outcome (see [`Self::activate`]).
    fn wait_for_generation(&mut self) -> Result<Option<ParamError>, ParamError> {
        loop {
            match self.handover.bank_rx.recv_timeout(POLL_WAIT) {
                Ok(bank) if bank.generation == self.generation => {
                    self.values = bank.values;
                    self.notes.applied = (bank.values, self.notes.bend);
                    // The bank it replaces (if any) is dropped here, on the main thread.
                    self.bank = Some(bank);
                    self.reset();
                    break;
                }
                Ok(_) => {}
                Err(RecvTimeoutError::Disconnected) => {
                    return Err(ParamError::new(
                        "worker thread",
                        "stopped",
                        "a running worker",
                    ))
                }
                Err(RecvTimeoutError::Timeout) => {}
            }
            if let Some((g, Err(e))) = self.status.outcome.lock().ok().and_then(|o| o.clone()) {
                if g == self.generation {
                    return Err(e);
                }
            }
        }
        match self.status.outcome.lock().ok().and_then(|o| o.clone()) {
            Some((g, result)) if g == self.generation => result,
            _ => Ok(None),
        }
    }

    /// Stops the voice pool's workers (main thread; a worker in the middle of a voice finishes
    /// it first) and tells the worker thread to build nothing until the next activation (it is
    /// not joined: a build under way finishes in the background). The engine keeps its bank
    /// and can still process, on the audio thread alone and without rebuilds, until
    /// re-activated.
    pub fn deactivate(&mut self) {
        if let Ok(mut r) = self.request.lock() {
            r.active = false;
        }
        if let Some(mut p) = self.jobs.pool.take() {
            p.stop();
            self.counts.worker_jobs_past += p.worker_jobs();
        }
    }
}
