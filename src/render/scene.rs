//! Rendering a whole [`Scene`]: build its model (plate or string) as a [`RenderSource`], run it
//! through the one offline loop, and fill the report.

use super::offline::{render_with_shapes, Rendered};
use super::report::{spectral_centroid, RenderReport};
use super::source::{ModelDetails, RenderSource};
use super::step_join::SpinJoin;
use crate::analysis::dispersion::max_cents_error;
use crate::error::{Error, ParamError};
use crate::models::plate::voice::PlateVoice;
use crate::models::sav_relaxation::SavRelaxation;
use crate::models::sitar::Sitar;
use crate::models::string::StiffString;
use crate::models::tanpura::Tanpura;
use crate::scene::{Scene, StringSpec};

/// Energy samples kept for plots and statistics over a render.
pub const ENERGY_POINTS: usize = 4000;

/// Smallest coupling tensor (stored entries) whose SAV step [`render_scene_on`] shares between
/// two threads: the engine's threshold.
pub use noether_core::models::plate::SPLIT_MIN_ENTRIES;

/// A scene's model, ready to render, with what the report says about it.
pub struct SceneSource {
    /// The model.
    pub source: Box<dyn RenderSource>,
    /// Model family (`plate` or `string`).
    pub model: &'static str,
    /// Scheme identifier.
    pub scheme: String,
    /// Transverse (plate) or string modes.
    pub n_phi: usize,
    /// In-plane modes (0 for strings).
    pub n_psi: usize,
    /// Instants (s) at which to record the model's shape.
    pub snapshots: Vec<f64>,
    /// Threads sharing each step: 2 when a plate's SAV coupling kernel is split
    /// ([`render_scene_on`]), else 1.
    pub step_threads: usize,
}

/// Builds the string of `scene` and sets its initial condition or strike.
pub fn build_string(scene: &StringSpec) -> Result<StiffString, ParamError> {
    scene.validate()?;
    let scoped = |mut e: ParamError| {
        e.field = format!("string.{}", e.field);
        e
    };
    let mut s = StiffString::new(&scene.config()).map_err(scoped)?;
    s.set_contact_scheme(scene.scheme()?);
    s.set_sav_relaxation(SavRelaxation::from_scene(
        scene.sav_relaxation,
        s.params().h(),
    ));
    if let Some(p) = scene.pluck() {
        s.pluck(&p).map_err(scoped)?;
    }
    if let Some(f) = scene.strike() {
        s.strike(&f).map_err(scoped)?;
    }
    Ok(s)
}

/// Builds the model of `scene` (validated).
pub fn build_source(scene: &Scene) -> Result<SceneSource, ParamError> {
    build_source_on(scene, 1)
}

/// [`build_source`], sharing each step of a plate's `sav` scheme between two threads (a
/// [`SpinJoin`] helper) when `threads` ≥ 2 and its tensor has at least [`SPLIT_MIN_ENTRIES`]
/// stored entries. The split changes the order of one sum (round-off), and its result does
/// not depend on the thread count.
pub fn build_source_on(scene: &Scene, threads: usize) -> Result<SceneSource, ParamError> {
    match (&scene.plate, &scene.string) {
        (Some(plate), None) => {
            let mut voice = PlateVoice::build(plate)?;
            let mut step_threads = 1;
            if threads >= 2 && voice.model().coupling().nnz() >= SPLIT_MIN_ENTRIES {
                // No helper thread (the system refused one): the render runs on one thread.
                if let Ok(join) = SpinJoin::new() {
                    if voice.set_step_join(Some(std::sync::Arc::new(join))) {
                        step_threads = 2;
                    }
                }
            }
            let info = voice.info().clone();
            Ok(SceneSource {
                source: Box::new(voice),
                model: "plate",
                scheme: info.scheme.clone(),
                n_phi: info.n_phi,
                n_psi: info.n_psi,
                snapshots: Vec::new(),
                step_threads,
            })
        }
        (None, None) => {
            let (source, model, modes): (Box<dyn RenderSource>, _, _) =
                match (&scene.tanpura, &scene.sitar) {
                    (Some(spec), None) => (Box::new(Tanpura::build(spec)?), "tanpura", spec.modes),
                    (None, Some(spec)) => (Box::new(Sitar::build(spec)?), "sitar", spec.modes),
                    _ => return Err(no_single_model(scene)),
                };
            Ok(SceneSource {
                source,
                model,
                scheme: "exact-modal+discrete-gradient-network".into(),
                n_phi: modes,
                n_psi: 0,
                snapshots: Vec::new(),
                step_threads: 1,
            })
        }
        (None, Some(string)) => Ok(SceneSource {
            source: Box::new(build_string(string)?),
            model: "string",
            scheme: match string.scheme() {
                Ok(crate::models::string::ContactScheme::Quadratised) => {
                    "exact-modal+quadratised-contact".into()
                }
                _ => "exact-modal+discrete-gradient-contact".into(),
            },
            n_phi: string.modes,
            n_psi: 0,
            snapshots: string.effective_snapshots(),
            step_threads: 1,
        }),
        _ => Err(no_single_model(scene)),
    }
}

