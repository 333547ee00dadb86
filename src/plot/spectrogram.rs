//! Spectrogram heat map PNG (time horizontal, frequency vertical, dB colour scale).

use super::{ensure_font, err, PlotError, FONT};
use crate::analysis::spectrogram::Spectrogram;
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

/// Writes `spec` as a heat map, showing frequencies up to `max_freq` Hz and a dynamic range
/// of `range_db` dB below the loudest cell.
pub fn write_spectrogram_png(
    path: &Path,
    title: &str,
    spec: &Spectrogram,
    max_freq: f64,
    range_db: f64,
) -> Result<(), PlotError> {
    ensure_font();
    let (w, h) = (1100u32, 620u32);
    let root = BitMapBackend::new(path, (w, h)).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let t_end = spec.times.last().copied().unwrap_or(0.0)
        + if spec.times.len() > 1 {
            spec.times[1] - spec.times[0]
        } else {
            0.0
        };
    let f_top = max_freq
        .min(spec.freqs.last().copied().unwrap_or(max_freq))
        .max(1.0);
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (FONT, 22).into_font())
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..t_end.max(1e-9), 0.0..f_top)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("time (s)")
        .y_desc("frequency (Hz)")
        .label_style((FONT, 14).into_font())
        .axis_desc_style((FONT, 15).into_font())
        .draw()
        .map_err(err)?;
    let (px0, px1) = chart.plotting_area().get_pixel_range();
    let (iw, ih) = (
        (px0.end - px0.start).max(1) as u32,
        (px1.end - px1.start).max(1) as u32,
    );
    let mut buf = vec![0u8; (iw * ih * 3) as usize];
    let frames = spec.db.len().max(1);
    let df = if spec.freqs.len() > 1 {
        spec.freqs[1]
    } else {
        1.0
    };
    for x in 0..iw {
        let fi = ((x as f64 / iw as f64) * frames as f64) as usize;
        let Some(frame) = spec.db.get(fi.min(frames - 1)) else {
            continue;
        };
        for y in 0..ih {
            let f = (1.0 - (y as f64 + 0.5) / ih as f64) * f_top;
            let bin = ((f / df).round() as usize).min(frame.len().saturating_sub(1));
            let v = (frame.get(bin).copied().unwrap_or(-200.0) + range_db) / range_db;
            let c = colour(v);
            let i = ((y * iw + x) * 3) as usize;
            buf[i..i + 3].copy_from_slice(&c);
        }
    }
    let elem = BitMapElement::with_owned_buffer((0.0, f_top), (iw, ih), buf)
        .ok_or_else(|| PlotError("spectrogram buffer size mismatch".into()))?;
    chart.draw_series(std::iter::once(elem)).map_err(err)?;
    root.present()
        .map_err(|e| PlotError(format!("writing {}: {e}", path.display())))?;
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
        let path = std::env::temp_dir().join(format!("noether-spec-{}.png", std::process::id()));
        write_spectrogram_png(&path, "chirp", &s, 4000.0, 90.0).unwrap();
        assert!(std::fs::metadata(&path).unwrap().len() > 1000);
        std::fs::remove_file(&path).ok();
    }
}
