//! Plates: modal bases (circular and rectangular) and their coupling kernels, the plate schemes
//! (exactness, backbone, SAV), strike-mirror bases and plate scenes rendered end to end.

/// Every test binary shares one global allocator: `assert_no_alloc`'s, with a per-thread
/// allocation counter (`noether_testkit::alloc`).
#[global_allocator]
static A: noether_testkit::alloc::Guard = noether_testkit::alloc::Guard;

#[path = "../common/compat.rs"]
mod compat;

mod coupling_block_kernels;
mod modal_circular;
mod modal_rect;
mod plate_backbone;
mod plate_band_above;
mod plate_closure;
mod plate_hand;
mod plate_mallet;
mod plate_mallet_hertz;
mod plate_mallet_scene;
mod plate_mirror;
mod plate_render;
mod plate_sav;
mod plate_sav_split;
mod plate_scheme;
mod plate_shell;
mod plate_shell_backbone;
mod plate_shell_scene;
mod plate_single;
