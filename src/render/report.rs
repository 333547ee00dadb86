//! The render report (JSON) and figures (energy curves, waveform, spectrogram).

use super::offline::{EnergyStats, Rendered};
use super::shape_plot::write_shape_png;
use super::source::ContactSummary;
use crate::analysis::spectrogram::spectrogram;
use crate::error::Error;
use crate::plot::spectrogram::{write_spectrogram_png, FreqAxis};
use crate::plot::{write_png, Panel, Series};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The JSON report of one render.
#[derive(Debug, Clone, Serialize)]
pub struct RenderReport {
    /// Scene name.
    pub scene: String,
    /// Model family (`plate`, ...).
    pub model: String,
    /// Scheme identifier.
    pub scheme: String,
    /// Whether the scheme conserves its discrete energy.
    pub conservative: bool,
    /// WAV sample rate (Hz).
    pub sample_rate: u32,
    /// Simulation rate (Hz).
    pub sim_rate: f64,
    /// Rendered duration (s).
    pub seconds: f64,
    /// Transverse modes.
    pub n_phi: usize,
    /// In-plane modes.
    pub n_psi: usize,
    /// Energy figures.
    pub energy: EnergyStats,
    /// Non-finite samples or energies (0 for a healthy run).
    pub nan_count: u64,
    /// Largest absolute output sample (after gain).
    pub peak: f64,
    /// Wall-clock seconds of simulation.
    pub wall_seconds: f64,
    /// Simulated seconds per wall-clock second.
    pub realtime_factor: f64,
    /// Threads that shared each step: 2 when a plate's SAV coupling kernel was split between
    /// two (`noether render` with a tensor of at least
    /// [`super::scene::SPLIT_MIN_ENTRIES`] entries and two cores), else 1.
    pub step_threads: usize,
    /// Spectral centroid of pickup 1 (Hz) over the first and the last 100 ms: a rising value
    /// shows energy moving to high frequencies (the gong's cascade); `null` for silence.
    pub spectral_centroid_hz: [Option<f64>; 2],
    /// Largest error (cents) of the scheme's linear partials against the continuous model's,
    /// over the modes below the output's Nyquist frequency (closed form,
    /// [`crate::analysis::dispersion`]); `null` when the model reports none.
    pub linear_partials_max_cents: Option<f64>,
    /// Contact solver figures (models with a contact only): `contact.max_penetration`,
    /// `contact.newton_max_iterations`, `contact.newton_failures`, the iteration histogram.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact: Option<ContactSummary>,
    /// Model-specific figures.
    pub details: serde_json::Map<String, serde_json::Value>,
    /// What the model leaves wrong that a user should know, in words (for example a string
    /// network whose modes lie above the Nyquist frequency); `noether render` prints them.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<String>,
    /// What `quality = "auto"` chose and how it was verified (auto scenes only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub auto: Option<super::auto::AutoReport>,
}

/// Power-weighted mean frequency (Hz) of `x` sampled at `rate`, Hann-windowed over its whole
/// length; `None` when `x` is silent or shorter than 16 samples.
pub fn spectral_centroid(x: &[f64], rate: f64) -> Option<f64> {
    if x.len() < 16 {
        return None;
    }
    let s = spectrogram(x, rate, x.len(), x.len());
    let frame = s.db.first()?;
    let (mut num, mut den) = (0.0, 0.0);
    for (f, db) in s.freqs.iter().zip(frame) {
        let p = 10f64.powf(db / 10.0);
        num += f * p;
        den += p;
    }
    (den > 0.0 && frame.iter().any(|&d| d > -200.0)).then(|| num / den)
}

