//! Accuracy against a reference render: the metrics of `noether accuracy` (stated in
//! docs/ACCURACY.md) and the study that varies one setting of a scene.
//!
//! Metrics, each comparing pickup 1 of a render with pickup 1 of the reference, both at the
//! scene's output rate (every render is resampled to it by the render loop, so the signals share
//! one rate and one length):
//! - **relative L2 error over the first 50 ms**: `‖y - y_ref‖₂ / ‖y_ref‖₂` over the first
//!   `round(0.05 · rate)` samples (long waveforms of nonlinear models diverge in phase, so only
//!   the attack is compared sample by sample);
//! - **log-spectral distance** over the whole render: the RMS over STFT frames and bins of
//!   `10 log10(P + ε) - 10 log10(P_ref + ε)` (dB), Hann window of 2048 samples, hop 512, with
//!   `ε` = 1e-8 of the reference's largest bin power (a -80 dB floor, so bins silent in both do
//!   not count);
//! - **linear partials**: the largest error in cents of the scheme's linear partials against
//!   the continuous model's, over the modes below the output Nyquist frequency (closed form from
//!   the scheme's coefficients, [`crate::analysis::dispersion`]);
//! - **energy balance error**: the render's largest `|balance_n - balance_0| / max energy`
//!   (energy + dissipated - work), the drift of the quantity the scheme conserves.
//!
//! Runs on the CLI thread (allocates, renders).

use super::offline::Rendered;
use super::report::RenderReport;
use super::scene::render_scene;
use crate::error::Error;
use crate::scene::Scene;
use rayon::prelude::*;
use rustfft::{num_complex::Complex, FftPlanner};
use serde::Serialize;

/// STFT window of the log-spectral distance (samples).
pub const LSD_WINDOW: usize = 2048;
/// STFT hop of the log-spectral distance (samples).
pub const LSD_HOP: usize = 512;
/// Floor of the log-spectral distance relative to the reference's largest bin power.
pub const LSD_FLOOR: f64 = 1e-8;
/// Length of the waveform comparison (s).
pub const L2_SECONDS: f64 = 0.05;

/// Relative L2 error `‖y - r‖ / ‖r‖` over the first `n` samples (or the common length).
pub fn relative_l2(y: &[f64], reference: &[f64], n: usize) -> f64 {
    let n = n.min(y.len()).min(reference.len());
    let (mut num, mut den) = (0.0, 0.0);
    for (a, b) in y[..n].iter().zip(&reference[..n]) {
        num += (a - b) * (a - b);
        den += b * b;
    }
    if den > 0.0 {
        (num / den).sqrt()
    } else {
        num.sqrt()
    }
}

/// Power spectra `|X|²` of Hann-windowed frames of `x`.
fn power_frames(x: &[f64]) -> Vec<Vec<f64>> {
    let fft = FftPlanner::<f64>::new().plan_fft_forward(LSD_WINDOW);
    let hann: Vec<f64> = (0..LSD_WINDOW)
        .map(|n| 0.5 - 0.5 * (std::f64::consts::TAU * n as f64 / LSD_WINDOW as f64).cos())
        .collect();
    let mut out = Vec::new();
    let mut buf = vec![Complex::new(0.0, 0.0); LSD_WINDOW];
    let mut start = 0;
    loop {
        for (n, b) in buf.iter_mut().enumerate() {
            *b = Complex::new(x.get(start + n).copied().unwrap_or(0.0) * hann[n], 0.0);
        }
        fft.process(&mut buf);
        out.push(
            buf[..=LSD_WINDOW / 2]
                .iter()
                .map(|c| c.norm_sqr())
                .collect(),
        );
        start += LSD_HOP;
        if start + LSD_WINDOW > x.len() {
            break;
        }
    }
    out
}

/// Log-spectral distance in dB between `y` and `reference` (see the module doc).
pub fn log_spectral_distance(y: &[f64], reference: &[f64]) -> f64 {
    let n = y.len().min(reference.len());
    let (a, b) = (power_frames(&y[..n]), power_frames(&reference[..n]));
    let peak = b.iter().flatten().fold(0.0f64, |m, &p| m.max(p));
    let eps = (LSD_FLOOR * peak).max(f64::MIN_POSITIVE);
    let (mut sum, mut count) = (0.0, 0usize);
    for (fa, fb) in a.iter().zip(&b) {
        for (pa, pb) in fa.iter().zip(fb) {
            let d = 10.0 * ((pa + eps) / (pb + eps)).log10();
            sum += d * d;
            count += 1;
        }
    }
    (sum / count.max(1) as f64).sqrt()
}

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

/// Compares a render with the reference render.
pub fn compare(
    variant: &Variant,
    r: &Rendered,
    report: &RenderReport,
    reference: &Rendered,
    out_rate: u32,
) -> AccuracyRow {
    let n = (L2_SECONDS * out_rate as f64).round() as usize;
    AccuracyRow {
        setting: variant.setting.clone(),
        value: variant.value,
        sim_rate: report.sim_rate,
        n_phi: report.n_phi,
        n_psi: report.n_psi,
        scheme: report.scheme.clone(),
        wall_seconds: report.wall_seconds,
        l2_50ms: relative_l2(&r.out[0], &reference.out[0], n),
        lsd_db: log_spectral_distance(&r.out[0], &reference.out[0]),
        partial_cents: report.linear_partials_max_cents,
        energy_balance_error: report.energy.max_balance_error,
        energy_drift: report.energy.max_rel_drift,
        max_penetration: report.contact.as_ref().map(|c| c.max_penetration),
        newton_failures: report.contact.as_ref().map(|c| c.newton_failures),
    }
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
    let mut rows = Vec::new();
    for (v, render) in variants.iter().zip(renders) {
        let (r, report) = render?;
        let row = compare(v, &r, &report, &ref_out, out_rate);
        log(&format!(
            "{} = {}: {:.2} s wall, L2(50 ms) {:.3e}, LSD {:.3} dB, partials {} cents, balance error {:.2e}",
            vary,
            v.setting,
            row.wall_seconds,
            row.l2_50ms,
            row.lsd_db,
            row.partial_cents.map_or("-".into(), |c| format!("{c:.2e}")),
            row.energy_balance_error
        ));
        rows.push(row);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Identical signals have zero distance; a 1 % amplitude change gives L2 = 0.01 exactly
    /// (to round-off, 1e-12) and, on a broadband signal whose bins all lie far above the -80 dB
    /// floor, an LSD of 20 log10(1.01) = 0.0864 dB (the floor's pull is below 1e-6 dB here).
    #[test]
    fn metrics_of_known_differences() {
        // Deterministic pseudo-random noise (xorshift64), uniform in [-1, 1).
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let x: Vec<f64> = (0..48_000)
            .map(|_| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
            })
            .collect();
        let y: Vec<f64> = x.iter().map(|v| 1.01 * v).collect();
        assert_eq!(relative_l2(&x, &x, 2400), 0.0);
        assert_eq!(log_spectral_distance(&x, &x), 0.0);
        assert!((relative_l2(&y, &x, 2400) - 0.01).abs() < 1e-12);
        let lsd = log_spectral_distance(&y, &x);
        let full = 20.0 * 1.01f64.log10();
        assert!((lsd - full).abs() < 1e-6, "{lsd} vs {full}");
    }
}
