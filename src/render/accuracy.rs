//! Accuracy against a reference render: the metrics of `noether accuracy` (stated in
//! docs/ACCURACY.md) and the study that varies one setting of a scene.
//!
//! Metrics, each comparing pickup 1 of a render with pickup 1 of the reference, both at the
//! scene's output rate (every render is resampled to it by the render loop, so the signals share
//! one rate and one length):
//! - **relative L2 error over the first 50 ms**, **log-spectral distance** and **band-level
//!   distance** over the whole render ([`super::metrics`]);
//! - **linear partials**: the largest error in cents of the scheme's linear partials against
//!   the continuous model's, over the modes below the output Nyquist frequency (closed form from
//!   the scheme's coefficients, [`crate::analysis::dispersion`]);
//! - **energy balance error**: the render's largest `|balance_n - balance_0| / max energy`
//!   (energy + dissipated - work), the drift of the quantity the scheme conserves.
//!
//! Runs on the CLI thread (allocates, renders).

use super::metrics::{signal_distances, BandComparison};
use super::offline::Rendered;
use super::report::RenderReport;
use super::scene::render_scene;
use crate::error::Error;
use crate::scene::Scene;
use rayon::prelude::*;
use serde::Serialize;

/// One row of an accuracy table.
#[derive(Debug, Clone, Serialize)]
pub struct AccuracyRow {
    /// The varied setting as given (`96000`, `300`, `sav`, ...).
    pub setting: String,
    /// Its numeric value, when it is a number (for plots).
    pub value: Option<f64>,
    /// Simulation rate of the render (Hz).
    pub sim_rate: f64,
    /// Transverse modes of the render (string: modes).
    pub n_phi: usize,
    /// In-plane modes of the render (0 for strings).
    pub n_psi: usize,
    /// Scheme of the render.
    pub scheme: String,
    /// Wall-clock seconds of the simulation.
    pub wall_seconds: f64,
    /// Relative L2 error of pickup 1 over the first 50 ms.
    pub l2_50ms: f64,
    /// Log-spectral distance of pickup 1 over the whole render (dB).
    pub lsd_db: f64,
    /// Band-level (third-octave) distance of pickup 1 over the whole render (dB).
    pub band_db: f64,
    /// Largest error of the linear partials below the output Nyquist frequency against the
    /// continuous model (cents, closed form; `None` when the model reports none).
    pub partial_cents: Option<f64>,
    /// Largest relative energy-balance error of the render.
    pub energy_balance_error: f64,
    /// Largest relative drift of the energy itself (equals the balance error when lossless).
    pub energy_drift: f64,
    /// Largest contact penetration (m), for models with contact.
    pub max_penetration: Option<f64>,
    /// Newton cap hits, for models with contact.
    pub newton_failures: Option<u64>,
}

/// The result of a study: the reference and one row per value.
#[derive(Debug, Clone, Serialize)]
pub struct AccuracyStudy {
    /// Scene name.
    pub scene: String,
    /// The varied setting (`rate`, `modes`, `psi`, `scheme`).
    pub vary: String,
    /// Rendered duration (s).
    pub seconds: f64,
    /// Output rate all signals are compared at (Hz).
    pub compare_rate: u32,
    /// How the reference was made.
    pub reference: String,
    /// Wall-clock seconds of the reference render.
    pub reference_wall_seconds: f64,
    /// Energy balance error of the reference.
    pub reference_energy_balance_error: f64,
    /// Linear-partial error of the reference (cents).
    pub reference_partial_cents: Option<f64>,
    /// The metrics' floor for this note (preset studies; `None` for scenes).
    pub sensitivity: Option<SensitivityFloor>,
    /// One row per value.
    pub rows: Vec<AccuracyRow>,
    /// Per row (same order), the distances band by band (kept out of the rows so that they
    /// stay one CSV line each).
    pub row_bands: Vec<Vec<BandComparison>>,
}

/// How far the metrics move for an inaudible change of the note itself: the reference against
/// the same reference with its excitation level (strike force, mallet speed or pluck amplitude)
/// changed by a relative `relative_change`. A variant whose distance from the reference is
/// near or below this floor differs from it by no more than the note's own sensitivity (a
/// hard-struck gong in its cascade regime is chaotic: docs/ACCURACY.md).
#[derive(Debug, Clone, Serialize)]
pub struct SensitivityFloor {
    /// The engine parameter changed (its key).
    pub parameter: String,
    /// The relative change of its value (negative: quieter).
    pub relative_change: f64,
    /// Relative L2 over the first 50 ms, as [`AccuracyRow::l2_50ms`].
    pub l2_50ms: f64,
    /// Log-spectral distance (dB), as [`AccuracyRow::lsd_db`].
    pub lsd_db: f64,
    /// Band-level distance (dB), as [`AccuracyRow::band_db`].
    pub band_db: f64,
    /// The distances band by band.
    pub bands: Vec<BandComparison>,
}

impl SensitivityFloor {
    /// How tables and figures name the floor: `floor: <parameter> <relative change>`.
    pub fn label(&self) -> String {
        format!("floor: {} {:+e}", self.parameter, self.relative_change)
    }
}

