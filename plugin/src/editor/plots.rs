//! Drawing of the live views (GUI thread only): per-voice energy bars, the mode spectrum, the
//! string or plate displacement and the CPU load bar. Each takes plain slices so it does not
//! depend on how the telemetry reached the GUI.

use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, StrokeKind, Ui, Vec2};

/// Colours of the four energy terms, in the order of [`ENERGY_LABELS`].
pub const ENERGY_COLOURS: [Color32; 4] = [
    Color32::from_rgb(90, 170, 255),
    Color32::from_rgb(120, 220, 120),
    Color32::from_rgb(255, 170, 60),
    Color32::from_rgb(235, 235, 235),
];

/// Labels of the four energy terms of a voice.
pub const ENERGY_LABELS: [&str; 4] = ["kinetic", "linear", "nonlin./contact", "total"];

/// Lower end of the energy meters, in dB relative to the loudest total shown (energies span
/// many decades while a note decays; 80 dB shows the whole audible part of a decay).
const ENERGY_RANGE_DB: f32 = 80.0;

fn frame(ui: &mut Ui, size: Vec2) -> (Rect, egui::Painter) {
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

fn small_font() -> FontId {
    FontId::proportional(11.0)
}

/// Maps an energy to a bar fraction in [0, 1] on a dB scale below `reference`.
fn energy_fraction(e: f32, reference: f32) -> f32 {
    // Also rejects NaN.
    if !(e.is_finite() && e > 0.0 && reference.is_finite() && reference > 0.0) {
        return 0.0;
    }
    let db = 10.0 * (e / reference).log10();
    ((db + ENERGY_RANGE_DB) / ENERGY_RANGE_DB).clamp(0.0, 1.0)
}

/// Per-voice energy meters: for each voice, four bars (kinetic, linear potential, nonlinear or
/// contact potential, total), in dB below the largest total among the voices. `voices` holds
/// `(label, [kinetic, linear, nonlinear, total])` in joules.
pub fn energy_meters(ui: &mut Ui, voices: &[(String, [f32; 4])], width: f32) {
    let row_h = 30.0;
    let h = 18.0 + row_h * voices.len().max(1) as f32;
    let (rect, painter) = frame(ui, Vec2::new(width, h));
    let reference =
        voices
            .iter()
            .map(|(_, e)| e[3])
            .fold(0.0f32, |m, e| if e.is_finite() { m.max(e) } else { m });
    let mut x = rect.left() + 70.0;
    for (label, colour) in ENERGY_LABELS.iter().zip(ENERGY_COLOURS) {
        painter.text(
            Pos2::new(x, rect.top() + 3.0),
            Align2::LEFT_TOP,
            label,
            small_font(),
            colour,
        );
        x += (width - 80.0) / 4.0;
    }
    if voices.is_empty() {
        painter.text(
            rect.center() + Vec2::new(0.0, 8.0),
            Align2::CENTER_CENTER,
            "no voice sounding",
            small_font(),
            Color32::GRAY,
        );
        return;
    }
    for (row, (label, e)) in voices.iter().enumerate() {
        let top = rect.top() + 18.0 + row_h * row as f32;
        painter.text(
            Pos2::new(rect.left() + 6.0, top + row_h * 0.5),
            Align2::LEFT_CENTER,
            label,
            small_font(),
            Color32::LIGHT_GRAY,
        );
        let bar_w = (width - 80.0) / 4.0 - 6.0;
        for (k, colour) in ENERGY_COLOURS.iter().enumerate() {
            let left = rect.left() + 70.0 + k as f32 * (bar_w + 6.0);
            let full =
                Rect::from_min_size(Pos2::new(left, top + 6.0), Vec2::new(bar_w, row_h - 12.0));
            painter.rect_filled(full, 1.0, Color32::from_gray(35));
            let f = energy_fraction(e[k], reference);
            let bar = Rect::from_min_size(full.min, Vec2::new(bar_w * f, full.height()));
            painter.rect_filled(bar, 1.0, *colour);
            painter.text(
                full.right_center() - Vec2::new(3.0, 0.0),
                Align2::RIGHT_CENTER,
                format!("{:.2e} J", e[k]),
                small_font(),
                Color32::from_gray(200),
            );
        }
    }
}

/// The mode spectrum: one vertical line per mode at its frequency (log axis from 20 Hz to
/// `f_max`), height its amplitude `|q_s|` in dB below the strongest mode (60 dB shown).
pub fn mode_spectrum(ui: &mut Ui, freqs_hz: &[f32], amplitudes: &[f32], f_max: f32, size: Vec2) {
    let (rect, painter) = frame(ui, size);
    let f_min = 20.0f32;
    let f_max = f_max.max(2.0 * f_min);
    let x_of = |f: f32| {
        let t = (f.max(f_min).ln() - f_min.ln()) / (f_max.ln() - f_min.ln());
        rect.left() + 4.0 + t.clamp(0.0, 1.0) * (rect.width() - 8.0)
    };
    for f in [100.0f32, 1_000.0, 10_000.0] {
        if f < f_max {
            let x = x_of(f);
            painter.line_segment(
                [Pos2::new(x, rect.top()), Pos2::new(x, rect.bottom())],
                Stroke::new(1.0, Color32::from_gray(45)),
            );
            let label = if f >= 1000.0 {
                format!("{} kHz", f / 1000.0)
            } else {
                format!("{f} Hz")
            };
            painter.text(
                Pos2::new(x + 2.0, rect.top() + 2.0),
                Align2::LEFT_TOP,
                label,
                small_font(),
                Color32::GRAY,
            );
        }
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
    let range_db = 60.0f32;
    for (&f, &e) in freqs_hz.iter().zip(amplitudes) {
        if !(e.is_finite() && e > 0.0 && f.is_finite()) {
            continue;
        }
        let db = 20.0 * (e / e_max).log10();
        let t = ((db + range_db) / range_db).clamp(0.0, 1.0);
        if t <= 0.0 {
            continue;
        }
        let x = x_of(f);
        let y = rect.bottom() - 2.0 - t * (rect.height() - 16.0);
        painter.line_segment(
            [Pos2::new(x, rect.bottom() - 2.0), Pos2::new(x, y)],
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
    painter.text(
        rect.left_top() + Vec2::new(4.0, 2.0),
        Align2::LEFT_TOP,
        format!("{label}, full scale {scale:.2e} m"),
        small_font(),
        Color32::GRAY,
    );
}

/// CPU load bar: `load` is the audio thread's processing time over the real time of the audio
/// it produced (1.0 = one full core's budget; above that the audio drops out).
pub fn cpu_bar(ui: &mut Ui, load: f32, width: f32) {
    let (rect, painter) = frame(ui, Vec2::new(width, 16.0));
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
}