/// The error of a scene without exactly one model table: its validation's, or a missing table.
fn no_single_model(scene: &Scene) -> ParamError {
    scene.validate().err().unwrap_or_else(|| {
        ParamError::new(
            "plate",
            "missing",
            "a scene needs exactly one model table: [plate], [string], [tanpura] or [sitar]",
        )
    })
}

/// Builds the scene's model, renders it and returns the signals and the report. `progress`
/// receives the fraction done.
pub fn render_scene(
    scene: &Scene,
    progress: impl FnMut(f64),
) -> Result<(Rendered, RenderReport), Error> {
    render_scene_on(scene, 1, progress)
}

/// [`render_scene`] on up to `threads` threads: a heavy plate's SAV step is shared between two
/// ([`build_source_on`]); the report's `step_threads` says whether it was.
pub fn render_scene_on(
    scene: &Scene,
    threads: usize,
    progress: impl FnMut(f64),
) -> Result<(Rendered, RenderReport), Error> {
    let mut built = build_source_on(scene, threads)?;
    let gain = 10f64.powf(scene.output.gain_db / 20.0);
    let rendered = render_with_shapes(
        built.source.as_mut(),
        scene.output.seconds,
        scene.output.sample_rate,
        gain,
        ENERGY_POINTS,
        &built.snapshots,
        progress,
    )?;
    let source = built.source.as_ref();
    let s = &rendered.stats;
    let model_details = source.details();
    let warnings: Vec<String> = match &model_details {
        ModelDetails::Network(n) => n.aliasing_warning().into_iter().collect(),
        _ => Vec::new(),
    };
    let mut details = match serde_json::to_value(model_details) {
        Ok(serde_json::Value::Object(m)) => m,
        _ => serde_json::Map::new(),
    };
    if let Some(string) = &scene.string {
        details.insert("f_max".into(), string.f_max().into());
        details.insert(
            "f_1".into(),
            (string.params().omega(1) / std::f64::consts::TAU).into(),
        );
    }
    let report = RenderReport {
        scene: scene.name.clone(),
        model: built.model.into(),
        scheme: built.scheme.clone(),
        conservative: source.is_conservative(),
        sample_rate: scene.output.sample_rate,
        sim_rate: source.sim_rate(),
        seconds: s.seconds,
        n_phi: built.n_phi,
        n_psi: built.n_psi,
        energy: s.energy.clone(),
        nan_count: s.nan_count,
        peak: s.peak,
        wall_seconds: s.wall_seconds,
        realtime_factor: s.realtime_factor,
        step_threads: built.step_threads,
        spectral_centroid_hz: {
            let ch = &rendered.out[0];
            let n = (scene.output.sample_rate as usize / 10).min(ch.len());
            let rate = scene.output.sample_rate as f64;
            [
                spectral_centroid(&ch[..n], rate),
                spectral_centroid(&ch[ch.len() - n..], rate),
            ]
        },
        linear_partials_max_cents: max_cents_error(
            &source.linear_partials(),
            0.5 * (scene.output.sample_rate as f64).min(source.sim_rate()),
        ),
        contact: source.contact(),
        details,
        warnings,
        auto: None,
    };
    Ok((rendered, report))
}