/// One setting of a study: its label, its numeric value when it has one, and the scene under it.
#[derive(Debug, Clone)]
pub struct Variant {
    /// The setting as given on the command line.
    pub setting: String,
    /// Its numeric value, when it is a number.
    pub value: Option<f64>,
    /// The scene with the setting applied (validated).
    pub scene: Scene,
}

/// Compares a render with the reference render: its row and its distances band by band.
pub fn compare(
    variant: &Variant,
    r: &Rendered,
    report: &RenderReport,
    reference: &Rendered,
    out_rate: u32,
) -> (AccuracyRow, Vec<BandComparison>) {
    let d = signal_distances(&r.out[0], &reference.out[0], f64::from(out_rate));
    let row = AccuracyRow {
        setting: variant.setting.clone(),
        value: variant.value,
        sim_rate: report.sim_rate,
        n_phi: report.n_phi,
        n_psi: report.n_psi,
        scheme: report.scheme.clone(),
        wall_seconds: report.wall_seconds,
        l2_50ms: d.l2_50ms,
        lsd_db: d.lsd_db,
        band_db: d.band_db,
        partial_cents: report.linear_partials_max_cents,
        energy_balance_error: report.energy.max_balance_error,
        energy_drift: report.energy.max_rel_drift,
        max_penetration: report.contact.as_ref().map(|c| c.max_penetration),
        newton_failures: report.contact.as_ref().map(|c| c.newton_failures),
    };
    (row, d.bands)
}

/// Renders `reference` and every variant and compares each with the reference; `vary` names
/// the setting and `reference_description` says how the reference was made (both go into the
/// table). All scenes must share the output rate and duration. The renders run in parallel on
/// the cores (each render's `wall_seconds` is then measured beside the others); the rows keep
/// the variants' order. `log` receives one line per render, in that order, once all are done.
pub fn study(
    vary: &str,
    variants: &[Variant],
    reference: &Scene,
    reference_description: String,
    mut log: impl FnMut(&str),
) -> Result<AccuracyStudy, Error> {
    let out_rate = reference.output.sample_rate;
    for v in variants {
        if v.scene.output.sample_rate != out_rate
            || v.scene.output.seconds != reference.output.seconds
        {
            return Err(Error::StudyOutputMismatch {
                setting: v.setting.clone(),
            });
        }
    }
    // The renders are independent: all of them at once on the cores (rayon), the results
    // kept in the variants' order.
    let (reference_render, renders) = rayon::join(
        || render_scene(reference, |_| {}),
        || {
            variants
                .par_iter()
                .map(|v| render_scene(&v.scene, |_| {}))
                .collect::<Vec<_>>()
        },
    );
    let (ref_out, ref_report) = reference_render?;
    log(&format!(
        "reference ({reference_description}): {:.2} s wall",
        ref_report.wall_seconds
    ));
    let (mut rows, mut row_bands) = (Vec::new(), Vec::new());
    for (v, render) in variants.iter().zip(renders) {
        let (r, report) = render?;
        let (row, bands) = compare(v, &r, &report, &ref_out, out_rate);
        log(&format!(
            "{} = {}: {:.2} s wall, L2(50 ms) {:.3e}, LSD {:.3} dB, bands {:.3} dB, partials {} cents, balance error {:.2e}",
            vary,
            v.setting,
            row.wall_seconds,
            row.l2_50ms,
            row.lsd_db,
            row.band_db,
            row.partial_cents.map_or("-".into(), |c| format!("{c:.2e}")),
            row.energy_balance_error
        ));
        rows.push(row);
        row_bands.push(bands);
    }
    Ok(AccuracyStudy {
        scene: reference.name.clone(),
        vary: vary.into(),
        seconds: reference.output.seconds,
        compare_rate: out_rate,
        reference: reference_description,
        reference_wall_seconds: ref_report.wall_seconds,
        reference_energy_balance_error: ref_report.energy.max_balance_error,
        reference_partial_cents: ref_report.linear_partials_max_cents,
        sensitivity: None,
        rows,
        row_bands,
    })
}

/// Renders `scene` at each simulation rate of `rates` (Hz) and at `reference_rate`, and
/// compares each with the reference (the `rate` study of [`study`]).
pub fn study_rate(
    scene: &Scene,
    rates: &[f64],
    reference_rate: f64,
    log: impl FnMut(&str),
) -> Result<AccuracyStudy, Error> {
    let at = |fs: f64| -> Result<Scene, Error> {
        let mut s = scene.clone();
        s.set_sim_rate(fs)?;
        Ok(s)
    };
    let variants = rates
        .iter()
        .map(|&fs| {
            Ok(Variant {
                setting: format!("{fs}"),
                value: Some(fs),
                scene: at(fs)?,
            })
        })
        .collect::<Result<Vec<_>, Error>>()?;
    study(
        "rate",
        &variants,
        &at(reference_rate)?,
        format!("the same scene at sim_rate = {reference_rate} Hz (same modes, same scheme)"),
        log,
    )
}
