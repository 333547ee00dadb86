//! The gong voice that `benches/plate_gong.rs`, `benches/tensor_kernels.rs` and
//! `examples/gong_rtf.rs` measure: the lecture's gong scene (`assets/scenes/seed-gong-40N.toml`:
//! a = 0.4 m, h = 1 mm, free edge, power-law damping, 10 ms strike at 40 N) with overrides.
//! Included by path (`#[path]`), so the benches and the example share one copy.

use noether::models::plate::voice::PlateVoice;
use noether::scene::Scene;
use std::path::Path;

/// The lecture's gong scene the voices start from.
const SEED_GONG: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/assets/scenes/seed-gong-40N.toml"
);

/// The scene's voice with `sets` (`path=value` scene overrides, as `--set`) applied. Panics
/// on an override the scene refuses (a bench set-up error).
pub fn seed_gong_voice(sets: &[String]) -> PlateVoice {
    let scene = Scene::load(Path::new(SEED_GONG), sets).expect("the seed gong scene");
    PlateVoice::build(scene.plate.as_ref().expect("a plate scene")).expect("a gong voice")
}
