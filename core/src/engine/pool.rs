//! The voice pool: worker threads that run the voices of a chunk in parallel with the audio
//! thread, lock-free and without allocating.
//!
//! # Jobs
//!
//! A bank owns one [`Lane`] per voice (its [`Lanes`], allocated at build): the voice's output
//! buffers for one chunk (simulation rate) and an atomic state, the only thing the threads
//! share about it:
//!
//! ```text
//! IDLE ──(audio: queue)──> QUEUED ──(any participant: CAS)──> RUNNING ──(same: store)──> DONE
//!  ^                                                                                      │
//!  └────────────────────────────(audio: take the result)─────────────────────────────────┘
//! ```
//!
//! The audio thread owns the voice and the buffers in `IDLE` and `DONE`; the participant whose
//! compare-and-swap moved the lane to `RUNNING` owns them until it stores `DONE` (release),
//! and the audio thread reads the result after loading `DONE` (acquire). A chunk: the audio
//! thread queues its sounding voices, publishes the bank's lanes and bumps the epoch, wakes
//! the invited workers, claims lanes itself like any worker, then waits a bounded time for the
//! lanes the workers hold ([`Pool::run`]).
//!
//! # Late jobs
//!
//! A worker can be pre-empted in the middle of a voice. When the wait ends with a lane still
//! `RUNNING`, the voice's chunk is left out of the mix (counted as late) and the audio thread
//! does not touch that voice, its buffers, or the bank's voice list until the lane is `DONE`
//! (the engine then holds the bank aside, see `Engine`); the result is taken later and its
//! samples dropped. A bank leaves the audio thread (to be dropped by the builder thread) only
//! when the pool is quiescent ([`Pool::quiescent`]): no worker between its load of the
//! published lanes and the end of its scan, so no worker can reach the bank's memory.
//!
//! # Waking
//!
//! Workers spin for [`SPIN`] after their last job (the next chunk of the same host block
//! follows within microseconds), then park ([`std::thread::park`]); the audio thread unparks
//! only the invited workers that announced they were parking (a Dekker handshake on
//! sequentially consistent atomics: a worker either sees the new epoch or is seen parking).
//! Idle workers therefore sleep in the kernel between host blocks.
//!
//! # Split steps
//!
//! In a chunk whose sounding voices split their steps (a plate with a large coupling tensor,
//! `models::plate::step_board`), the invited workers, once out of voice jobs, take the halves
//! those voices offer on the pool's [`StepBoard`] until the audio thread ends the chunk; with a
//! single such voice, the audio thread keeps the voice and the worker only helps. A worker
//! does this while counted in `busy`, so the quiescence rule above also covers the jobs on the
//! board (they belong to a bank's voices).
//!
//! Threads: [`Pool::start`] and [`Pool::stop`] on the main thread (they spawn and join);
//! [`Pool::run`], [`Pool::quiescent`], [`Lanes`]' queueing and taking on the audio thread;
//! the workers run [`Lanes::claim`] and [`StepBoard::help`] only.

use super::voice::Voice;
use crate::models::plate::StepBoard;
use std::cell::{Cell, UnsafeCell};
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicU64, AtomicU8, AtomicUsize, Ordering};
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// How long a worker spins for the next chunk before it parks (s of wall time). A 64-sample
/// chunk at 48 kHz lasts 1.3 ms; the audio thread's serial part between two chunks of one
/// block (mix, resampler, events) takes tens of microseconds.
pub const SPIN: Duration = Duration::from_micros(50);

const IDLE: u8 = 0;
const QUEUED: u8 = 1;
const RUNNING: u8 = 2;
const DONE: u8 = 3;

thread_local! {
    // `const`: reading it never allocates, so an allocator may call `in_voice_job`.
    static IN_JOB_LOOP: Cell<bool> = const { Cell::new(false) };
}

/// Whether the calling thread is a pool worker inside its job loop (from its start to its
/// stop, parking included). For allocation checks: a test's global allocator can count the
/// allocations made on such threads (`noether_testkit::alloc`). Any thread; never allocates.
pub fn in_voice_job() -> bool {
    IN_JOB_LOOP.try_with(|c| c.get()).unwrap_or(false)
}

