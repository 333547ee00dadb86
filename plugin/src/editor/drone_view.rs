//! The tanpura drone's view (GUI thread only): its strings, each drawn along its length as it
//! moves (one common scale, so a loud string looks loud) with its note, pitch and energy, and
//! under them the pluck cycle: one period as a bar, a tick per string where the pattern plucks
//! it, and the playhead where the drone is now. Takes the telemetry's plain [`DroneView`].

use egui::{Align2, Color32, FontId, Pos2, Rect, Stroke, Ui, Vec2};
use noether_core::engine::DroneView;

/// Height of the cycle bar (points).
const CYCLE_H: f32 = 34.0;
/// Width of the label column left of the strings (points).
const LABEL_W: f32 = 120.0;
/// Range of the energy shading, dB below the loudest string.
const ENERGY_DB: f32 = 60.0;

/// The name of a string sounding `ratio` times Sa.
pub fn note_name(ratio: f32) -> &'static str {
    let near = |r: f32| (ratio - r).abs() < 1e-3;
    if near(1.0) {
        "Sa"
    } else if near(0.5) {
        "low Sa"
    } else if near(0.75) {
        "Pa"
    } else if near(2.0 / 3.0) {
        "Ma"
    } else if near(15.0 / 16.0) {
        "Ni"
    } else {
        "string"
    }
}

/// Draws `view` in `size` points: the strings over the cycle bar.
pub fn drone(ui: &mut Ui, view: &DroneView, size: Vec2) {
    let (rect, painter) = super::plots::frame(ui, size);
    let font = super::plots::small_font();
    let n = usize::from(view.strings).min(view.energy.len());
    if n == 0 {
        return;
    }
    let strings_rect = Rect::from_min_max(
        rect.min + Vec2::new(0.0, 16.0),
        Pos2::new(rect.right(), rect.bottom() - CYCLE_H - 6.0),
    );
    painter.text(
        rect.left_top() + Vec2::new(4.0, 2.0),
        Align2::LEFT_TOP,
        format!(
            "tanpura drone · Sa {:.2} Hz · {}",
            view.sa_hz,
            if view.plucking {
                "plucking"
            } else {
                "ringing out"
            }
        ),
        font.clone(),
        Color32::GRAY,
    );
    // One scale for every string: the largest displacement of any.
    let scale = view.displacement[..n]
        .iter()
        .flatten()
        .copied()
        .filter(|v| v.is_finite())
        .fold(0.0f32, |m, v| m.max(v.abs()))
        .max(1e-12);
    let loudest = view.energy[..n].iter().copied().fold(0.0f32, f32::max);
    let row_h = strings_rect.height() / n as f32;
    let x0 = strings_rect.left() + LABEL_W;
    let x1 = strings_rect.right() - 6.0;
    for i in 0..n {
        let y = strings_rect.top() + (i as f32 + 0.5) * row_h;
        let e = view.energy[i];
        let db = if e > 0.0 && loudest > 0.0 {
            10.0 * (e / loudest).log10()
        } else {
            -ENERGY_DB
        };
        let level = ((db + ENERGY_DB) / ENERGY_DB).clamp(0.0, 1.0);
        let shade = (60.0 + 195.0 * level) as u8;
        let colour = Color32::from_rgb(shade / 2, shade, shade);
        let ratio = view.ratio[i];
        painter.text(
            Pos2::new(strings_rect.left() + 6.0, y),
            Align2::LEFT_CENTER,
            format!(
                "{} {:.1} Hz  {}",
                note_name(ratio),
                view.sa_hz * ratio,
                if e > 0.0 {
                    format!("{:+.0} dB", db)
                } else {
                    "at rest".to_string()
                }
            ),
            font.clone(),
            colour,
        );
        let u = &view.displacement[i];
        let last = (u.len() - 1).max(1) as f32;
        let points: Vec<Pos2> = u
            .iter()
            .enumerate()
            .map(|(k, &v)| {
                let x = x0 + (x1 - x0) * k as f32 / last;
                let dy = (v / scale).clamp(-1.0, 1.0) * 0.45 * row_h;
                Pos2::new(x, y - dy)
            })
            .collect();
        painter.line(points, Stroke::new(1.5, colour));
        // The bridge end, where the jivari is.
        painter.line_segment(
            [
                Pos2::new(x0 - 3.0, y - 0.3 * row_h),
                Pos2::new(x0 - 3.0, y + 0.3 * row_h),
            ],
            Stroke::new(2.0, Color32::from_gray(120)),
        );
    }
    cycle_bar(
        &painter,
        view,
        n,
        Rect::from_min_max(
            Pos2::new(x0, rect.bottom() - CYCLE_H - 2.0),
            Pos2::new(x1, rect.bottom() - 4.0),
        ),
        font,
    );
}

/// The cycle: one period as a bar, each string's onset as a tick with its name, the
/// playhead at the cycle's phase.
fn cycle_bar(painter: &egui::Painter, view: &DroneView, n: usize, bar: Rect, font: FontId) {
    painter.rect_filled(bar, 2.0, Color32::from_gray(30));
    let x_of = |f: f32| bar.left() + bar.width() * f.clamp(0.0, 1.0);
    for i in 0..n {
        let x = x_of(view.onsets[i]);
        painter.line_segment(
            [Pos2::new(x, bar.top()), Pos2::new(x, bar.bottom())],
            Stroke::new(2.0, Color32::from_rgb(120, 200, 255)),
        );
        painter.text(
            Pos2::new(x + 3.0, bar.top() + 2.0),
            Align2::LEFT_TOP,
            note_name(view.ratio[i]),
            font.clone(),
            Color32::GRAY,
        );
    }
    let x = x_of(view.cycle_phase);
    painter.line_segment(
        [
            Pos2::new(x, bar.top() - 2.0),
            Pos2::new(x, bar.bottom() + 2.0),
        ],
        Stroke::new(
            2.0,
            if view.plucking {
                Color32::from_rgb(255, 200, 80)
            } else {
                Color32::from_gray(110)
            },
        ),
    );
    painter.text(
        Pos2::new(bar.right() - 4.0, bar.bottom() - 2.0),
        Align2::RIGHT_BOTTOM,
        format!("cycle {:.2} s", view.cycle_seconds),
        font,
        Color32::GRAY,
    );
}

#[cfg(test)]
mod tests {
    use super::note_name;

    /// The standard tunings' strings get their names; anything else is a plain "string".
    #[test]
    fn strings_are_named_by_their_note() {
        let names: Vec<&str> = [0.75f32, 1.0, 0.5, 2.0 / 3.0, 15.0 / 16.0, 0.8]
            .iter()
            .map(|&r| note_name(r))
            .collect();
        assert_eq!(names, ["Pa", "Sa", "low Sa", "Ma", "Ni", "string"]);
    }
}
