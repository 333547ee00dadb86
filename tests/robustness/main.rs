//! Robustness: the extremes sweep, hostile scenes and command lines, decay without subnormals,
//! and the bounded real-time soak.

/// Every test binary shares one global allocator: `assert_no_alloc`'s, with a per-thread
/// allocation counter (`noether_testkit::alloc`).
#[global_allocator]
static A: noether_testkit::alloc::Guard = noether_testkit::alloc::Guard;

mod cli_hostile;
mod denormals;
mod extremes;
mod hostile;
mod soak;
mod threads;
