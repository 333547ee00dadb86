//! Rendering a whole [`Scene`]: build its model, run it, and fill the report.

use super::offline::{render, Rendered};
use super::report::{spectral_centroid, RenderReport};
use super::source::RenderSource;
use crate::models::plate::voice::PlateVoice;
use crate::scene::Scene;

/// Energy samples kept for plots and statistics over a render.
pub const ENERGY_POINTS: usize = 4000;

/// Builds the scene's model, renders it and returns the signals and the report. `progress`
/// receives the fraction done.
pub fn render_scene(
    scene: &Scene,
    progress: impl FnMut(f64),
) -> Result<(Rendered, RenderReport), String> {
    let plate = scene
        .plate
        .as_ref()
        .ok_or("the scene has no model table ([plate])")?;
    let mut voice = PlateVoice::build(plate)?;
    let gain = 10f64.powf(scene.output.gain_db / 20.0);
    let rendered = render(
        &mut voice,
        scene.output.seconds,
        scene.output.sample_rate,
        gain,
        ENERGY_POINTS,
        progress,
    )?;
    let info = voice.info().clone();
    let s = &rendered.stats;
    let report = RenderReport {
        scene: scene.name.clone(),
        model: "plate".into(),
        scheme: info.scheme.clone(),
        conservative: voice.is_conservative(),
        sample_rate: scene.output.sample_rate,
        sim_rate: voice.sim_rate(),
        seconds: s.seconds,
        n_phi: info.n_phi,
        n_psi: info.n_psi,
        energy: s.energy.clone(),
        nan_count: s.nan_count,
        peak: s.peak,
        wall_seconds: s.wall_seconds,
        realtime_factor: s.realtime_factor,
        spectral_centroid_hz: {
            let ch = &rendered.out[0];
            let n = (scene.output.sample_rate as usize / 10).min(ch.len());
            let rate = scene.output.sample_rate as f64;
            [
                spectral_centroid(&ch[..n], rate),
                spectral_centroid(&ch[ch.len() - n..], rate),
            ]
        },
        details: voice.report_extras(),
    };
    Ok((rendered, report))
}
