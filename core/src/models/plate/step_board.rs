//! The second half of a SAV step offered to another real-time thread, with a bounded wait and
//! a defined fallback: how the engine's voice pool shares one heavy voice's step between two
//! cores (the offline [`super::StepJoin`] waits without a bound, which the audio thread may
//! not).
//!
//! # Protocol
//!
//! A plate model whose SAV kernel is split ([`super::ModalCoupling::split_row`]) owns one
//! [`HalfJob`] for the second half of the in-plane rows. Each step, its owner (the thread that
//! steps the voice):
//!
//! 1. if the job is at rest and the [`StepBoard`] is open, copies `q` and the in-plane
//!    weights into the job, marks it `POSTED` (release) and puts it on the board;
//! 2. runs the first half itself;
//! 3. takes the job off the board and tries `POSTED → IDLE`: if no helper took it, it runs the
//!    second half itself (no wait); if a helper did (`TAKEN`), it waits for `DONE` at most
//!    [`StepBoard::wait_for`] its own half's time, then copies the helper's result; when the
//!    wait runs out (the helper was pre-empted), it runs the second half itself into its own
//!    buffers and leaves the job to the helper, offering nothing until the job is `DONE`.
//!
//! ```text
//! IDLE ──(owner: post)──> POSTED ──(helper: CAS)──> TAKEN ──(helper: store)──> DONE
//!   ^                        │                                                    │
//!   └────(owner: CAS, runs the half itself)──┘    (owner: result copied) ─────────┘
//! ```
//!
//! The helper reads only the job's own copies of `q` and the weights and writes only the job's
//! outputs, so a late helper never races the owner, which has moved on. Both run the same
//! kernel on the same inputs, so the step has the same bits whoever ran the half.
//!
//! # Lifetime
//!
//! A helper reaches a job through the board's pointer, so the job (and the model's coupling
//! tensor, which it reads) must outlive every helper that may have loaded it. The engine
//! guarantees it as it does for voice jobs: helpers run [`StepBoard::help`] only while
//! counted as busy by the voice pool, and a bank (its voices, models and jobs) leaves the audio
//! thread only when the pool is quiescent. As a last guard, dropping a job waits until no
//! helper runs it (the drop happens on a builder thread).
//!
//! Threads: [`HalfJob`] and [`StepBoard`] are built on a worker thread; the owner's side runs
//! on whichever real-time thread steps the voice, the helper's on a pool worker; neither
//! allocates, locks or waits without a bound.

use super::coupling::ModalCoupling;
use std::cell::UnsafeCell;
use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicPtr, AtomicU64, AtomicU8, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Smallest coupling tensor (stored entries) whose SAV step is worth sharing between two
/// threads: below it the hand-over (a few hundred nanoseconds to a few microseconds per step)
/// is a large share of a step (at 84 000 entries, 510 × 15 mirror modes, a step takes about
/// 20 µs; docs/performance.md).
pub const SPLIT_MIN_ENTRIES: usize = 150_000;

const IDLE: u8 = 0;
const POSTED: u8 = 1;
const TAKEN: u8 = 2;
const DONE: u8 = 3;

/// The kernel of the coupling type a job was built for, behind a type-erased pointer.
type KernelFn = unsafe fn(
    *const (),
    Range<usize>,
    &[f64],
    &[f64],
    Option<&[f64]>,
    &mut [f64],
    &mut [f64],
    &mut [f64],
) -> bool;

/// # Safety
///
/// `c` must point to a live `C`.
#[allow(clippy::too_many_arguments)]
unsafe fn kernel_of<C: ModalCoupling>(
    c: *const (),
    rows: Range<usize>,
    q: &[f64],
    w: &[f64],
    shift: Option<&[f64]>,
    eta: &mut [f64],
    g: &mut [f64],
    y: &mut [f64],
) -> bool {
    // SAFETY: the caller's contract.
    let c = unsafe { &*(c as *const C) };
    match shift {
        None => c.quartic_gradient_rows(rows, q, w, eta, g, y),
        Some(s) => c.quartic_gradient_shifted_rows(rows, q, w, s, eta, g, y),
    }
}

