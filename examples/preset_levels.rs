//! Level calibration of the factory presets (a preset designer's tool): plays each preset's
//! notes C2-C7 (keys 36-96) at velocity 127 through the engine at 48 kHz, with the limiter and
//! the key tracking off, prints the raw peaks, and the `key_level` (dB per octave, the
//! least-squares slope of the peaks against octaves from the root key, negated) and the
//! `gain` that put the root key's peak at -3.5 dBFS, the middle of the -6 to -1 dBFS the
//! presets are held to (`tests/engine/preset_levels.rs`).
//!
//! ```text
//! cargo run --release --example preset_levels [-- STEM ...]
//! ```

use noether::engine::{Engine, ParamId, Preset, SharedParams};
use std::sync::Arc;

const RATE: f64 = 48_000.0;
const KEYS: [u8; 6] = [36, 48, 60, 72, 84, 96];
const TARGET_DB: f64 = -3.5;
/// Gain under which the notes are measured (dB), so the output guard never clips them.
const MEASURE_DB: f64 = 40.0;

fn peak_db(preset: &Preset, key: u8) -> f64 {
    let params = Arc::new(SharedParams::new());
    preset.apply(&params).unwrap();
    params.set(ParamId::Polyphony, 1.0).unwrap();
    params.set(ParamId::Limiter, 0.0).unwrap();
    params.set(ParamId::KeyLevel, 0.0).unwrap();
    // 40 dB down so no peak reaches the 0 dBFS guard; added back below.
    params.set(ParamId::Gain, -MEASURE_DB as f32).unwrap();
    let (mut e, _h) = Engine::new(params);
    e.activate(RATE, 256).unwrap();
    e.note_on(key, 1.0);
    let (mut l, mut r) = (vec![0.0f32; 256], vec![0.0f32; 256]);
    let mut peak = 0.0f32;
    for _ in 0..(0.6 * RATE / 256.0) as usize {
        e.process(&mut l, &mut r);
        peak = l.iter().chain(&r).fold(peak, |m, x| m.max(x.abs()));
    }
    20.0 * f64::from(peak).max(1e-12).log10() + MEASURE_DB
}

fn main() {
    let only: Vec<String> = std::env::args().skip(1).collect();
    for (stem, preset) in Preset::factory() {
        if !only.is_empty() && !only.iter().any(|s| s == stem) {
            continue;
        }
        let v = preset.values().unwrap();
        let root = v.get(ParamId::RootKey) as f64;
        let gain = v.get(ParamId::Gain) as f64;
        let pts: Vec<(f64, f64)> = KEYS
            .iter()
            .map(|&k| ((k as f64 - root) / 12.0, peak_db(&preset, k) + gain))
            .collect();
        let n = pts.len() as f64;
        let (mx, my) = (
            pts.iter().map(|p| p.0).sum::<f64>() / n,
            pts.iter().map(|p| p.1).sum::<f64>() / n,
        );
        let slope = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum::<f64>()
            / pts.iter().map(|p| (p.0 - mx).powi(2)).sum::<f64>();
        let at_root = my - slope * mx;
        let residual: Vec<String> = pts
            .iter()
            .map(|p| format!("{:+.1}", p.1 - (at_root + slope * p.0)))
            .collect();
        let raw: Vec<String> = pts.iter().map(|p| format!("{:.1}", p.1)).collect();
        println!(
            "{stem}: peaks (dBFS, with its gain {gain}) {raw:?}; slope {slope:+.2} dB/oct, fit at root \
             {at_root:.1}; suggest key_level = {:.1}, gain = {:.1}; residuals {residual:?}",
            -slope,
            gain + TARGET_DB - at_root
        );
    }
}