/// A finished job's result: whether the voice stayed finite and under the ceiling, its
/// simulation-rate left and right output, and its band above's (the bank's above rate).
pub(crate) type LaneOutput<'a> = (bool, [&'a [f32]; 2], [&'a [f32]; 2]);

/// One voice's job slot: its state, the job's parameters, and the voice's output buffers for
/// one chunk. Owned by a bank (allocated at build).
pub(crate) struct Lane {
    state: AtomicU8,
    /// The voice to run (written by the audio thread before `QUEUED`).
    voice: AtomicPtr<Voice>,
    /// Simulation samples of the job.
    len: AtomicUsize,
    /// Output gain, `f64` bits.
    gain: AtomicU64,
    /// `Voice::run`'s result: `false` when the voice diverged (its samples are dropped).
    ok: AtomicBool,
    /// Whether the voice was sounding at the end of the last chunk (audio thread; read-outs
    /// while the bank is held by a late job, when the voices themselves must not be read).
    sounding: AtomicBool,
    /// Left and right output (simulation rate, `max_in` samples each).
    buf: UnsafeCell<[Box<[f32]>; 2]>,
    /// Host-rate samples of the job's band above the simulation.
    above_len: AtomicUsize,
    /// Left and right output of the band above (the bank's above rate, `max_out` samples each).
    above: UnsafeCell<[Box<[f32]>; 2]>,
}

// SAFETY: the only non-`Sync` fields are `buf` and `above`, each accessed mutably by one
// thread at a time: the participant that moved `state` from QUEUED to RUNNING (until its
// release store of DONE), otherwise the audio thread (which reads them only after an acquire
// load of DONE or IDLE and writes nothing into them). See the module doc's state diagram.
unsafe impl Sync for Lane {}

/// The lanes of a bank, one per voice, in a heap allocation of their own (workers reach them
/// through one thin pointer, never through the bank).
pub(crate) struct Lanes {
    lanes: Box<[Lane]>,
}

impl Lanes {
    /// `voices` lanes with buffers of `max_in` simulation-rate and `max_out` band-above samples
    /// (builder thread; allocates).
    pub fn new(voices: usize, max_in: usize, max_out: usize) -> Box<Lanes> {
        // The chunk loop keeps a bit mask of queued lanes in a u64.
        assert!(voices <= 64, "at most 64 voices per bank, not {voices}");
        let lanes = (0..voices)
            .map(|_| Lane {
                state: AtomicU8::new(IDLE),
                voice: AtomicPtr::new(std::ptr::null_mut()),
                len: AtomicUsize::new(0),
                gain: AtomicU64::new(0),
                ok: AtomicBool::new(true),
                sounding: AtomicBool::new(false),
                buf: UnsafeCell::new([vec![0.0; max_in].into(), vec![0.0; max_in].into()]),
                above_len: AtomicUsize::new(0),
                above: UnsafeCell::new([vec![0.0; max_out].into(), vec![0.0; max_out].into()]),
            })
            .collect();
        Box::new(Lanes { lanes })
    }

    /// Number of lanes.
    pub fn len(&self) -> usize {
        self.lanes.len()
    }

    /// Whether lane `i` is at rest: the audio thread owns its voice (audio thread).
    pub fn is_idle(&self, i: usize) -> bool {
        self.lanes[i].state.load(Ordering::Acquire) == IDLE
    }

    /// Whether a job of these lanes is queued or running (a worker may still use the bank).
    pub fn any_busy(&self) -> bool {
        self.busy_among(u64::MAX)
    }

    /// Whether a job of the lanes in the bit mask `mask` (bit `i`: lane `i`) is queued or
    /// running.
    fn busy_among(&self, mask: u64) -> bool {
        self.lanes.iter().enumerate().any(|(i, l)| {
            mask >> i & 1 == 1 && matches!(l.state.load(Ordering::Acquire), QUEUED | RUNNING)
        })
    }

    /// Records whether lane `i`'s voice is sounding (audio thread, end of a chunk).
    pub fn set_sounding(&self, i: usize, sounding: bool) {
        self.lanes[i].sounding.store(sounding, Ordering::Relaxed);
    }

    /// Voices sounding at the end of the last chunk, as recorded by [`Self::set_sounding`].
    pub fn sounding(&self) -> usize {
        self.lanes
            .iter()
            .filter(|l| l.sounding.load(Ordering::Relaxed))
            .count()
    }

    /// Queues voice `voice` (lane `i`, at rest) for `len` simulation samples and `above_len`
    /// samples of its band above (at the bank's above rate), at output `gain` (audio thread).
    /// The caller gives up the voice until [`Self::take`] returns it.
    pub fn queue(&self, i: usize, voice: *mut Voice, (len, above_len): (usize, usize), gain: f64) {
        let l = &self.lanes[i];
        debug_assert_eq!(l.state.load(Ordering::Relaxed), IDLE);
        l.voice.store(voice, Ordering::Relaxed);
        l.len.store(len, Ordering::Relaxed);
        l.above_len.store(above_len, Ordering::Relaxed);
        l.gain.store(gain.to_bits(), Ordering::Relaxed);
        l.state.store(QUEUED, Ordering::Release);
    }

    /// Runs queued jobs until none is left, scanning from lane `from` (any participant).
    /// Returns the number of jobs this call ran.
    pub fn claim(&self, from: usize) -> usize {
        let n = self.lanes.len();
        let mut ran = 0;
        for k in 0..n {
            let l = &self.lanes[(from + k) % n];
            if l.state
                .compare_exchange(QUEUED, RUNNING, Ordering::Acquire, Ordering::Relaxed)
                .is_ok()
            {
                let len = l.len.load(Ordering::Relaxed);
                let above_len = l.above_len.load(Ordering::Relaxed);
                let gain = f64::from_bits(l.gain.load(Ordering::Relaxed));
                let v = l.voice.load(Ordering::Relaxed);
                // SAFETY: the successful QUEUED → RUNNING exchange makes this thread the only
                // user of the lane's buffers and of its voice until the DONE store below; the
                // acquire pairs with `queue`'s release, so `voice` and `len` are this job's.
                // The voice pointer was derived by the audio thread from the bank's voice list
                // for this job, and the bank outlives the job (it leaves the audio thread only
                // when the pool is quiescent). `len` ≤ the buffers' length (`max_in`), and
                // `above_len` ≤ `max_out`.
                let ok = unsafe {
                    let [bl, br] = &mut *l.buf.get();
                    let (bl, br) = (&mut bl[..len], &mut br[..len]);
                    bl.fill(0.0);
                    br.fill(0.0);
                    let [al, ar] = &mut *l.above.get();
                    let (al, ar) = (&mut al[..above_len], &mut ar[..above_len]);
                    al.fill(0.0);
                    ar.fill(0.0);
                    // The job's wall time, for the CPU governor (two clock reads per voice
                    // and chunk; no allocation).
                    let t0 = Instant::now();
                    let ok = (*v).run(bl, br, gain) && (*v).run_above(al, ar, gain);
                    (*v).job_seconds = t0.elapsed().as_secs_f64();
                    ok
                };
                l.ok.store(ok, Ordering::Relaxed);
                l.state.store(DONE, Ordering::Release);
                ran += 1;
            }
        }
        ran
    }

    /// Takes lane `i`'s result if its job is done (audio thread): `Some((ok, [left, right],
    /// [above left, above right]))` (simulation rate, then the band above at the bank's above
    /// rate),
    /// the lane back at rest and its voice back with the audio thread. The caller drops the
    /// slices before it queues lane `i` again (the audio thread's chunk loop does: it takes
    /// every result before it queues the next chunk).
    pub fn take(&self, i: usize) -> Option<LaneOutput<'_>> {
        let l = &self.lanes[i];
        if l.state.load(Ordering::Acquire) != DONE {
            return None;
        }
        l.state.store(IDLE, Ordering::Relaxed);
        let len = l.len.load(Ordering::Relaxed);
        // SAFETY: the acquire load of DONE pairs with the participant's release store, after
        // which it no longer touches the buffers; the lane is now IDLE, and only the audio
        // thread (the caller) can queue it again, which by this method's contract happens
        // after the returned slices are dropped. So no writer aliases this shared borrow.
        let above_len = l.above_len.load(Ordering::Relaxed);
        let [bl, br] = unsafe { &*l.buf.get() };
        // SAFETY: as for `buf`.
        let [al, ar] = unsafe { &*l.above.get() };
        Some((
            l.ok.load(Ordering::Relaxed),
            [&bl[..len], &br[..len]],
            [&al[..above_len], &ar[..above_len]],
        ))
    }
}

