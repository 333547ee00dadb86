//! The global allocator of Noether's test binaries: `assert_no_alloc`'s [`AllocDisabler`] (an
//! allocation inside an [`assert_no_alloc::assert_no_alloc`] scope aborts the process) with a
//! per-thread allocation counter on top (so a test can count what a closure allocates and name
//! the case that did, instead of aborting the whole binary).
//!
//! Install it once per test binary (every test of a binary shares its global allocator):
//!
//! ```ignore
//! #[global_allocator]
//! static A: noether_testkit::alloc::Guard = noether_testkit::alloc::Guard;
//! ```
//!
//! Tests run on parallel threads, so the counter is per thread: [`count_allocations`] sees only
//! what its closure (and anything else on the same thread) allocates.
//!
//! The engine's voice-pool workers are other threads: every allocation made on a thread inside
//! the pool's job loop ([`noether_core::engine::in_voice_job`]) is also counted in one global
//! counter, [`voice_job_allocations`], which a test reads after driving a threaded engine.

use assert_no_alloc::AllocDisabler;
use std::alloc::{GlobalAlloc, Layout};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

/// [`AllocDisabler`] plus a per-thread counter of allocations (reallocations count as one).
pub struct Guard;

thread_local! {
    // `const`: no lazy initialisation, so the allocator never recurses into itself.
    static ALLOCATIONS: Cell<u64> = const { Cell::new(0) };
}

/// Allocations made by any thread inside the voice pool's job loop.
static JOB_ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

fn bump() {
    // `try_with`: the thread-local may already be torn down at thread exit.
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
    if noether_core::engine::in_voice_job() {
        JOB_ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
    }
}

// SAFETY: every call is forwarded unchanged to `AllocDisabler`, itself a checked wrapper of
// the system allocator; the counter touches only a thread-local `Cell`.
unsafe impl GlobalAlloc for Guard {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        bump();
        unsafe { AllocDisabler.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { AllocDisabler.dealloc(ptr, layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        bump();
        unsafe { AllocDisabler.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        bump();
        unsafe { AllocDisabler.realloc(ptr, layout, new_size) }
    }
}

/// Allocations made by the current thread since it started (0 if [`Guard`] is not the global
/// allocator).
pub fn allocations() -> u64 {
    ALLOCATIONS.with(|c| c.get())
}

/// Runs `f` and returns its result with the number of allocations the current thread made
/// meanwhile.
pub fn count_allocations<T>(f: impl FnOnce() -> T) -> (T, u64) {
    let before = allocations();
    let r = f();
    (r, allocations() - before)
}

/// Allocations made inside the engine's voice-pool job loops (any worker thread of any engine)
/// since the process started (0 if [`Guard`] is not the global allocator).
pub fn voice_job_allocations() -> u64 {
    JOB_ALLOCATIONS.load(Ordering::Relaxed)
}

/// Whether [`Guard`] is this binary's global allocator (a deliberate allocation is counted), so
/// an allocation check cannot pass vacuously.
pub fn installed() -> bool {
    count_allocations(|| drop(std::hint::black_box(Vec::<u8>::with_capacity(16)))).1 > 0
}
