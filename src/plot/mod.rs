//! PNG figures: line plots in one or more panels (waveforms, energies, phase portraits,
//! convergence) drawn with `plotters` on its bitmap backend.
//!
//! Text uses DejaVu Sans embedded through the `dejavu` crate, so no system font library is
//! needed. Long series are reduced to a min/max envelope per pixel column before drawing, so a
//! 10⁶-sample oscillation still shows its envelope. Runs on whatever thread renders the report
//! (never the audio thread).

pub mod spectrogram;

pub use crate::error::PlotError;

use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};
use std::path::Path;
use std::sync::Once;

/// Font family name registered for all figures.
pub(crate) const FONT: &str = "sans-serif";
/// Maximum number of points drawn per series (after envelope reduction).
const MAX_POINTS: usize = 4000;

/// Maximum number of markers drawn per point series (evenly strided).
const MAX_SCATTER: usize = 20_000;

/// Distinct, colour-blind-friendly line colours (Okabe-Ito), cycled by series index.
const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
    RGBColor(0, 0, 0),
];

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mark {
    /// A continuous line.
    Line,
    /// Small filled circles at the data points.
    Points,
    /// A line with circles at the data points (for short series such as convergence studies).
    LinePoints,
}

/// One data series of a panel.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// Abscissae.
    pub x: Vec<f64>,
    /// Ordinates (same length as `x`).
    pub y: Vec<f64>,
    /// How to draw it.
    pub mark: Mark,
}

impl Series {
    /// A line series.
    pub fn line(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self {
            label: label.into(),
            x,
            y,
            mark: Mark::Line,
        }
    }

    /// A series with the given mark.
    pub fn with_mark(mut self, mark: Mark) -> Self {
        self.mark = mark;
        self
    }
}

/// Axis scale of a panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Scale {
    /// Linear axis.
    #[default]
    Linear,
    /// Base-10 logarithmic axis: data are plotted as `log10(value)` (non-positive values are
    /// dropped) and the axis label says so.
    Log10,
}

/// One panel (a set of axes) of a figure.
#[derive(Debug, Clone, Default)]
pub struct Panel {
    /// Caption above the panel.
    pub title: String,
    /// Label of the horizontal axis.
    pub x_label: String,
    /// Label of the vertical axis.
    pub y_label: String,
    /// Scale of the horizontal axis.
    pub x_scale: Scale,
    /// Scale of the vertical axis.
    pub y_scale: Scale,
    /// The data.
    pub series: Vec<Series>,
}

impl Panel {
    /// A panel with linear axes.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Self::default()
        }
    }

    /// Sets both axis scales.
    pub fn scales(mut self, x: Scale, y: Scale) -> Self {
        self.x_scale = x;
        self.y_scale = y;
        self
    }

    /// Adds a series.
    pub fn push(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }
}

pub(crate) fn err(e: impl std::fmt::Display) -> PlotError {
    PlotError(e.to_string())
}

pub(crate) fn ensure_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded font is valid TrueType; a failure here would be a packaging bug.
        let _ = register_font(FONT, FontStyle::Normal, dejavu::sans::regular());
    });
}

/// Writes a PNG of `panels` stacked in a grid of `cols` columns, each panel `panel_size` pixels.
pub fn write_png(
    path: &Path,
    title: &str,
    panels: &[Panel],
    cols: usize,
    panel_size: (u32, u32),
) -> Result<(), PlotError> {
    ensure_font();
    let cols = cols.max(1);
    let rows = panels.len().div_ceil(cols).max(1);
    let size = (panel_size.0 * cols as u32, panel_size.1 * rows as u32 + 40);
    let root = BitMapBackend::new(path, size).into_drawing_area();
    root.fill(&WHITE).map_err(err)?;
    let root = root.titled(title, (FONT, 24).into_font()).map_err(err)?;
    let areas = root.split_evenly((rows, cols));
    for (panel, area) in panels.iter().zip(areas.iter()) {
        draw_panel(area, panel)?;
    }
    root.present()
        .map_err(|e| PlotError(format!("writing {}: {e}", path.display())))?;
    Ok(())
}

