//! The control side of the engine: [`EngineHandle`] (GUI commands in, telemetry out, worker
//! status) and the worker thread that builds voice banks.
//!
//! The worker lives as long as its engine (started by the first activation, joined when the
//! engine is dropped), so an activation never waits for it and its in-memory modal cache
//! outlives activations. Each activation is a new *generation* ([`BuildRequest`]): the worker
//! builds the first bank of a generation at once (the activation's build, or the last model
//! that builds when the parameters are refused) and tags every bank with its generation; the
//! audio thread takes only banks of its own. Within a generation the worker polls
//! [`SharedParams`] every few milliseconds; when the values of the parameters that trigger a
//! rebuild ([`super::ParamInfo::rebuild`]) have changed and stayed unchanged for [`DEBOUNCE`]
//! (a knob being dragged), it builds a new bank and sends it to the audio thread through a
//! bounded crossbeam channel (lock-free `try_recv` on the audio side). Banks the audio thread
//! has replaced come back through a second channel and are dropped here, never on the audio
//! thread. While the engine is deactivated the worker builds nothing.

use super::bank::{Bank, ModalCache};
use super::events::GuiCommand;
use super::governor::voice_share;
use super::params::{ParamId, ParamValues, SharedParams};
use super::telemetry::Telemetry;
use crate::error::ParamError;
use crossbeam_channel::{Receiver, Sender, TrySendError};
use ringbuf::traits::{Consumer, Producer};
use ringbuf::{HeapCons, HeapProd};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long the rebuild parameters must stay unchanged before the worker builds.
pub const DEBOUNCE: Duration = Duration::from_millis(30);

/// What the engine does with a parameter set it cannot build (appended to the error).
pub(crate) const KEPT: &str = "the last model that could be built keeps playing";

/// Worker polling period.
const POLL: Duration = Duration::from_millis(4);

/// State shared by worker, audio thread and GUI. The audio thread reads only the atomics.
#[derive(Debug, Default)]
pub(crate) struct WorkerStatus {
    /// A build is in progress.
    pub rebuilding: AtomicBool,
    /// Banks built by the worker (the activations' own builds excluded).
    pub built: AtomicU64,
    /// Heap bytes of the coupling tensors in the worker's modal cache, after its last build.
    pub cache_bytes: AtomicU64,
    /// The last build error (worker writes, GUI reads; never the audio thread).
    pub error: Mutex<Option<String>>,
    /// The outcome of the latest generation's first build, with its generation: `Ok(None)`
    /// built as asked, `Ok(Some(e))` refused and the last good model or the defaults built,
    /// `Err(e)` nothing built (worker writes, the activating main thread reads).
    pub outcome: Mutex<Option<(u64, BuildOutcome)>>,
}

/// The outcome of a generation's first build: `Ok(None)` built as asked, `Ok(Some(refusal))`
/// a fallback built, `Err` nothing built.
pub(crate) type BuildOutcome = Result<Option<ParamError>, ParamError>;

/// What the worker builds for: written by the engine's `activate`/`deactivate` (main thread),
/// read by the worker at every poll (never by the audio thread).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BuildRequest {
    /// Host rate of the generation's banks (Hz).
    pub host_rate: f64,
    /// The activation this request belongs to (banks carry it; the audio thread takes only
    /// its own generation's).
    pub generation: u64,
    /// The engine is active: the worker builds (deactivated: it only drops returned banks).
    pub active: bool,
    /// The parameters of the bank the engine played last (the fallback when the wanted set is
    /// refused).
    pub last_good: Option<ParamValues>,
    /// The engine has nothing to play until the first bank arrives (a real-time activation
    /// without a bank for this rate): the worker first builds and sends the preview
    /// (`Bank::preview_of`), then the full model.
    pub preview: bool,
    /// The CPU governor is on: string banks are fitted to one voice's share of the budget
    /// (`governor::voice_share`, `string_bank`).
    pub governed: bool,
    /// `None`: the generation needs a first build. `Some`: the engine kept a bank of these
    /// parameters at this rate, with this rebuild key, which the worker compares the
    /// parameters with from then on. Not the parameters the worker reads when it sees the
    /// generation: those may already have moved on (a host writing a new set right after an
    /// activation), and taking them as built would never build them.
    pub kept: Option<ParamValues>,
}

/// GUI / controller side of an [`Engine`](super::Engine): send commands, read telemetry,
/// see whether a model is being rebuilt, read the last build error, and reach the shared
/// parameters. Owned by the GUI or main thread (one owner: the queues are single-producer /
/// single-consumer). Created with the engine by [`Engine::new`](super::Engine::new).
pub struct EngineHandle {
    pub(crate) params: Arc<SharedParams>,
    pub(crate) commands: HeapProd<GuiCommand>,
    pub(crate) telemetry: HeapCons<Telemetry>,
    pub(crate) status: Arc<WorkerStatus>,
}

