//! # noether-testkit
//!
//! Test tools shared by Noether's test suites and examples (a dev-dependency; nothing here runs
//! in the product):
//!
//! - [`soak`]: the real-time soak, a seeded random host driving the engine (`tests/soak.rs`,
//!   `examples/soak.rs`).

pub mod soak;
