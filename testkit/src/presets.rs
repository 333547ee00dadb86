//! Factory presets as the engine tests and benchmarks start from them: the preset's shared
//! parameters with some of them changed.
//!
//! Test and benchmark set-up only (the main or a test thread): panics with the preset and the
//! parameter named when the set-up itself is wrong (an unknown stem, a value out of range).

use noether_core::engine::{ParamId, Preset, SharedParams};
use std::sync::Arc;

/// The parameters of factory preset `stem` (for example `"gong-40N"`) with each `(id, value)`
/// of `sets` applied in order (plain values in the parameter's unit).
pub fn preset_params(stem: &str, sets: &[(ParamId, f32)]) -> Arc<SharedParams> {
    let params = Arc::new(SharedParams::new());
    Preset::factory_named(stem)
        .unwrap_or_else(|| panic!("no factory preset named {stem}"))
        .apply(&params)
        .unwrap_or_else(|e| panic!("factory preset {stem} does not apply: {e}"));
    for &(id, value) in sets {
        params
            .set(id, value)
            .unwrap_or_else(|e| panic!("{stem}: {} = {value}: {e}", id.info().key));
    }
    params
}