/// What the audio thread shares with the workers.
struct Shared {
    /// Bumped (sequentially consistent) for every chunk handed over.
    epoch: AtomicU64,
    /// The lanes of the chunk in progress (null between chunks).
    table: AtomicPtr<Lanes>,
    /// Workers invited to the chunk in progress (workers `0..invited`).
    invited: AtomicUsize,
    /// Workers between their load of `table` and the end of their scan.
    busy: AtomicUsize,
    stop: AtomicBool,
    /// Per worker: it announced it is about to park.
    parking: Box<[AtomicBool]>,
    /// Per worker: CPU time consumed so far (ns of its thread clock).
    cpu_ns: Box<[AtomicU64]>,
    /// Jobs run by the workers (not by the audio thread) since the start.
    worker_jobs: AtomicU64,
    /// Where the voices of a bank with split steps offer their steps' second halves.
    board: Arc<StepBoard>,
    /// The chunk in progress has voices with split steps: invited workers help on the board
    /// after their voice jobs, until the chunk ends.
    assist: AtomicBool,
}

/// The pool of worker threads (owned by the engine; started by `activate`, stopped by
/// `deactivate` and on drop).
pub(crate) struct Pool {
    shared: Arc<Shared>,
    threads: Vec<JoinHandle<()>>,
    /// Workers' CPU time already reported (ns).
    cpu_seen: u64,
}