/// The job's buffers: inputs written by the owner before `POSTED`, outputs written by the
/// helper between `TAKEN` and `DONE`.
struct Buffers {
    q: Box<[f64]>,
    w: Box<[f64]>,
    /// The in-plane offsets of a curved plate's quartic (`shifted`), else unused.
    shift: Box<[f64]>,
    shifted: bool,
    eta: Box<[f64]>,
    g: Box<[f64]>,
    y: Box<[f64]>,
}

/// The second half of one model's split SAV kernel, as a job another thread may run (module
/// docs). Owned (boxed, so its address is fixed) by the model's SAV scratch.
pub struct HalfJob {
    state: AtomicU8,
    /// The model's coupling (`*const C`), alive as long as the model.
    coupling: *const (),
    kernel: KernelFn,
    rows: Range<usize>,
    buf: UnsafeCell<Buffers>,
}

// SAFETY: `buf` is accessed by one thread at a time, as the state machine of the module docs
// says: the owner while the job is IDLE (and DONE, after its acquire load), the helper whose
// POSTED → TAKEN exchange succeeded until its release store of DONE. `coupling` is only read
// (the kernel takes `&C`, and `C: Sync` as every `ModalCoupling`).
unsafe impl Sync for HalfJob {}
// SAFETY: as above; the raw pointer is the model's own coupling, which moves with it.
unsafe impl Send for HalfJob {}

#[cfg(test)]
thread_local! {
    /// Test hook: a helper holding this job's pointer from an earlier step takes the job right
    /// after the owner posts it (on the owner's thread; `step_board_tests.rs`).
    static STALE_TAKE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// How [`HalfJob::finish`] got the second half of an offered step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum HalfOutcome {
    /// By a helper, in parallel with the owner's half.
    Shared,
    /// By the owner: no helper took the offer.
    Own,
    /// By the owner after the bounded wait for a helper that took it ran out.
    Late,
}