/// Writes the energy, waveform and spectrogram PNGs of a render into `dir`, named after
/// `stem`; returns the paths written. `max_freq` (Hz) is the top of the spectrogram's
/// logarithmic frequency axis (see [`write_spectrogram`]).
pub fn write_plots(
    dir: &Path,
    stem: &str,
    r: &Rendered,
    sim_rate: f64,
    out_rate: u32,
    max_freq: f64,
) -> Result<Vec<PathBuf>, Error> {
    std::fs::create_dir_all(dir).map_err(|source| Error::CreateDir {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut written = Vec::new();
    let dt = r.energy_stride as f64 / sim_rate;
    let t: Vec<f64> = (0..r.energy.len()).map(|k| k as f64 * dt).collect();
    let col = |f: &dyn Fn(&super::source::EnergyTerms) -> f64| {
        r.energy.iter().map(f).collect::<Vec<f64>>()
    };
    let energies = Panel::new(
        "energies (as on the lecture's slide)",
        "t (s)",
        "energy (J)",
    )
    .push(Series::line("total", t.clone(), col(&|e| e.total())))
    .push(Series::line("kinetic", t.clone(), col(&|e| e.kinetic)))
    .push(Series::line(
        "transverse (linear potential)",
        t.clone(),
        col(&|e| e.linear),
    ))
    .push(Series::line(
        "in-plane / contact (nonlinear)",
        t.clone(),
        col(&|e| e.nonlinear),
    ));
    let scale = r.stats.energy.max.max(f64::MIN_POSITIVE);
    let b0 = r.energy.first().map_or(0.0, |e| e.balance());
    let balance = Panel::new(
        "power balance error",
        "t (s)",
        "(balance - balance0) / max energy",
    )
    .push(Series::line(
        "energy + dissipated - work",
        t.clone(),
        col(&|e| (e.balance() - b0) / scale),
    ));
    let share = Panel::new(
        "nonlinear share of the energy (in-plane or contact)",
        "t (s)",
        "nonlinear / total",
    )
    .push(Series::line(
        "nonlinear / total",
        t.clone(),
        col(&|e| {
            if e.total() > 0.0 {
                e.nonlinear / e.total()
            } else {
                0.0
            }
        }),
    ));
    let losses = Panel::new("losses and work", "t (s)", "energy (J)")
        .push(Series::line(
            "dissipated",
            t.clone(),
            col(&|e| e.dissipated),
        ))
        .push(Series::line(
            "work by the excitation",
            t.clone(),
            col(&|e| e.work),
        ));
    let path = dir.join(format!("{stem}-energy.png"));
    write_png(
        &path,
        &format!("{stem}: energy"),
        &[energies, balance, share, losses],
        2,
        (760, 420),
    )?;
    written.push(path);
    let ch = &r.out[0];
    written.push(write_waveform_png(dir, stem, ch, out_rate)?);
    written.push(write_spectrogram(dir, stem, ch, out_rate, max_freq)?);
    if !r.shapes.is_empty() {
        let path = dir.join(format!("{stem}-shape.png"));
        write_shape_png(
            &path,
            &format!("{stem}: string shape against the obstacle"),
            &r.shapes,
        )?;
        written.push(path);
    }
    Ok(written)
}

/// Bottom of the spectrograms' logarithmic frequency axis (Hz): about twice the bin spacing of
/// their 2048-sample window at 48 kHz (23 Hz); lower rows would only repeat a few bins.
pub const SPECTROGRAM_MIN_HZ: f64 = 50.0;

/// Writes `<stem>-waveform.png` into `dir`: channel `ch` at `rate` Hz and its level (10 ms
/// RMS, dB relative to the loudest frame, floored at -160 dB). Returns the path.
pub fn write_waveform_png(dir: &Path, stem: &str, ch: &[f64], rate: u32) -> Result<PathBuf, Error> {
    let tt: Vec<f64> = (0..ch.len()).map(|n| n as f64 / rate as f64).collect();
    let wave = Panel::new("pickup 1", "t (s)", "output").push(Series::line("", tt, ch.to_vec()));
    let frame = (rate as usize / 100).max(1);
    let rms: Vec<f64> = ch
        .chunks(frame)
        .map(|c| (c.iter().map(|x| x * x).sum::<f64>() / c.len() as f64).sqrt())
        .collect();
    let loudest = rms
        .iter()
        .fold(0.0f64, |m, &x| m.max(x))
        .max(f64::MIN_POSITIVE);
    let db: Vec<f64> = rms
        .iter()
        .map(|&r| (20.0 * (r / loudest).log10()).max(-160.0))
        .collect();
    let t_frames: Vec<f64> = (0..db.len())
        .map(|k| (k * frame) as f64 / rate as f64)
        .collect();
    let env = Panel::new("level (10 ms RMS)", "t (s)", "dB re loudest frame")
        .push(Series::line("", t_frames, db));
    let path = dir.join(format!("{stem}-waveform.png"));
    write_png(
        &path,
        &format!("{stem}: waveform"),
        &[wave, env],
        1,
        (1100, 320),
    )?;
    Ok(path)
}

/// Writes `<stem>-spectrogram.png` into `dir`: channel `ch` at `rate` Hz (2048-sample Hann
/// window, hop 256, 100 dB range) on a logarithmic frequency axis from
/// [`SPECTROGRAM_MIN_HZ`] to `max_freq` (capped at Nyquist), so a cascade from a few hundred
/// Hz to kHz is as tall as it is audible. Returns the path.
pub fn write_spectrogram(
    dir: &Path,
    stem: &str,
    ch: &[f64],
    rate: u32,
    max_freq: f64,
) -> Result<PathBuf, Error> {
    let spec = spectrogram(ch, rate as f64, 2048, 256);
    let path = dir.join(format!("{stem}-spectrogram.png"));
    write_spectrogram_png(
        &path,
        &format!("{stem}: spectrogram (pickup 1, dB)"),
        &spec,
        FreqAxis::Log {
            min: SPECTROGRAM_MIN_HZ,
            max: max_freq,
        },
        100.0,
    )?;
    Ok(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 1 kHz sine has its centroid at 1 kHz (within the Hann main lobe's symmetric spread:
    /// 1 Hz here); silence has none.
    #[test]
    fn centroid_of_a_sine() {
        let rate = 48_000.0;
        let x: Vec<f64> = (0..4800)
            .map(|n| (std::f64::consts::TAU * 1000.0 * n as f64 / rate).sin())
            .collect();
        let c = spectral_centroid(&x, rate).unwrap();
        assert!((c - 1000.0).abs() < 1.0, "{c}");
        assert!(spectral_centroid(&[0.0; 4800], rate).is_none());
    }
}
