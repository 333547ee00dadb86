//! Spectrogram heat map PNG (time horizontal, frequency vertical, dB colour scale), on a linear
//! or a logarithmic frequency axis ([`FreqAxis`]).
//!
//! Each pixel row shows the loudest STFT bin among those its frequency interval covers (at
//! least the nearest bin), so a narrow partial is not lost when many bins share a row (the
//! top of a log axis, or any long linear axis); where a row is narrower than a bin (the bottom
//! of a log axis) neighbouring rows repeat that bin.

use super::{ensure_font, err, PlotError, FONT};
use crate::analysis::spectrogram::Spectrogram;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::element::BitMapElement;
use plotters::prelude::*;
use std::path::Path;

/// Control points of the viridis colour map (0 = dark purple, 1 = yellow).
const VIRIDIS: [(f64, [u8; 3]); 5] = [
    (0.0, [68, 1, 84]),
    (0.25, [59, 82, 139]),
    (0.5, [33, 145, 140]),
    (0.75, [94, 201, 98]),
    (1.0, [253, 231, 37]),
];

/// Figure size in pixels.
const SIZE: (u32, u32) = (1100, 620);

/// Tick candidates of a logarithmic axis (Hz): 1-2-5 per decade.
const LOG_TICKS: [f64; 13] = [
    10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1e3, 2e3, 5e3, 1e4, 2e4, 5e4, 1e5,
];

fn colour(v: f64) -> [u8; 3] {
    let v = v.clamp(0.0, 1.0);
    for w in VIRIDIS.windows(2) {
        let ((a, ca), (b, cb)) = (w[0], w[1]);
        if v <= b {
            let t = (v - a) / (b - a);
            let mix = |i: usize| (ca[i] as f64 + t * (cb[i] as f64 - ca[i] as f64)).round() as u8;
            return [mix(0), mix(1), mix(2)];
        }
    }
    VIRIDIS[4].1
}

/// The frequency axis of a spectrogram figure (Hz). Both bounds are capped at the
/// spectrogram's highest bin (its Nyquist frequency).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FreqAxis {
    /// Linear from 0 Hz to `max`.
    Linear {
        /// Top of the axis (Hz).
        max: f64,
    },
    /// Logarithmic from `min` to `max` (`0 < min < max`): equal heights for equal frequency
    /// ratios, so a cascade from hundreds of Hz to kHz spreads over the figure.
    Log {
        /// Bottom of the axis (Hz, > 0).
        min: f64,
        /// Top of the axis (Hz).
        max: f64,
    },
}

impl FreqAxis {
    /// The axis' bounds after capping at `nyquist` (Hz); the bottom stays below the top.
    fn bounds(self, nyquist: f64) -> (f64, f64) {
        match self {
            FreqAxis::Linear { max } => (0.0, max.min(nyquist).max(1.0)),
            FreqAxis::Log { min, max } => {
                let top = max.min(nyquist).max(2.0);
                (min.clamp(1e-3, top / 2.0), top)
            }
        }
    }

    /// Frequency (Hz) at fraction `frac` of the plot height measured from the top.
    fn freq_at(self, lo: f64, hi: f64, frac: f64) -> f64 {
        match self {
            FreqAxis::Linear { .. } => hi - frac * (hi - lo),
            FreqAxis::Log { .. } => (hi.ln() - frac * (hi.ln() - lo.ln())).exp(),
        }
    }
}

/// Writes `spec` as a heat map on frequency axis `axis`, with a dynamic range of `range_db` dB
/// below the loudest cell.
pub fn write_spectrogram_png(
    path: &Path,
    title: &str,
    spec: &Spectrogram,
    axis: FreqAxis,
    range_db: f64,
) -> Result<(), PlotError> {
    ensure_font();
    let root = BitMapBackend::new(path, SIZE).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let t_end = spec.times.last().copied().unwrap_or(0.0)
        + if spec.times.len() > 1 {
            spec.times[1] - spec.times[0]
        } else {
            0.0
        };
    let nyquist = spec.freqs.last().copied().unwrap_or(f64::INFINITY);
    let (lo, hi) = axis.bounds(nyquist);
    let mut builder = ChartBuilder::on(&root);
    builder
        .caption(title, (FONT, 22).into_font())
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70);
    let x = 0.0..t_end.max(1e-9);
    match axis {
        FreqAxis::Linear { .. } => {
            let chart = builder.build_cartesian_2d(x, lo..hi).map_err(err)?;
            draw_heat(chart, spec, axis, (lo, hi), range_db, "frequency (Hz)")?;
        }
        FreqAxis::Log { .. } => {
            let mut ticks: Vec<f64> = LOG_TICKS
                .iter()
                .copied()
                .filter(|&f| f >= lo && f <= hi)
                .collect();
            if ticks.len() < 2 {
                ticks = vec![lo, hi];
            }
            let chart = builder
                .build_cartesian_2d(x, (lo..hi).log_scale().with_key_points(ticks))
                .map_err(err)?;
            draw_heat(
                chart,
                spec,
                axis,
                (lo, hi),
                range_db,
                "frequency (Hz, log scale)",
            )?;
        }
    }
    root.present()
        .map_err(|e| PlotError(format!("writing {}: {e}", path.display())))?;
    Ok(())
}

