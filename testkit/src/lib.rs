//! # noether-testkit
//!
//! Test tools shared by Noether's test suites and examples (a dev-dependency; nothing here runs
//! in the product):
//!
//! - [`harness`]: the model × scheme catalogue and the one run every case goes through
//!   (finiteness, power balance to a stated tolerance, no allocation in the step);
//! - [`alloc`]: the test binaries' global allocator (`assert_no_alloc`'s, with a per-thread
//!   allocation counter);
//! - [`env`]: the process environment the tests share (the modal cache directory, set once);
//! - [`performance`]: long performances (minutes of playing, then a fresh strike compared
//!   with the same strike on a new instance);
//! - [`presets`]: a factory preset's parameters with some changed, the set-up the engine
//!   tests and benchmarks start from;
//! - [`soak`]: the real-time soak, a seeded random host driving the engine (`tests/robustness`,
//!   `examples/soak.rs`);
//! - [`take`]: the engine tests' render loops (a stereo take with the first block's events,
//!   a script of events, or blocks with the voice's energy after each) and its peak and RMS.

pub mod alloc;
pub mod env;
pub mod harness;
pub mod performance;
pub mod presets;
pub mod soak;
pub mod take;