impl EngineHandle {
    /// The parameters the engine reads (write them with [`SharedParams::set`]).
    pub fn params(&self) -> &Arc<SharedParams> {
        &self.params
    }

    /// Queues a command for the audio thread (applied at the start of its next block).
    /// Lock-free; gives the command back if the queue (256 entries) is full.
    pub fn send(&mut self, cmd: GuiCommand) -> Result<(), GuiCommand> {
        self.commands.try_push(cmd)
    }

    /// The newest telemetry frame, discarding older queued ones (`None` if nothing arrived
    /// since the last call). Lock-free.
    pub fn telemetry(&mut self) -> Option<Telemetry> {
        let mut last = None;
        while let Some(t) = self.telemetry.try_pop() {
            last = Some(t);
        }
        last
    }

    /// Whether the worker is building a new voice bank (show "rebuilding" in the editor).
    pub fn is_rebuilding(&self) -> bool {
        self.status.rebuilding.load(Ordering::Acquire)
    }

    /// Number of banks the worker has built since the engine was created.
    pub fn banks_built(&self) -> u64 {
        self.status.built.load(Ordering::Acquire)
    }

    /// The last build error (a [`crate::ParamError`] message naming the parameter, its
    /// value and the allowed range), cleared by the next successful build.
    pub fn last_error(&self) -> Option<String> {
        self.status.error.lock().ok().and_then(|e| e.clone())
    }
}

/// The running worker thread (owned by the engine; stopped and joined on deactivate/drop,
/// which happen on the host's main thread).
pub(crate) struct Worker {
    stop: Arc<AtomicBool>,
    thread: Option<JoinHandle<()>>,
}

/// Everything the worker thread owns.
pub(crate) struct WorkerSetup {
    pub params: Arc<SharedParams>,
    pub status: Arc<WorkerStatus>,
    /// The engine's current request (main thread writes, the worker reads).
    pub request: Arc<Mutex<BuildRequest>>,
    pub bank_tx: Sender<Box<Bank>>,
    pub retire_rx: Receiver<Box<Bank>>,
    pub cache: ModalCache,
    /// The voice pool's board for split steps (the banks' large plate voices offer on it).
    pub board: Arc<crate::models::plate::StepBoard>,
    /// Rebuild key of the bank the audio thread has (or will have: the last one sent).
    pub built_key: ParamValues,
    /// Identifier of the next bank.
    pub next_id: u64,
    /// Cores of the machine (the governor's default budget).
    pub cores: f64,
}

impl WorkerSetup {
    /// Marks a build as under way and returns the identifier of the bank it makes.
    fn begin_build(&mut self) -> u64 {
        self.status.rebuilding.store(true, Ordering::Release);
        self.next_id += 1;
        self.next_id - 1
    }

    /// The most one voice of a bank for `v` may cost, when the generation is governed.
    fn share(&self, current: &Current, v: &ParamValues) -> Option<f64> {
        current
            .governed
            .then(|| voice_share(v.get(ParamId::CpuBudget), self.cores))
    }
}

/// The worker's view of its current generation.
struct Current {
    host_rate: f64,
    generation: u64,
    /// The CPU governor was on when the generation started.
    governed: bool,
}

impl Worker {
    /// Starts the worker thread.
    pub fn spawn(setup: WorkerSetup) -> std::io::Result<Self> {
        let stop = Arc::new(AtomicBool::new(false));
        let s2 = stop.clone();
        let thread = std::thread::Builder::new()
            .name("noether-worker".into())
            .spawn(move || run(setup, &s2))?;
        Ok(Self {
            stop,
            thread: Some(thread),
        })
    }

    /// Asks the thread to stop and joins it.
    pub fn stop(&mut self) {
        self.stop.store(true, Ordering::Release);
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        self.stop();
    }
}

