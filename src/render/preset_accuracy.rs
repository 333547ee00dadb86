//! Accuracy of a factory preset as the instrument plays it: the preset's note rendered through
//! the real-time [`Engine`] (bank, voice, resampler: what a DAW hears), under several settings of
//! one quality parameter, each compared with a reference render of the same note at a richer
//! setting. The metrics are those of [`super::accuracy`] (relative L2 over the first 50 ms of the
//! left output, log-spectral distance over the whole render); the energy balance error is the
//! voice's own (`kinetic + potential + dissipated − work`, sampled once per block, relative to the
//! largest energy). The linear-partial error in cents is not available through the engine
//! (`partial_cents` is `None`): a preset's note retunes its modes per key.
//!
//! Threads: [`render_preset`] runs on the calling thread; the engine is started and its bank
//! awaited by [`super::preset_engine::start_engine`] (as `noether play` does), no rebuild is
//! requested during a render, and the engine's voice pool is not used (`threads = 1`: a
//! one-voice render gives it nothing to share). [`preset_study`] runs its renders on rayon's
//! threads.

use super::accuracy::{AccuracyRow, AccuracyStudy, SensitivityFloor};
use super::metrics::signal_distances;
use super::preset_engine::{start_engine, PresetEngine, BANK_TIMEOUT};
use crate::engine::{ParamId, Preset, PresetValue};
use crate::error::{Error, ParamError};
use rayon::prelude::*;

/// Host rate of preset renders (Hz).
pub const PRESET_HOST_RATE: f64 = 48_000.0;
/// Host block size of preset renders (samples).
pub const PRESET_BLOCK: usize = 256;
/// Note-on velocity of preset renders (0 to 1).
pub const PRESET_VELOCITY: f32 = 0.8;
/// Relative change of the excitation level behind a study's sensitivity floor: 1e-4 quieter,
/// 0.0009 dB, far below what anyone hears.
pub const SENSITIVITY_CHANGE: f64 = -1e-4;

/// One preset render: the left output and what it cost.
#[derive(Debug, Clone)]
pub struct PresetRender {
    /// Left output at [`PRESET_HOST_RATE`].
    pub left: Vec<f64>,
    /// Wall-clock seconds of the processing loop (activation excluded).
    pub wall_seconds: f64,
    /// Largest `|balance − balance₀| / max energy` over the render (sampled per block).
    pub energy_balance_error: f64,
    /// Largest `|energy − energy₀| / max energy` (the drift; equals the balance error when
    /// the voice is lossless and unforced after the strike).
    pub energy_drift: f64,
    /// Simulation rate (Hz), transverse modes, in-plane modes and scheme name of the render.
    pub sim_rate: f64,
    /// Transverse (plate) or string modes.
    pub modes: usize,
    /// In-plane modes (0 for strings).
    pub in_plane_modes: usize,
    /// Plate scheme name, or `modal-exact` for strings.
    pub scheme: String,
}

/// Applies `key = value` overrides (engine parameter keys; numbers, or enumeration names) to
/// `preset`, checking each against the parameter table.
pub fn with_overrides(preset: &Preset, sets: &[String]) -> Result<Preset, Error> {
    let mut p = preset.clone();
    for s in sets {
        let (k, v) = s
            .split_once('=')
            .ok_or_else(|| Error::OverrideSyntax { given: s.clone() })?;
        let (k, v) = (k.trim(), v.trim());
        if ParamId::from_key(k).is_none() {
            return Err(Error::UnknownParam {
                key: k.to_string(),
                given: s.clone(),
            });
        }
        let value = v
            .parse::<f64>()
            .map_or_else(|_| PresetValue::Name(v.to_string()), PresetValue::Number);
        p.params.insert(k.to_string(), value);
    }
    p.values()?;
    Ok(p)
}