/// Draws the mesh and the heat map into `chart` (any frequency coordinate whose values are Hz).
fn draw_heat<Y>(
    mut chart: ChartContext<'_, BitMapBackend<'_>, Cartesian2d<RangedCoordf64, Y>>,
    spec: &Spectrogram,
    axis: FreqAxis,
    (lo, hi): (f64, f64),
    range_db: f64,
    y_desc: &str,
) -> Result<(), PlotError>
where
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("time (s)")
        .y_desc(y_desc)
        .y_label_formatter(&|f| {
            if *f >= 1000.0 {
                format!("{}k", *f / 1000.0)
            } else {
                format!("{f}")
            }
        })
        .label_style((FONT, 14).into_font())
        .axis_desc_style((FONT, 15).into_font())
        .draw()
        .map_err(err)?;
    let (px0, px1) = chart.plotting_area().get_pixel_range();
    let (iw, ih) = (
        (px0.end - px0.start).max(1) as u32,
        (px1.end - px1.start).max(1) as u32,
    );
    let df = if spec.freqs.len() > 1 {
        spec.freqs[1]
    } else {
        1.0
    };
    let last_bin = spec.freqs.len().saturating_sub(1);
    // Bins covered by each pixel row: from the row's bottom edge to its top edge.
    let rows: Vec<(usize, usize)> = (0..ih)
        .map(|y| {
            let f_top = axis.freq_at(lo, hi, y as f64 / ih as f64);
            let f_bot = axis.freq_at(lo, hi, (y + 1) as f64 / ih as f64);
            let centre = axis.freq_at(lo, hi, (y as f64 + 0.5) / ih as f64);
            let nearest = ((centre / df).round() as usize).min(last_bin);
            let a = ((f_bot / df).ceil() as usize).min(last_bin);
            let b = ((f_top / df).floor() as usize).min(last_bin);
            if a <= b {
                (a, b)
            } else {
                (nearest, nearest)
            }
        })
        .collect();
    let mut buf = vec![0u8; (iw * ih * 3) as usize];
    let frames = spec.db.len().max(1);
    for x in 0..iw {
        let fi = ((x as f64 / iw as f64) * frames as f64) as usize;
        let Some(frame) = spec.db.get(fi.min(frames - 1)) else {
            continue;
        };
        for (y, &(a, b)) in rows.iter().enumerate() {
            let db = frame
                .get(a..=b)
                .map_or(-200.0, |s| s.iter().fold(-200.0f64, |m, &v| m.max(v)));
            let c = colour((db + range_db) / range_db);
            let i = ((y as u32 * iw + x) * 3) as usize;
            buf[i..i + 3].copy_from_slice(&c);
        }
    }
    let elem = BitMapElement::with_owned_buffer((0.0, hi), (iw, ih), buf)
        .ok_or_else(|| PlotError("spectrogram buffer size mismatch".into()))?;
    chart.draw_series(std::iter::once(elem)).map_err(err)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::spectrogram::spectrogram;

    #[test]
    fn writes_a_spectrogram() {
        let rate = 8000.0;
        let x: Vec<f64> = (0..16000)
            .map(|n| (std::f64::consts::TAU * (200.0 + 0.1 * n as f64) * n as f64 / rate).sin())
            .collect();
        let s = spectrogram(&x, rate, 512, 128);
        for (name, axis) in [
            ("lin", FreqAxis::Linear { max: 4000.0 }),
            (
                "log",
                FreqAxis::Log {
                    min: 20.0,
                    max: 4000.0,
                },
            ),
        ] {
            let path = std::env::temp_dir()
                .join(format!("noether-spec-{name}-{}.png", std::process::id()));
            write_spectrogram_png(&path, "chirp", &s, axis, 90.0).unwrap();
            assert!(std::fs::metadata(&path).unwrap().len() > 1000);
            std::fs::remove_file(&path).ok();
        }
    }

    /// On the log axis, the row at fraction `f` of the height has frequency `lo (hi/lo)^(1-f)`:
    /// the middle row of 20 Hz..2 kHz is 200 Hz (exact up to round-off, 1e-9 relative); on
    /// the linear axis it is the arithmetic mean. The bounds are capped at Nyquist.
    #[test]
    fn row_frequencies() {
        let log = FreqAxis::Log {
            min: 20.0,
            max: 2000.0,
        };
        let (lo, hi) = log.bounds(24_000.0);
        assert!((log.freq_at(lo, hi, 0.5) - 200.0).abs() < 200.0 * 1e-9);
        let lin = FreqAxis::Linear { max: 2000.0 };
        let (lo, hi) = lin.bounds(24_000.0);
        assert!((lin.freq_at(lo, hi, 0.5) - 1000.0).abs() < 1e-9);
        assert_eq!(log.bounds(1000.0), (20.0, 1000.0));
    }
}