impl HalfJob {
    /// A job for rows `rows` of `coupling`'s kernel with `n_phi` modes, `n_psi` in-plane
    /// weights and kernel scratch of `y_len` values. Worker thread (allocates).
    pub(crate) fn new<C: ModalCoupling + 'static>(
        coupling: &Arc<C>,
        rows: Range<usize>,
        n_phi: usize,
        n_psi: usize,
        y_len: usize,
    ) -> Box<HalfJob> {
        Box::new(HalfJob {
            state: AtomicU8::new(IDLE),
            coupling: Arc::as_ptr(coupling) as *const (),
            kernel: kernel_of::<C>,
            buf: UnsafeCell::new(Buffers {
                q: vec![0.0; n_phi].into(),
                w: vec![0.0; n_psi].into(),
                shift: vec![0.0; n_psi].into(),
                shifted: false,
                eta: vec![0.0; rows.len()].into(),
                g: vec![0.0; n_phi].into(),
                y: vec![0.0; y_len].into(),
            }),
            rows,
        })
    }

    /// Helper: runs the job if it is posted (`POSTED → TAKEN`, run, `DONE`); whether it ran.
    fn try_run(&self) -> bool {
        if self
            .state
            .compare_exchange(POSTED, TAKEN, Ordering::Acquire, Ordering::Relaxed)
            .is_err()
        {
            return false;
        }
        // SAFETY: the successful exchange makes this thread the buffers' only user until the
        // DONE store (module docs); the acquire pairs with the owner's release store of
        // POSTED, after its writes of `q` and `w`. The coupling outlives the job.
        unsafe {
            let b = &mut *self.buf.get();
            let shift = b.shifted.then_some(&b.shift[..]);
            (self.kernel)(
                self.coupling,
                self.rows.clone(),
                &b.q,
                &b.w,
                shift,
                &mut b.eta,
                &mut b.g,
                &mut b.y,
            );
        }
        self.state.store(DONE, Ordering::Release);
        true
    }

    /// Owner, step 1: offers the half for `q`, in-plane weights `w` and (a curved plate) the
    /// quartic's offsets `shift` on `board`. Returns
    /// whether it is posted (or already taken: see below), to be ended by [`Self::finish`];
    /// `false` (run the half yourself) when the board is closed or holds another job, or this
    /// job is still out with a late helper.
    pub(crate) fn offer(
        &self,
        board: &StepBoard,
        q: &[f64],
        w: &[f64],
        shift: Option<&[f64]>,
    ) -> bool {
        if !board.open.load(Ordering::Relaxed) {
            return false;
        }
        match self.state.load(Ordering::Acquire) {
            IDLE => {}
            // A late helper has finished since: the job is the owner's again.
            DONE => self.state.store(IDLE, Ordering::Relaxed),
            _ => return false,
        }
        {
            // SAFETY: IDLE: no helper uses the buffers (module docs).
            let b = unsafe { &mut *self.buf.get() };
            b.q.copy_from_slice(q);
            b.w.copy_from_slice(w);
            b.shifted = shift.is_some();
            if let Some(s) = shift {
                b.shift.copy_from_slice(s);
            }
        }
        self.state.store(POSTED, Ordering::Release);
        #[cfg(test)]
        if STALE_TAKE.with(|s| s.get()) {
            assert!(self.try_run(), "the stale helper takes the posted job");
        }
        let me = self as *const HalfJob as *mut HalfJob;
        if board
            .slot
            .compare_exchange(
                std::ptr::null_mut(),
                me,
                Ordering::AcqRel,
                Ordering::Relaxed,
            )
            .is_ok()
        {
            return true;
        }
        // Another job holds the board. A helper that loaded this job's pointer during an earlier
        // step may still take it now (it reaches the job, not the board): take it back only
        // if it is still posted; otherwise a helper runs it and `finish` waits for it as for
        // any taken offer.
        self.state
            .compare_exchange(POSTED, IDLE, Ordering::Acquire, Ordering::Relaxed)
            .is_err()
    }

    /// Owner, step 3, after an offer that returned `true` and the owner's own half (which
    /// took `own`): withdraws the offer and gets the half into `eta`, `g` (and the kernel
    /// scratch `y`): the helper's result, or the owner's own run of [`Self::run_here`] on `q`,
    /// `w` when no helper took it or the bounded wait ran out.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn finish(
        &self,
        board: &StepBoard,
        own: Duration,
        q: &[f64],
        w: &[f64],
        shift: Option<&[f64]>,
        eta: &mut [f64],
        g: &mut [f64],
        y: &mut [f64],
    ) -> HalfOutcome {
        let me = self as *const HalfJob as *mut HalfJob;
        let _ = board.slot.compare_exchange(
            me,
            std::ptr::null_mut(),
            Ordering::AcqRel,
            Ordering::Relaxed,
        );
        if self
            .state
            .compare_exchange(POSTED, IDLE, Ordering::Acquire, Ordering::Relaxed)
            .is_ok()
        {
            self.run_here(q, w, shift, eta, g, y);
            return HalfOutcome::Own;
        }
        // TAKEN or DONE: a helper has it. Wait a bounded time.
        let limit = board.wait_for(own);
        let start = Instant::now();
        loop {
            if self.state.load(Ordering::Acquire) == DONE {
                // SAFETY: DONE (acquire): the helper has stored its result and no longer
                // touches the buffers; the owner resets the job to IDLE after reading.
                let b = unsafe { &*self.buf.get() };
                eta.copy_from_slice(&b.eta);
                g.copy_from_slice(&b.g);
                self.state.store(IDLE, Ordering::Release);
                board.shared.fetch_add(1, Ordering::Relaxed);
                return HalfOutcome::Shared;
            }
            if start.elapsed() > limit {
                break;
            }
            std::hint::spin_loop();
        }
        // The helper is late: compute the half here; the job stays with the helper.
        board.late.fetch_add(1, Ordering::Relaxed);
        self.run_here(q, w, shift, eta, g, y);
        HalfOutcome::Late
    }

    /// The half on the calling thread, into the caller's buffers (never the job's).
    pub(crate) fn run_here(
        &self,
        q: &[f64],
        w: &[f64],
        shift: Option<&[f64]>,
        eta: &mut [f64],
        g: &mut [f64],
        y: &mut [f64],
    ) {
        // SAFETY: the coupling outlives the job, and the job is the model's.
        let ok = unsafe { (self.kernel)(self.coupling, self.rows.clone(), q, w, shift, eta, g, y) };
        debug_assert!(ok, "the split kernel was probed at build");
    }

    /// Whether a helper holds the job (taken and not yet done).
    #[cfg(test)]
    fn is_out(&self) -> bool {
        self.state.load(Ordering::Acquire) == TAKEN
    }
}

