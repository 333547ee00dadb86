//! Stiff strings against obstacles: the model, its SAV contact, the rows path, renders and the
//! real-time methods' allocation check.

/// Every test binary shares one global allocator: `assert_no_alloc`'s, with a per-thread
/// allocation counter (`noether_testkit::alloc`).
#[global_allocator]
static A: noether_testkit::alloc::Guard = noether_testkit::alloc::Guard;

mod crossings;
mod network;
mod sitar;
mod string_alloc;
mod string_bounce;
mod string_hand;
mod string_model;
mod string_partials;
mod string_render;
mod string_repluck;
mod string_rows;
mod string_sav;
mod tanpura;
