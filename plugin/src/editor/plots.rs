//! Drawing of the live views (GUI thread only): the mode spectrum, the string or plate
//! displacement and the CPU load bar (the energy meters are in `meters`). Each takes plain
//! slices so it does not depend on how the telemetry reached the GUI.

use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, StrokeKind, Ui, Vec2};

/// A dark framed area of `size` points for a plot, and its painter.
pub(super) fn frame(ui: &mut Ui, size: Vec2) -> (Rect, egui::Painter) {
    let (response, painter) = ui.allocate_painter(size, Sense::hover());
    let rect = response.rect;
    painter.rect_filled(rect, 2.0, Color32::from_gray(18));
    painter.rect_stroke(
        rect,
        2.0,
        Stroke::new(1.0, Color32::from_gray(60)),
        StrokeKind::Inside,
    );
    (rect, painter)
}

/// The plots' label font.
pub(super) fn small_font() -> FontId {
    FontId::proportional(11.0)
}

/// Range of the spectrum's amplitude axis, dB below the strongest mode.
const SPECTRUM_DB: f32 = 60.0;
/// Left margin of the spectrum for its dB labels (points).
const AXIS_W: f32 = 34.0;

/// Frequency tick label: "50 Hz", "1 kHz".
fn freq_label(f: f32) -> String {
    if f >= 1000.0 {
        format!("{} kHz", f / 1000.0)
    } else {
        format!("{f} Hz")
    }
}

/// The mode spectrum: one vertical line per mode at its frequency (log axis from 20 Hz to
/// `f_max`), height its amplitude `|q_s|` in dB re the strongest mode (0 to -60 dB, labelled
/// on the left). Frequency labels sit at the bottom, kept inside the frame.
pub fn mode_spectrum(ui: &mut Ui, freqs_hz: &[f32], amplitudes: &[f32], f_max: f32, size: Vec2) {
    let (outer, painter) = frame(ui, size);
    let rect = Rect::from_min_max(
        Pos2::new(outer.left() + AXIS_W, outer.top() + 6.0),
        Pos2::new(outer.right() - 6.0, outer.bottom() - 16.0),
    );
    let f_min = 20.0f32;
    let f_max = f_max.max(2.0 * f_min);
    let x_of = |f: f32| {
        let t = (f.max(f_min).ln() - f_min.ln()) / (f_max.ln() - f_min.ln());
        rect.left() + t.clamp(0.0, 1.0) * rect.width()
    };
    let y_of = |db: f32| rect.top() + (-db / SPECTRUM_DB).clamp(0.0, 1.0) * rect.height();
    let grid = Stroke::new(1.0, Color32::from_gray(45));
    for db in [0.0f32, -20.0, -40.0, -60.0] {
        let y = y_of(db);
        painter.line_segment(
            [Pos2::new(rect.left(), y), Pos2::new(rect.right(), y)],
            grid,
        );
        painter.text(
            Pos2::new(rect.left() - 4.0, y),
            Align2::RIGHT_CENTER,
            format!("{db:.0} dB"),
            small_font(),
            Color32::from_gray(170),
        );
    }
    let mut last_right = f32::NEG_INFINITY;
    for f in [50.0f32, 100.0, 200.0, 500.0, 1e3, 2e3, 5e3, 1e4, 2e4] {
        if f > f_max {
            break;
        }
        let x = x_of(f);
        painter.line_segment(
            [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
            grid,
        );
        let label = freq_label(f);
        let w = 6.0 * label.len() as f32;
        // Centred under the tick, shifted inside the frame, skipped if it would overlap.
        let cx = x.clamp(outer.left() + 0.5 * w, outer.right() - 0.5 * w - 2.0);
        if cx - 0.5 * w < last_right + 4.0 {
            continue;
        }
        last_right = cx + 0.5 * w;
        painter.text(
            Pos2::new(cx, outer.bottom() - 2.0),
            Align2::CENTER_BOTTOM,
            label,
            small_font(),
            Color32::from_gray(170),
        );
    }
    let e_max = amplitudes
        .iter()
        .copied()
        .filter(|e| e.is_finite())
        .fold(0.0f32, f32::max);
    if e_max <= 0.0 {
        painter.text(
            rect.center(),
            Align2::CENTER_CENTER,
            "silent",
            small_font(),
            Color32::GRAY,
        );
        return;
    }
    for (&f, &e) in freqs_hz.iter().zip(amplitudes) {
        if !(e.is_finite() && e > 0.0 && f.is_finite()) {
            continue;
        }
        let db = 20.0 * (e / e_max).log10();
        if db < -SPECTRUM_DB {
            continue;
        }
        let x = x_of(f);
        painter.line_segment(
            [Pos2::new(x, rect.bottom()), Pos2::new(x, y_of(db))],
            Stroke::new(1.5, Color32::from_rgb(255, 200, 80)),
        );
    }
}

/// A displacement profile in metres (along a plate's diameter or diagonal, or a string's
/// length), scaled to its largest magnitude; `label` names the line.
pub fn displacement(ui: &mut Ui, u: &[f32], label: &str, size: Vec2) {
    let (rect, painter) = frame(ui, size);
    let scale = u
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f32, |m, v| m.max(v.abs()))
        .max(1e-12);
    let to_points = |v: &[f32]| -> Vec<Pos2> {
        let n = v.len().max(2) - 1;
        v.iter()
            .enumerate()
            .map(|(i, &y)| {
                let x = rect.left() + 4.0 + (rect.width() - 8.0) * i as f32 / n as f32;
                let y = rect.center().y - (y / scale).clamp(-1.0, 1.0) * (rect.height() * 0.45);
                Pos2::new(x, y)
            })
            .collect()
    };
    painter.line_segment(
        [
            Pos2::new(rect.left(), rect.center().y),
            Pos2::new(rect.right(), rect.center().y),
        ],
        Stroke::new(1.0, Color32::from_gray(50)),
    );
    if u.len() >= 2 {
        painter.line(
            to_points(u),
            Stroke::new(1.5, Color32::from_rgb(120, 200, 255)),
        );
    }
    let silent = scale <= 1e-12;
    painter.text(
        rect.left_top() + Vec2::new(4.0, 2.0),
        Align2::LEFT_TOP,
        if silent {
            format!("{label} · at rest")
        } else {
            format!(
                "{label} · full scale ±{}",
                crate::format::format_value(noether_core::engine::ParamId::PluckAmplitude, scale)
            )
        },
        small_font(),
        Color32::GRAY,
    );
}

/// CPU load bar: `load` is the audio thread's processing time over the real time of the audio
/// it produced (1.0 = one full core's budget; above that the audio drops out).
pub fn cpu_bar(ui: &mut Ui, load: f32, width: f32) -> egui::Response {
    let (response, painter) = ui.allocate_painter(Vec2::new(width, 16.0), Sense::hover());
    let rect = response.rect;
    painter.rect_filled(rect, 2.0, Color32::from_gray(18));
    let f = if load.is_finite() {
        load.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let colour = if load < 0.5 {
        Color32::from_rgb(90, 200, 90)
    } else if load < 0.85 {
        Color32::from_rgb(230, 190, 60)
    } else {
        Color32::from_rgb(230, 70, 60)
    };
    let bar = Rect::from_min_size(rect.min, Vec2::new(rect.width() * f, rect.height()));
    painter.rect_filled(bar, 2.0, colour);
    painter.text(
        rect.center(),
        Align2::CENTER_CENTER,
        format!("CPU {:.0} %", 100.0 * load),
        small_font(),
        Color32::WHITE,
    );
    response
}
