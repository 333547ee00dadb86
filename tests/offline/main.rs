//! The offline side: scene files and assets, `quality = auto`, preset accuracy, `noether play`.

/// Every test binary shares one global allocator: `assert_no_alloc`'s, with a per-thread
/// allocation counter (`noether_testkit::alloc`).
#[global_allocator]
static A: noether_testkit::alloc::Guard = noether_testkit::alloc::Guard;

mod auto;
mod cli_modes;
mod cli_output;
mod network_report;
mod opera_gongs;
mod play;
mod preset_accuracy;
mod scene_assets;
mod scene_errors;