fn transform(v: f64, scale: Scale) -> Option<f64> {
    match scale {
        Scale::Linear => v.is_finite().then_some(v),
        Scale::Log10 => (v > 0.0 && v.is_finite()).then(|| v.log10()),
    }
}

fn axis_label(label: &str, scale: Scale) -> String {
    match scale {
        Scale::Linear => label.to_string(),
        Scale::Log10 => format!("log10 {label}"),
    }
}

/// Reduces a series to at most about `MAX_POINTS` points, keeping each bucket's min and max
/// (in sample order) so oscillation envelopes survive.
fn envelope(x: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    let n = x.len().min(y.len());
    if n <= MAX_POINTS {
        return (0..n).map(|i| (x[i], y[i])).collect();
    }
    let buckets = MAX_POINTS / 2;
    let mut out = Vec::with_capacity(MAX_POINTS + 2);
    for b in 0..buckets {
        let (lo, hi) = (
            b * n / buckets,
            ((b + 1) * n / buckets).max(b * n / buckets + 1),
        );
        let (mut imin, mut imax) = (lo, lo);
        for i in lo..hi.min(n) {
            if y[i] < y[imin] {
                imin = i;
            }
            if y[i] > y[imax] {
                imax = i;
            }
        }
        let (a, b2) = if imin <= imax {
            (imin, imax)
        } else {
            (imax, imin)
        };
        out.push((x[a], y[a]));
        if b2 != a {
            out.push((x[b2], y[b2]));
        }
    }
    out
}

fn draw_panel(
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    panel: &Panel,
) -> Result<(), PlotError> {
    let data: Vec<Vec<(f64, f64)>> = panel
        .series
        .iter()
        .map(|s| {
            let pts = if s.mark == Mark::Line {
                envelope(&s.x, &s.y)
            } else {
                let stride = s.x.len().div_ceil(MAX_SCATTER).max(1);
                s.x.iter()
                    .copied()
                    .zip(s.y.iter().copied())
                    .step_by(stride)
                    .collect()
            };
            pts.into_iter()
                .filter_map(|(x, y)| {
                    Some((transform(x, panel.x_scale)?, transform(y, panel.y_scale)?))
                })
                .collect()
        })
        .collect();
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in data.iter().flatten() {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    let pad = |lo: f64, hi: f64| {
        let span = hi - lo;
        // A constant series gets a band of ±50 % of its value (±1 around zero).
        let m = if span > 0.0 {
            0.05 * span
        } else if lo != 0.0 {
            0.5 * lo.abs()
        } else {
            1.0
        };
        (lo - m, hi + m)
    };
    // Scatter panels (no continuous line) get room around their points and headroom for the
    // legend (upper right) so no point hides at an edge or under the legend.
    let scatter = panel.series.iter().all(|s| s.mark != Mark::Line);
    let (x0, x1) = if x1 > x0 && !scatter {
        (x0, x1)
    } else {
        pad(x0, x1)
    };
    let (y0, y1) = pad(y0, y1);
    let y1 = if scatter { y1 + 0.5 * (y1 - y0) } else { y1 };
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, (FONT, 18).into_font())
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(axis_label(&panel.x_label, panel.x_scale))
        .y_desc(axis_label(&panel.y_label, panel.y_scale))
        .label_style((FONT, 14).into_font())
        .axis_desc_style((FONT, 15).into_font())
        .y_label_formatter(&|v| format_tick(*v, y1 - y0))
        .x_label_formatter(&|v| format_tick(*v, x1 - x0))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(err)?;
    for (k, (s, pts)) in panel.series.iter().zip(data).enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        // Wide strokes of dense, nearly vertical envelope segments render as spikes past the
        // plot area in plotters' bitmap backend: dense series are drawn one pixel wide.
        let width = if pts.len() > 1000 { 1 } else { 2 };
        let style = ShapeStyle::from(&color).stroke_width(width);
        let legend_style = style;
        match s.mark {
            Mark::Line => {
                chart
                    .draw_series(LineSeries::new(pts, style))
                    .map_err(err)?
                    .label(s.label.clone())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], legend_style)
                    });
            }
            Mark::Points | Mark::LinePoints => {
                if s.mark == Mark::LinePoints {
                    chart
                        .draw_series(LineSeries::new(pts.clone(), style))
                        .map_err(err)?;
                }
                chart
                    .draw_series(pts.into_iter().map(|p| Circle::new(p, 3, color.filled())))
                    .map_err(err)?
                    .label(s.label.clone())
                    .legend(move |(x, y)| Circle::new((x + 10, y), 3, color.filled()));
            }
        }
    }
    if panel.series.iter().any(|s| !s.label.is_empty()) {
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FONT, 14).into_font())
            .position(SeriesLabelPosition::UpperRight)
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