fn run(mut s: WorkerSetup, stop: &AtomicBool) {
    let mut pending: Option<(ParamValues, Instant)> = None;
    let mut current = Current {
        host_rate: 0.0,
        generation: 0,
        governed: false,
    };
    while !stop.load(Ordering::Acquire) {
        while let Ok(old) = s.retire_rx.try_recv() {
            drop(old);
        }
        let request = match s.request.lock() {
            Ok(r) => *r,
            Err(p) => *p.into_inner(),
        };
        if request.active && request.generation != current.generation {
            current = Current {
                host_rate: request.host_rate,
                generation: request.generation,
                governed: request.governed,
            };
            pending = None;
            match request.kept {
                // Parameters changed since the activation are built by the next polls.
                Some(kept) => s.built_key = kept,
                None => {
                    let wanted = s.params.snapshot();
                    s.built_key = wanted.rebuild_key();
                    if request.preview {
                        preview(&mut s, &current, &wanted, stop);
                    }
                    first_build(&mut s, &current, wanted, request.last_good, stop);
                }
            }
        } else if request.active {
            let v = s.params.snapshot();
            let key = v.rebuild_key();
            if key == s.built_key {
                pending = None;
            } else {
                match pending {
                    Some((k, since)) if k == key && since.elapsed() >= DEBOUNCE => {
                        pending = None;
                        build_and_send(&mut s, &current, &v, stop);
                        s.built_key = key;
                    }
                    Some((k, _)) if k == key => {}
                    _ => pending = Some((key, Instant::now())),
                }
            }
        }
        std::thread::sleep(POLL);
    }
}

/// The first bank of a generation: the wanted parameters, or the last good model or the
/// defaults when they are refused ([`Bank::build_playable`]); the outcome goes to
/// [`WorkerStatus::outcome`] and the refusal to the error the editor shows.
fn first_build(
    s: &mut WorkerSetup,
    current: &Current,
    wanted: ParamValues,
    last_good: Option<ParamValues>,
    stop: &AtomicBool,
) {
    let id = s.begin_build();
    let share = s.share(current, &wanted);
    let built = Bank::build_playable(
        wanted,
        last_good,
        current.host_rate,
        &mut s.cache,
        &s.board,
        id,
        share,
    );
    let (bank, outcome) = match built {
        Ok((bank, refused)) => (Some(bank), Ok(refused)),
        Err(e) => (None, Err(e)),
    };
    if let Ok(mut slot) = s.status.error.lock() {
        *slot = match &outcome {
            Ok(None) => None,
            Ok(Some(e)) | Err(e) => Some(format!("{e}; {KEPT}")),
        };
    }
    // The outcome is published before the bank, so a blocking activation that receives the
    // bank reads its outcome.
    if let Ok(mut slot) = s.status.outcome.lock() {
        *slot = Some((current.generation, outcome));
    }
    if let Some(mut bank) = bank {
        bank.generation = current.generation;
        send(s, bank, stop);
    }
    s.status.rebuilding.store(false, Ordering::Release);
}

/// Builds and sends the preview of `wanted` (`Bank::preview_of`), if it has one and builds;
/// a refusal is left to the full build that follows, which reports it.
fn preview(s: &mut WorkerSetup, current: &Current, wanted: &ParamValues, stop: &AtomicBool) {
    if Bank::preview_of(wanted).is_none() && !wanted.model().is_network() {
        return;
    }
    let id = s.begin_build();
    if let Some(mut bank) =
        Bank::build_preview(wanted, current.host_rate, &mut s.cache, &s.board, id)
    {
        bank.generation = current.generation;
        send(s, Box::new(bank), stop);
    }
}

/// Sends `bank` to the audio thread, waiting while the channel holds an earlier bank the
/// audio thread has not taken (dropping returned banks meanwhile) unless the worker is asked
/// to stop or the engine's generation moves on.
fn send(s: &mut WorkerSetup, mut bank: Box<Bank>, stop: &AtomicBool) {
    s.status
        .cache_bytes
        .store(s.cache.heap_bytes() as u64, Ordering::Release);
    loop {
        match s.bank_tx.try_send(bank) {
            Ok(()) | Err(TrySendError::Disconnected(_)) => return,
            Err(TrySendError::Full(b)) => {
                bank = b;
                let moved_on = s
                    .request
                    .lock()
                    .is_ok_and(|r| r.generation != bank.generation || !r.active);
                if stop.load(Ordering::Acquire) || moved_on {
                    return;
                }
                while let Ok(old) = s.retire_rx.try_recv() {
                    drop(old);
                }
                std::thread::sleep(POLL);
            }
        }
    }
}

fn build_and_send(s: &mut WorkerSetup, current: &Current, v: &ParamValues, stop: &AtomicBool) {
    let id = s.begin_build();
    let share = s.share(current, v);
    match Bank::build(v, current.host_rate, &mut s.cache, &s.board, id, share) {
        Ok(mut bank) => {
            if let Ok(mut e) = s.status.error.lock() {
                *e = None;
            }
            bank.generation = current.generation;
            send(s, Box::new(bank), stop);
            s.status.built.fetch_add(1, Ordering::AcqRel);
        }
        Err(e) => {
            if let Ok(mut slot) = s.status.error.lock() {
                *slot = Some(format!("{e}; {KEPT}"));
            }
        }
    }
    s.status.rebuilding.store(false, Ordering::Release);
}