/// Plays the preset's root key once (one voice, velocity [`PRESET_VELOCITY`]) for `seconds`
/// through a fresh engine at [`PRESET_HOST_RATE`].
pub fn render_preset(preset: &Preset, seconds: f64) -> Result<PresetRender, ParamError> {
    if !(seconds.is_finite() && (0.01..=60.0).contains(&seconds)) {
        return Err(ParamError::new("seconds", seconds, "0.01 to 60"));
    }
    let PresetEngine {
        mut engine,
        params,
        handle: _handle,
        ..
    } = start_engine(
        preset,
        // The audio thread alone: the studies run their renders in parallel already, and a
        // one-voice bank gives the voice pool nothing to share.
        &[(ParamId::Polyphony, 1.0), (ParamId::Threads, 1.0)],
        PRESET_HOST_RATE,
        PRESET_BLOCK,
        BANK_TIMEOUT,
    )?;
    let v = params.snapshot();
    let kind = v.model();
    let key = params.get(ParamId::RootKey) as u8;
    let total = (seconds * PRESET_HOST_RATE).round() as usize;
    let (mut l, mut r) = (vec![0.0f32; PRESET_BLOCK], vec![0.0f32; PRESET_BLOCK]);
    let mut left = Vec::with_capacity(total);
    let (mut max_e, mut e0, mut b0) = (0.0f64, None, None);
    let (mut worst_balance, mut worst_drift) = (0.0f64, 0.0f64);
    let start = std::time::Instant::now();
    engine.note_on(key, PRESET_VELOCITY);
    while left.len() < total {
        let n = PRESET_BLOCK.min(total - left.len());
        engine.process(&mut l[..n], &mut r[..n]);
        left.extend(l[..n].iter().map(|&x| f64::from(x)));
        if let Some(t) = engine.voice_energy(0) {
            let (e, b) = (t.total(), t.balance());
            max_e = max_e.max(e.abs());
            let (e0, b0) = (*e0.get_or_insert(e), *b0.get_or_insert(b));
            worst_balance = worst_balance.max((b - b0).abs());
            worst_drift = worst_drift.max((e - e0).abs());
        }
    }
    let wall_seconds = start.elapsed().as_secs_f64();
    let scale = if max_e > 0.0 { max_e } else { 1.0 };
    Ok(PresetRender {
        left,
        wall_seconds,
        energy_balance_error: worst_balance / scale,
        energy_drift: worst_drift / scale,
        sim_rate: f64::from(v.get(ParamId::SimRate)),
        modes: v.index_of(ParamId::Modes),
        in_plane_modes: if kind.is_plate() {
            v.index_of(ParamId::InPlaneModes)
        } else {
            0
        },
        scheme: if kind.is_plate() {
            crate::engine::preset::enum_keys(ParamId::Scheme)
                .and_then(|n| n.get(v.index_of(ParamId::Scheme)))
                .map_or("?".to_string(), |s| s.to_string())
        } else {
            "modal-exact".to_string()
        },
    })
}

/// The parameter that sets how hard a preset's note is excited: the pluck amplitude of a
/// string or the drone, the mallet's speed with the mallet exciter, else the strike force.
pub fn excitation_level(preset: &Preset) -> Result<ParamId, ParamError> {
    let v = preset.values()?;
    Ok(if !v.model().is_plate() {
        ParamId::PluckAmplitude
    } else if v.index_of(ParamId::Exciter) == 1 {
        ParamId::MalletSpeed
    } else {
        ParamId::StrikeForce
    })
}

/// `preset` with parameter `id` multiplied by `factor` (checked against its range).
pub fn scaled(preset: &Preset, id: ParamId, factor: f64) -> Result<Preset, ParamError> {
    let x = f64::from(preset.values()?.get(id)) * factor;
    let mut p = preset.clone();
    p.params
        .insert(id.info().key.to_string(), PresetValue::Number(x));
    p.values()?;
    Ok(p)
}

/// One setting of a preset study: its label, numeric value, and the preset under it.
#[derive(Debug, Clone)]
pub struct PresetVariant {
    /// The setting as given.
    pub setting: String,
    /// Its numeric value, when it is a number.
    pub value: Option<f64>,
    /// The preset with the setting applied.
    pub preset: Preset,
}