impl Pool {
    /// Workers for this machine: `available_parallelism() - 1` (the audio thread is the other
    /// participant), 0 if the OS does not tell.
    pub fn default_workers() -> usize {
        std::thread::available_parallelism().map_or(0, |n| n.get() - 1)
    }

    /// Starts `workers` worker threads that help on `board` when a chunk asks (main thread;
    /// allocates and spawns).
    pub fn start(workers: usize, board: Arc<StepBoard>) -> std::io::Result<Pool> {
        let shared = Arc::new(Shared {
            epoch: AtomicU64::new(0),
            table: AtomicPtr::new(std::ptr::null_mut()),
            invited: AtomicUsize::new(0),
            busy: AtomicUsize::new(0),
            stop: AtomicBool::new(false),
            parking: (0..workers).map(|_| AtomicBool::new(false)).collect(),
            cpu_ns: (0..workers).map(|_| AtomicU64::new(0)).collect(),
            worker_jobs: AtomicU64::new(0),
            board,
            assist: AtomicBool::new(false),
        });
        let mut pool = Pool {
            shared,
            threads: Vec::with_capacity(workers),
            cpu_seen: 0,
        };
        for k in 0..workers {
            let s = pool.shared.clone();
            let t = std::thread::Builder::new()
                .name(format!("noether-voices-{k}"))
                .spawn(move || worker(&s, k));
            match t {
                Ok(t) => pool.threads.push(t),
                Err(e) => {
                    pool.stop();
                    return Err(e);
                }
            }
        }
        Ok(pool)
    }

    /// Worker threads (the audio thread excluded).
    pub fn workers(&self) -> usize {
        self.threads.len()
    }

    /// Stops and joins the workers (main thread). A worker in the middle of a job finishes it
    /// first, so no job is left running.
    pub fn stop(&mut self) {
        self.shared.stop.store(true, Ordering::SeqCst);
        for t in &self.threads {
            t.thread().unpark();
        }
        for t in self.threads.drain(..) {
            let _ = t.join();
        }
    }

    /// Runs the jobs queued in `lanes` (the lanes in the bit mask `queued`) with up to
    /// `helpers` workers besides the calling audio thread, which claims jobs too; then waits
    /// at most `wait` for the jobs the workers hold. Returns with each of those jobs `DONE`
    /// or, if a worker was late, still `RUNNING`. With `assist` (the bank's voices split their
    /// steps, `step_board`), the workers also take the halves offered on the board until the
    /// chunk ends, and a single queued voice is left to the audio thread (so that a worker
    /// helps it rather than runs it alone). Audio thread: no allocation, no lock; `unpark` is
    /// a futex wake, made only when a worker sleeps.
    pub fn run(&self, lanes: &Lanes, queued: u64, helpers: usize, wait: Duration, assist: bool) {
        let helpers = helpers.min(self.threads.len());
        if helpers == 0 {
            lanes.claim(0);
            return;
        }
        let s = &*self.shared;
        let alone = assist && queued.count_ones() == 1;
        s.invited.store(helpers, Ordering::SeqCst);
        s.assist.store(assist, Ordering::SeqCst);
        s.board.set_open(assist);
        let table = if alone {
            std::ptr::null_mut()
        } else {
            lanes as *const Lanes as *mut Lanes
        };
        s.table.store(table, Ordering::SeqCst);
        s.epoch.fetch_add(1, Ordering::SeqCst);
        for (k, t) in self.threads.iter().enumerate().take(helpers) {
            if s.parking[k].load(Ordering::SeqCst) {
                t.thread().unpark();
            }
        }
        lanes.claim(0);
        // Bounded wait for the jobs the workers claimed: spin (no system call; a yield could
        // give the core away for a whole time slice on a loaded machine) until `wait`.
        let start = Instant::now();
        while lanes.busy_among(queued) && start.elapsed() < wait {
            std::hint::spin_loop();
        }
        s.board.set_open(false);
        s.assist.store(false, Ordering::SeqCst);
        s.table.store(std::ptr::null_mut(), Ordering::SeqCst);
    }

