//! A preset loaded into a fresh real-time [`Engine`] the way the plugin loads one, shared by
//! `noether play` ([`super::play`]) and the preset accuracy studies
//! ([`super::preset_accuracy`]).
//!
//! The plugin resolves a preset to its full parameter set ([`Preset::values`]: defaults where
//! the file names none, every value checked) and writes it into the [`SharedParams`] the engine
//! reads, then activates the engine at the host's rate and block size. The voice bank is built
//! by the engine (at activation, or on its worker thread): [`start_engine`] waits, bounded by
//! a timeout, until a bank is in use and no rebuild is pending before any note is sent, so the
//! first note is never lost to a bank still being built.
//!
//! Threads: everything here runs on the calling (CLI) thread, which plays the host's main and
//! audio threads in turn; the engine's worker thread is started by [`Engine::activate`].

use crate::engine::{Engine, EngineHandle, ParamId, Preset, SharedParams};
use crate::error::ParamError;
use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Longest wait for the first voice bank (s): a new large modal basis takes seconds to build
/// (the 1000-mode gong's about 10 s on the 2-core machine); a cached one milliseconds.
pub const BANK_TIMEOUT: Duration = Duration::from_secs(300);

/// Polling period while waiting for the bank.
const BANK_POLL: Duration = Duration::from_millis(2);

/// A preset found by name or path: the factory stem or the file stem, and the preset.
#[derive(Debug, Clone)]
pub struct FoundPreset {
    /// File stem (factory presets: their stem in `assets/presets/`), used for output names.
    pub stem: String,
    /// The parsed preset (values not yet checked: [`Preset::values`] checks them).
    pub preset: Preset,
}

/// Finds `name_or_path`: a factory preset's stem (`gong-40N`), else a preset TOML file.
/// An unknown name that is not a readable file is an error naming it and listing the factory
/// stems.
pub fn find_preset(name_or_path: &str) -> Result<FoundPreset, ParamError> {
    if let Some(preset) = Preset::factory_named(name_or_path) {
        return Ok(FoundPreset {
            stem: name_or_path.to_string(),
            preset,
        });
    }
    let path = Path::new(name_or_path);
    if path.is_file() {
        let preset = Preset::load(path)?;
        let stem = path
            .file_stem()
            .map_or("preset".into(), |s| s.to_string_lossy().into_owned());
        return Ok(FoundPreset { stem, preset });
    }
    let stems: Vec<&str> = Preset::factory().iter().map(|(s, _)| *s).collect();
    Err(ParamError::new(
        "PRESET",
        name_or_path,
        format!(
            "a factory preset ({}) or the path of a preset TOML file",
            stems.join(", ")
        ),
    ))
}

/// An engine playing a preset, activated, with its bank in use.
pub struct PresetEngine {
    /// The engine (the caller's thread drives it as the audio thread).
    pub engine: Engine,
    /// Its control handle (worker status, telemetry).
    pub handle: EngineHandle,
    /// The parameters it reads, holding the preset's values.
    pub params: Arc<SharedParams>,
    /// Wall-clock seconds from activation until the bank was in use (the bank build).
    pub bank_seconds: f64,
}

/// Writes `preset` into fresh shared parameters (with `overrides` applied after it, e.g. a
/// polyphony of 1 for a study), activates an engine at `host_rate` Hz with blocks of at most
/// `max_block` samples, and waits for its voice bank ([`wait_for_bank`], at most `timeout`).
pub fn start_engine(
    preset: &Preset,
    overrides: &[(ParamId, f32)],
    host_rate: f64,
    max_block: usize,
    timeout: Duration,
) -> Result<PresetEngine, ParamError> {
    let params = Arc::new(SharedParams::new());
    preset.apply(&params)?;
    for &(id, v) in overrides {
        params.set(id, v)?;
    }
    let (mut engine, handle) = Engine::new(params.clone());
    // Offline: the audio thread waits for the voice pool's workers as long as they take (10 s
    // bound), so no voice's chunk is ever left out as late and renders repeat bit for bit.
    engine.set_job_wait(Some(Duration::from_secs(10)));
    let start = Instant::now();
    // Offline renders are strict: a set the models refuse is an error, not a fallback.
    if let Some(refused) = engine.activate(host_rate, max_block)? {
        return Err(refused);
    }
    wait_for_bank(&mut engine, &handle, max_block, timeout)?;
    Ok(PresetEngine {
        engine,
        handle,
        params,
        bank_seconds: start.elapsed().as_secs_f64(),
    })
}

/// Waits until `engine` has a voice bank in use ([`Engine::bank_id`] non-zero) and its worker
/// is not building another ([`EngineHandle::is_rebuilding`]). Meanwhile it processes silent
/// blocks of `block` samples (discarded), as a host does, so that a bank sent by the worker is
/// taken at a block boundary. Errors: the worker's build error, or no bank after `timeout`
/// (each naming the bank, what happened and what was expected).
pub fn wait_for_bank(
    engine: &mut Engine,
    handle: &EngineHandle,
    block: usize,
    timeout: Duration,
) -> Result<(), ParamError> {
    let start = Instant::now();
    let n = block.max(1);
    let (mut l, mut r) = (vec![0.0f32; n], vec![0.0f32; n]);
    loop {
        if engine.bank_id() != 0 && !handle.is_rebuilding() {
            return Ok(());
        }
        if let Some(e) = handle.last_error() {
            return Err(ParamError::new(
                "voice bank",
                format!("build failed: {e}"),
                "a bank the engine can build from the preset",
            ));
        }
        if start.elapsed() >= timeout {
            return Err(ParamError::new(
                "voice bank",
                format!(
                    "not in use after {:.1} s (bank id {}, rebuilding {})",
                    timeout.as_secs_f64(),
                    engine.bank_id(),
                    handle.is_rebuilding()
                ),
                format!("built within {:.0} s", timeout.as_secs_f64()),
            ));
        }
        engine.process(&mut l, &mut r);
        std::thread::sleep(BANK_POLL);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A factory stem resolves; an unknown name is refused with the factory list.
    #[test]
    fn finds_factory_presets_and_refuses_unknown_names() {
        assert_eq!(find_preset("gong-40N").unwrap().stem, "gong-40N");
        let e = find_preset("no-such-preset").unwrap_err();
        assert_eq!(e.field, "PRESET");
        assert!(e.allowed.contains("gong-40N"), "{e}");
    }

    /// After [`start_engine`] the bank is in use; a zero timeout on a fresh engine that has a
    /// bank returns at once (the bank check comes before the clock).
    #[test]
    fn the_bank_is_in_use_after_start() {
        noether_testkit::env::test_cache_dir();
        let p = Preset::factory_named("gong-40N").unwrap();
        let mut s = start_engine(
            &p,
            &[(ParamId::Modes, 20.0), (ParamId::InPlaneModes, 4.0)],
            48_000.0,
            256,
            BANK_TIMEOUT,
        )
        .unwrap();
        assert_ne!(s.engine.bank_id(), 0);
        wait_for_bank(&mut s.engine, &s.handle, 256, Duration::ZERO).unwrap();
    }

    /// An engine that was never activated has no bank: the wait ends with an error naming the
    /// bank and the timeout instead of hanging.
    #[test]
    fn no_bank_is_a_bounded_wait_and_a_clear_error() {
        let params = Arc::new(SharedParams::new());
        let (mut engine, handle) = Engine::new(params);
        let e = wait_for_bank(&mut engine, &handle, 64, Duration::from_millis(20)).unwrap_err();
        assert_eq!(e.field, "voice bank");
        assert!(e.value.contains("not in use after"), "{e}");
    }
}