/// Renders the reference and every variant for `seconds` and compares each with the reference
/// (see the module docs), and measures the metrics' floor for the note: the reference against
/// itself with its [`excitation_level`] changed by [`SENSITIVITY_CHANGE`] ([`SensitivityFloor`]).
/// The renders run in parallel on the cores; the rows keep the variants' order, and `log`
/// receives one line per render, in that order, once all are done.
pub fn preset_study(
    name: &str,
    vary: &str,
    variants: &[PresetVariant],
    reference: &Preset,
    reference_description: String,
    seconds: f64,
    mut log: impl FnMut(&str),
) -> Result<AccuracyStudy, ParamError> {
    let level = excitation_level(reference)?;
    let nudged = scaled(reference, level, 1.0 + SENSITIVITY_CHANGE)?;
    // Independent renders: all at once on the cores, results kept in the variants' order.
    let ((reference_render, nudged_render), renders) = rayon::join(
        || {
            rayon::join(
                || render_preset(reference, seconds),
                || render_preset(&nudged, seconds),
            )
        },
        || {
            variants
                .par_iter()
                .map(|v| render_preset(&v.preset, seconds))
                .collect::<Vec<_>>()
        },
    );
    let r = reference_render?;
    log(&format!(
        "reference ({reference_description}): {:.2} s wall",
        r.wall_seconds
    ));
    let nudged = nudged_render?;
    let floor = signal_distances(&nudged.left, &r.left, PRESET_HOST_RATE);
    let sensitivity = SensitivityFloor {
        parameter: level.info().key.to_string(),
        relative_change: SENSITIVITY_CHANGE,
        l2_50ms: floor.l2_50ms,
        lsd_db: floor.lsd_db,
        band_db: floor.band_db,
        bands: floor.bands,
    };
    log(&format!(
        "floor: the reference with {} {:+e} relative: L2(50 ms) {:.3e}, LSD {:.3} dB, bands {:.3} dB",
        sensitivity.parameter,
        SENSITIVITY_CHANGE,
        sensitivity.l2_50ms,
        sensitivity.lsd_db,
        sensitivity.band_db
    ));
    let (mut rows, mut row_bands) = (Vec::new(), Vec::new());
    for (v, render) in variants.iter().zip(renders) {
        let x = render?;
        let d = signal_distances(&x.left, &r.left, PRESET_HOST_RATE);
        let row = AccuracyRow {
            setting: v.setting.clone(),
            value: v.value,
            sim_rate: x.sim_rate,
            n_phi: x.modes,
            n_psi: x.in_plane_modes,
            scheme: x.scheme.clone(),
            wall_seconds: x.wall_seconds,
            l2_50ms: d.l2_50ms,
            lsd_db: d.lsd_db,
            band_db: d.band_db,
            partial_cents: None,
            energy_balance_error: x.energy_balance_error,
            energy_drift: x.energy_drift,
            max_penetration: None,
            newton_failures: None,
        };
        log(&format!(
            "{vary} = {}: {:.2} s wall, L2(50 ms) {:.3e}, LSD {:.3} dB, bands {:.3} dB, balance error {:.2e}",
            v.setting,
            row.wall_seconds,
            row.l2_50ms,
            row.lsd_db,
            row.band_db,
            row.energy_balance_error
        ));
        rows.push(row);
        row_bands.push(d.bands);
    }
    Ok(AccuracyStudy {
        scene: format!("preset-{name}"),
        vary: vary.into(),
        seconds,
        compare_rate: PRESET_HOST_RATE as u32,
        reference: reference_description,
        reference_wall_seconds: r.wall_seconds,
        reference_energy_balance_error: r.energy_balance_error,
        reference_partial_cents: None,
        sensitivity: Some(sensitivity),
        rows,
        row_bands,
    })
}