impl Drop for HalfJob {
    fn drop(&mut self) {
        // The engine drops a bank only when no helper can reach it (module docs); should a
        // helper still run this job, wait for it (a builder thread, never the audio thread).
        while self.state.load(Ordering::Acquire) == TAKEN {
            std::thread::yield_now();
        }
    }
}

impl std::fmt::Debug for HalfJob {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HalfJob")
            .field("rows", &self.rows)
            .field("state", &self.state.load(Ordering::Relaxed))
            .finish()
    }
}

/// Where owners post the halves of their steps and helpers find them: one slot (two cores
/// share at most one voice's step), open only while helpers are there to take a job, and
/// counters of what happened. Shared by the engine's voice pool and its bank's models.
#[derive(Debug, Default)]
pub struct StepBoard {
    slot: AtomicPtr<HalfJob>,
    open: AtomicBool,
    /// Halves run by a helper.
    shared: AtomicU64,
    /// Halves a helper took but the owner computed itself after the bounded wait.
    late: AtomicU64,
}

impl StepBoard {
    /// An empty, closed board (main thread).
    pub fn new() -> Self {
        Self::default()
    }

    /// Opens or closes the board: owners offer halves only while it is open, that is while a
    /// helper polls it (the voice pool, per chunk). Any thread.
    pub fn set_open(&self, open: bool) {
        self.open.store(open, Ordering::SeqCst);
    }

    /// Helper: runs the posted half, if any; whether it ran one. Any real-time thread; no
    /// allocation.
    ///
    /// # Safety
    ///
    /// Every job that may be on the board (since the caller's last quiescent point) must be
    /// alive until this returns: the voice pool calls it only while counted as busy, and
    /// banks are dropped only when it is quiescent (module docs).
    pub unsafe fn help(&self) -> bool {
        let p = self.slot.load(Ordering::Acquire);
        if p.is_null() {
            return false;
        }
        // SAFETY: the caller's contract keeps the job alive.
        unsafe { &*p }.try_run()
    }

    /// How long an owner whose own half took `own` waits for a helper's half: twice that,
    /// plus 20 µs for the hand-over (the halves are balanced, so a helper that is running
    /// finishes within about `own`).
    pub fn wait_for(&self, own: Duration) -> Duration {
        own * 2 + Duration::from_micros(20)
    }

    /// Halves run by a helper since the board was made.
    pub fn shared_halves(&self) -> u64 {
        self.shared.load(Ordering::Relaxed)
    }

    /// Halves whose helper was late (the owner computed them after the bounded wait).
    pub fn late_halves(&self) -> u64 {
        self.late.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
#[path = "step_board_tests.rs"]
mod tests;