    /// Whether no worker can reach any bank's memory: none holds the lanes published by a
    /// chunk that has ended (audio thread, between chunks; see the module doc). A bank may
    /// leave the audio thread only then.
    pub fn quiescent(&self) -> bool {
        // The audio thread stored a null `table` (sequentially consistent) at the end of its
        // last chunk; a worker counted in `busy` after this load reads that null or a later
        // chunk's lanes, never a bank handed away after this point.
        self.shared.busy.load(Ordering::SeqCst) == 0
    }

    /// Workers' CPU time since the previous call (s; audio thread).
    pub fn take_cpu(&mut self) -> f64 {
        let total: u64 = self
            .shared
            .cpu_ns
            .iter()
            .map(|c| c.load(Ordering::Relaxed))
            .sum();
        let d = total.saturating_sub(self.cpu_seen);
        self.cpu_seen = total;
        d as f64 * 1e-9
    }

    /// Jobs run by the workers since the start.
    pub fn worker_jobs(&self) -> u64 {
        self.shared.worker_jobs.load(Ordering::Relaxed)
    }
}

impl Drop for Pool {
    fn drop(&mut self) {
        self.stop();
    }
}

/// CPU time of the calling thread (ns), `None` where the platform has no thread clock. Not
/// I/O: a clock read (one syscall at most).
fn thread_cpu_ns() -> Option<u64> {
    crate::clock::thread_cpu_time().map(|d| d.as_nanos() as u64)
}

/// A worker's loop: wait for a new epoch (spin, then park), run the jobs it can claim,
/// publish its CPU time. No allocation, no lock, no I/O.
fn worker(s: &Shared, k: usize) {
    IN_JOB_LOOP.with(|c| c.set(true));
    let mut seen = s.epoch.load(Ordering::SeqCst);
    // Without a thread clock: wall time from wake to the end of the scan, spin excluded.
    let mut active_ns = 0u64;
    loop {
        // Wait for the next chunk.
        let spin_start = Instant::now();
        loop {
            if s.stop.load(Ordering::SeqCst) {
                IN_JOB_LOOP.with(|c| c.set(false));
                return;
            }
            if s.epoch.load(Ordering::SeqCst) != seen {
                break;
            }
            if spin_start.elapsed() < SPIN {
                std::hint::spin_loop();
                continue;
            }
            s.parking[k].store(true, Ordering::SeqCst);
            if s.epoch.load(Ordering::SeqCst) == seen && !s.stop.load(Ordering::SeqCst) {
                std::thread::park();
            }
            s.parking[k].store(false, Ordering::SeqCst);
        }
        seen = s.epoch.load(Ordering::SeqCst);
        let woke = Instant::now();
        if k < s.invited.load(Ordering::SeqCst) {
            s.busy.fetch_add(1, Ordering::SeqCst);
            let t = s.table.load(Ordering::SeqCst);
            if !t.is_null() {
                // SAFETY: `t` was published by the audio thread for a chunk in progress and
                // this worker is counted in `busy`, so the bank owning the lanes cannot be
                // handed away (and dropped) before the decrement below (`Pool::quiescent`).
                let lanes = unsafe { &*t };
                let n = lanes.len().max(1);
                let ran = lanes.claim((k + 1) * n / (s.invited.load(Ordering::Relaxed) + 1));
                s.worker_jobs.fetch_add(ran as u64, Ordering::Relaxed);
            }
            // Help with the steps' second halves until the chunk ends (bounded by the chunk:
            // the audio thread clears `assist` at its end; the next chunk bumps the epoch).
            while s.assist.load(Ordering::SeqCst)
                && s.epoch.load(Ordering::SeqCst) == seen
                && !s.stop.load(Ordering::SeqCst)
            {
                // SAFETY: this worker is counted in `busy`, so no bank (and no job on the
                // board, which belong to a bank's voices) is dropped before the decrement
                // below (`Pool::quiescent`).
                if !unsafe { s.board.help() } {
                    std::hint::spin_loop();
                }
            }
            s.busy.fetch_sub(1, Ordering::SeqCst);
        }
        active_ns += woke.elapsed().as_nanos() as u64;
        let cpu = thread_cpu_ns().unwrap_or(active_ns);
        s.cpu_ns[k].store(cpu, Ordering::Relaxed);
    }
}