/// Tick label for value `v` on an axis spanning `span`: values within `1e-9 span` of zero
/// print as 0; enough significant digits are kept to tell neighbouring ticks apart (about a
/// hundredth of the span); scientific notation outside `[1e-3, 1e5)`.
fn format_tick(v: f64, span: f64) -> String {
    let a = v.abs();
    if a == 0.0 || (span > 0.0 && a < 1e-9 * span) {
        return "0".into();
    }
    // Digits after the leading one needed to resolve span/100 at magnitude |v|.
    let resolution = if span > 0.0 { span / 100.0 } else { a * 1e-3 };
    let digits = ((a / resolution).log10().ceil().max(1.0) as usize).min(12);
    if (1e-3..1e5).contains(&a) {
        let decimals = digits
            .saturating_sub(a.log10().floor() as usize + 1)
            .min(12);
        let decimals = if a < 1.0 {
            (-(resolution.log10().floor())).max(0.0) as usize
        } else {
            decimals
        };
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.prec$e}", prec = digits.saturating_sub(1).min(10))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn envelope_keeps_extremes_and_bounds_size() {
        let n = 1_000_000;
        let x: Vec<f64> = (0..n).map(|i| i as f64).collect();
        let y: Vec<f64> = (0..n).map(|i| (i as f64 * 0.37).sin()).collect();
        let e = envelope(&x, &y);
        assert!(e.len() <= MAX_POINTS + 2);
        let max = e.iter().map(|p| p.1).fold(f64::MIN, f64::max);
        assert!(max > 0.999, "envelope lost the peaks: {max}");
    }

    #[test]
    fn tick_labels_resolve_their_axis() {
        assert_eq!(format_tick(-2.22e-16, 2.0), "0");
        assert_eq!(format_tick(0.25, 2.0), "0.25");
        assert_eq!(format_tick(12.0, 40.0), "12");
        // Large values with a tiny span keep enough digits to differ.
        let a = format_tick(7.07000001e11, 2e4);
        let b = format_tick(7.07000003e11, 2e4);
        assert_ne!(a, b, "{a} vs {b}");
        assert_eq!(format_tick(1.5e-12, 3e-12), "1.5e-12");
    }

    #[test]
    fn writes_a_png() {
        let dir = std::env::temp_dir().join(format!("noether-plot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("t.png");
        let x: Vec<f64> = (0..100).map(|i| i as f64 * 0.1).collect();
        let y: Vec<f64> = x.iter().map(|t| t.sin()).collect();
        let panel = Panel::new("sine", "t", "u").push(Series::line("sin", x.clone(), y));
        let log = Panel::new("log", "h", "err")
            .scales(Scale::Log10, Scale::Log10)
            .push(Series::line("e", vec![0.1, 0.01], vec![1e-2, 1e-4]).with_mark(Mark::LinePoints));
        write_png(&path, "test", &[panel, log], 2, (400, 300)).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[1..4], b"PNG");
        std::fs::remove_dir_all(&dir).ok();
    }
}
