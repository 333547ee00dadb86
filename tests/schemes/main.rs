//! Time schemes of one and N degrees of freedom, the integrator lab and its CLI, and the model ×
//! scheme catalogue run through the shared harness (`noether_testkit::harness`).

/// Every test binary shares one global allocator: `assert_no_alloc`'s, with a per-thread
/// allocation counter (`noether_testkit::alloc`).
#[global_allocator]
static A: noether_testkit::alloc::Guard = noether_testkit::alloc::Guard;

mod catalogue;
mod cli_lab;
mod ndof;
mod oscillators;
