//! The real-time engine: voices, banks, parameters, presets, and `assert_no_alloc` around
//! `Engine::process`.

/// Every test binary shares one global allocator: `assert_no_alloc`'s, with a per-thread
/// allocation counter (`noether_testkit::alloc`).
#[global_allocator]
static A: noether_testkit::alloc::Guard = noether_testkit::alloc::Guard;

mod activation;
mod always_playable;
mod band_above;
mod cascade;
mod closure;
mod drone;
mod engine;
mod engine_alloc;
mod engine_hand;
mod engine_mallet;
mod engine_shape;
mod engine_split_step;
mod engine_threads;
mod extreme_levels;
mod governor;
mod long_performance;
mod param_meta;
mod per_note;
mod pitch_from_sound;
mod preset_levels;
mod sitar;
mod strike_above;
mod string_presets;
mod tiers;

use noether::engine::{Engine, ParamId, SharedParams};
use noether_testkit::presets::preset_params;
use std::sync::Arc;

/// An engine playing the factory preset `preset` with `sets` applied to its parameters,
/// activated at 48 kHz with blocks of up to 256 samples.
pub fn engine_with(preset: &str, sets: &[(ParamId, f32)]) -> (Engine, Arc<SharedParams>) {
    let params = preset_params(preset, sets);
    let (mut e, _h) = Engine::new(params.clone());
    e.activate(48_000.0, 256).unwrap();
    (e, params)
}
