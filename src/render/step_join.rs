//! [`SpinJoin`]: a helper thread that takes the second half of every step of one heavy plate
//! render ([`noether_core::models::plate::StepJoin`]), so that a single offline render uses
//! two cores.
//!
//! # Protocol
//!
//! The render thread publishes the job (a pointer to `b`, valid until `join` returns), bumps
//! `epoch` (release), runs `a`, then spins until `done` equals the epoch (acquire). The helper
//! spins on `epoch` for [`SPIN`] after each job, then parks; the render thread unparks it when
//! it announced parking (a Dekker handshake on sequentially consistent atomics, as the
//! engine's voice pool does). A step of the lecture's gong takes about 200 µs, so the helper
//! stays awake through a render and sleeps between renders.
//!
//! Offline only: `join` waits for the helper without a bound (the real-time engine shares work
//! through its voice pool, which has a bounded wait and a fallback). A panic in `b` is caught
//! on the helper and raised again on the render thread.

use noether_core::models::plate::StepJoin;
use std::cell::UnsafeCell;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::thread::{JoinHandle, Thread};
use std::time::{Duration, Instant};

/// How long the helper spins for the next step before it parks (wall time).
pub const SPIN: Duration = Duration::from_millis(2);

/// The job slot: a lifetime-erased pointer to the current `b`.
type Job = *mut (dyn FnMut() + Send + 'static);

struct Shared {
    epoch: AtomicU64,
    done: AtomicU64,
    job: UnsafeCell<Option<Job>>,
    panicked: AtomicBool,
    parking: AtomicBool,
    stop: AtomicBool,
    /// A `join` holds the helper (a second concurrent caller runs both halves itself).
    busy: AtomicBool,
}

// SAFETY: `job` is written by the render thread only while the helper is not reading it
// (before the release store of a new epoch, after the acquire load of `done` of the previous
// one) and read by the helper only between its acquire load of the new epoch and its release
// store of `done`.
unsafe impl Sync for Shared {}
// SAFETY: as above; the raw pointer is only dereferenced under that protocol.
unsafe impl Send for Shared {}

/// A helper thread that runs the second job of each [`StepJoin::join`] (see the module
/// documentation). Created and dropped on the render's (main or rayon) thread.
pub struct SpinJoin {
    shared: Arc<Shared>,
    helper: Thread,
    handle: Option<JoinHandle<()>>,
}

impl SpinJoin {
    /// Starts the helper thread.
    pub fn new() -> std::io::Result<Self> {
        let shared = Arc::new(Shared {
            epoch: AtomicU64::new(0),
            done: AtomicU64::new(0),
            job: UnsafeCell::new(None),
            panicked: AtomicBool::new(false),
            parking: AtomicBool::new(false),
            stop: AtomicBool::new(false),
            busy: AtomicBool::new(false),
        });
        let s = shared.clone();
        let handle = std::thread::Builder::new()
            .name("noether-step-join".into())
            .spawn(move || helper_loop(&s))?;
        Ok(Self {
            shared,
            helper: handle.thread().clone(),
            handle: Some(handle),
        })
    }

    fn wake(&self) {
        if self.shared.parking.load(Ordering::SeqCst) {
            self.helper.unpark();
        }
    }
}

fn helper_loop(s: &Shared) {
    let mut seen = 0u64;
    loop {
        let mut since = Instant::now();
        let epoch = loop {
            let e = s.epoch.load(Ordering::SeqCst);
            if e != seen {
                break e;
            }
            if since.elapsed() < SPIN {
                std::hint::spin_loop();
                continue;
            }
            s.parking.store(true, Ordering::SeqCst);
            if s.epoch.load(Ordering::SeqCst) == seen {
                std::thread::park_timeout(Duration::from_millis(100));
            }
            s.parking.store(false, Ordering::SeqCst);
            since = Instant::now();
        };
        seen = epoch;
        if s.stop.load(Ordering::SeqCst) {
            return;
        }
        // SAFETY: the render thread wrote `job` before its release store of this epoch and
        // keeps `b` alive until it observes `done == epoch`.
        if let Some(job) = unsafe { *s.job.get() } {
            // SAFETY: as above: `job` points to a live `FnMut` owned by the waiting `join`.
            let run = catch_unwind(AssertUnwindSafe(|| unsafe { (*job)() }));
            if run.is_err() {
                s.panicked.store(true, Ordering::SeqCst);
            }
        }
        s.done.store(epoch, Ordering::SeqCst);
    }
}

impl StepJoin for SpinJoin {
    fn join(&self, a: &mut (dyn FnMut() + Send), b: &mut (dyn FnMut() + Send)) {
        let s = &*self.shared;
        if s.busy.swap(true, Ordering::Acquire) {
            // Another thread's join holds the helper (a cloned model stepped concurrently).
            a();
            b();
            return;
        }
        // SAFETY: only the lifetime is erased; `b` outlives its use because this function
        // returns only after the helper's `done` store for this epoch.
        let job: Job = unsafe {
            std::mem::transmute::<*mut (dyn FnMut() + Send + '_), Job>(
                b as *mut (dyn FnMut() + Send),
            )
        };
        // SAFETY: the helper is idle (it stored `done` for the previous epoch, which the
        // previous `join` observed), so nobody reads `job` now.
        unsafe { *s.job.get() = Some(job) };
        let epoch = s.epoch.load(Ordering::SeqCst) + 1;
        s.epoch.store(epoch, Ordering::SeqCst);
        self.wake();
        a();
        while s.done.load(Ordering::SeqCst) != epoch {
            std::hint::spin_loop();
        }
        s.busy.store(false, Ordering::Release);
        if s.panicked.swap(false, Ordering::SeqCst) {
            panic!("SpinJoin: the helper thread's half of the step panicked");
        }
    }
}

impl Drop for SpinJoin {
    fn drop(&mut self) {
        let s = &*self.shared;
        s.stop.store(true, Ordering::SeqCst);
        // SAFETY: no join is running (`join` borrows `self`), so the helper is idle.
        unsafe { *s.job.get() = None };
        s.epoch.fetch_add(1, Ordering::SeqCst);
        self.helper.unpark();
        if let Some(h) = self.handle.take() {
            let _ = h.join();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Both halves run, many times in a row, and each `join` returns only after `b` wrote its
    /// result (the counter would fall behind otherwise).
    #[test]
    fn both_jobs_finish_before_join_returns() {
        let j = SpinJoin::new().unwrap();
        let (mut x, mut y) = (0u64, 0u64);
        for i in 0..20_000u64 {
            j.join(&mut || x += i, &mut || y += 2 * i);
            assert_eq!(y, (0..=i).map(|k| 2 * k).sum::<u64>());
        }
        assert_eq!(x, (0..20_000u64).sum::<u64>());
    }

    /// The helper parks when idle and wakes for the next job.
    #[test]
    fn wakes_after_parking() {
        let j = SpinJoin::new().unwrap();
        std::thread::sleep(SPIN * 5);
        let mut y = 0;
        j.join(&mut || {}, &mut || y = 7);
        assert_eq!(y, 7);
    }

    /// A panic in the helper's half reaches the caller.
    #[test]
    #[should_panic(expected = "helper thread's half")]
    fn helper_panic_is_raised() {
        let j = SpinJoin::new().unwrap();
        j.join(&mut || {}, &mut || panic!("boom"));
    }
}
