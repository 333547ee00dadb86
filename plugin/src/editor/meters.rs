//! Per-voice energy meters on one shared scale (GUI thread only): the energy of every voice
//! in dB re 1 J (absolute, so a quiet voice reads quiet and two meters compare directly),
//! from -120 dB (1 pJ) to 0 dB (1 J), with a strip chart of the last three seconds so a decay
//! reads as a slope. Fixed-height rows (at most [`ROWS`] voices listed, the rest counted) so
//! the column below does not move as voices start and stop.

use crate::format::note_name;
use egui::{Align2, Color32, FontId, Pos2, Rect, Sense, Stroke, StrokeKind, Ui, Vec2};
use noether_core::engine::{Telemetry, MAX_VOICES};
use std::collections::VecDeque;

/// Bottom and top of the shared scale, dB re 1 J.
pub const DB_MIN: f32 = -120.0;
/// Top of the shared scale, dB re 1 J.
pub const DB_MAX: f32 = 0.0;
/// Voice rows listed (fixed, so the block keeps its height).
pub const ROWS: usize = 4;
/// Seconds of history in the strip chart.
const HISTORY_S: f64 = 3.0;
const ROW_H: f32 = 18.0;
/// The colour of the band-above tick on an energy bar.
const ABOVE_TICK: Color32 = Color32::from_rgb(80, 220, 255);
const LABEL_W: f32 = 96.0;
const CHART_H: f32 = 64.0;

/// Colour of voice slot `i` (bars and chart lines).
fn slot_colour(i: usize) -> Color32 {
    const C: [Color32; 6] = [
        Color32::from_rgb(90, 170, 255),
        Color32::from_rgb(255, 170, 60),
        Color32::from_rgb(120, 220, 120),
        Color32::from_rgb(230, 110, 200),
        Color32::from_rgb(240, 230, 90),
        Color32::from_rgb(110, 220, 220),
    ];
    C[i % C.len()]
}

/// Energy `e` in J as dB re 1 J, clamped to the scale (NaN and ≤ 0 read as the bottom).
pub fn energy_db(e: f64) -> f32 {
    if e.is_finite() && e > 0.0 {
        ((10.0 * e.log10()) as f32).clamp(DB_MIN, DB_MAX)
    } else {
        DB_MIN
    }
}

/// Fraction of the scale for `db`.
fn fraction(db: f32) -> f32 {
    ((db - DB_MIN) / (DB_MAX - DB_MIN)).clamp(0.0, 1.0)
}

/// The meters' history: per telemetry frame, its time and the total energy (dB) of each slot
/// (`None`: silent).
#[derive(Default)]
pub struct EnergyHistory {
    samples: VecDeque<(f64, [Option<f32>; MAX_VOICES])>,
    last_frame: u64,
}

impl EnergyHistory {
    /// Appends the frame `t` if it is new (time `now`, s) and forgets samples older than the
    /// chart's span.
    pub fn push(&mut self, t: &Telemetry, now: f64) {
        if t.frame == self.last_frame {
            return;
        }
        self.last_frame = t.frame;
        let mut row = [None; MAX_VOICES];
        for (r, v) in row.iter_mut().zip(&t.voices) {
            if v.active {
                *r = Some(energy_db(v.energy.total()));
            }
        }
        self.samples.push_back((now, row));
        while self
            .samples
            .front()
            .is_some_and(|(s, _)| now - s > HISTORY_S)
        {
            self.samples.pop_front();
        }
    }
}

fn scale_x(rect: Rect, db: f32) -> f32 {
    rect.left() + fraction(db) * rect.width()
}

/// Draws the meters for `t` and the strip chart from `history`, `width` points wide.
pub fn energy_meters(ui: &mut Ui, t: &Telemetry, history: &EnergyHistory, width: f32) {
    let font = FontId::proportional(11.0);
    let h = 16.0 + ROW_H * (ROWS as f32 + 1.0) + CHART_H + 6.0;
    let (response, painter) = ui.allocate_painter(Vec2::new(width, h), Sense::hover());
    let rect = response.rect;
    painter.rect_filled(rect, 2.0, Color32::from_gray(18));
    let bars = Rect::from_min_max(
        Pos2::new(rect.left() + LABEL_W, rect.top() + 16.0),
        Pos2::new(rect.right() - 8.0, rect.top() + 16.0 + ROW_H * ROWS as f32),
    );
    // The scale: dB re 1 J, ticks every 20 dB.
    for db in (0..=6).map(|i| DB_MIN + 20.0 * i as f32) {
        let x = scale_x(bars, db);
        painter.line_segment(
            [Pos2::new(x, bars.top()), Pos2::new(x, rect.bottom() - 4.0)],
            Stroke::new(1.0, Color32::from_gray(40)),
        );
        let align = if db >= DB_MAX {
            Align2::RIGHT_TOP
        } else {
            Align2::CENTER_TOP
        };
        painter.text(
            Pos2::new(x, rect.top() + 2.0),
            align,
            format!("{db:.0}"),
            font.clone(),
            Color32::from_gray(170),
        );
    }
    painter.text(
        Pos2::new(rect.left() + 6.0, rect.top() + 2.0),
        Align2::LEFT_TOP,
        "dB re 1 J",
        font.clone(),
        Color32::from_gray(170),
    );
    let active: Vec<usize> = (0..MAX_VOICES).filter(|&i| t.voices[i].active).collect();
    for (row, &i) in active.iter().take(ROWS).enumerate() {
        let v = &t.voices[i];
        let top = bars.top() + ROW_H * row as f32;
        painter.text(
            Pos2::new(rect.left() + 6.0, top + 0.5 * ROW_H),
            Align2::LEFT_CENTER,
            format!(
                "{} {}",
                note_name(i32::from(v.key)),
                match (v.held, v.latched) {
                    (true, _) => "held",
                    (false, true) => "latched",
                    (false, false) => "released",
                }
            ),
            font.clone(),
            slot_colour(i),
        );
        let full = Rect::from_min_max(
            Pos2::new(bars.left(), top + 3.0),
            Pos2::new(bars.right(), top + ROW_H - 3.0),
        );
        painter.rect_filled(full, 1.0, Color32::from_gray(35));
        let db = energy_db(v.energy.total());
        let bar = Rect::from_min_max(full.min, Pos2::new(scale_x(bars, db), full.bottom()));
        painter.rect_filled(bar, 1.0, slot_colour(i).gamma_multiply(0.55));
        // What the voice simulates for its note, and its level, right-aligned over the bar.
        let m = v.model;
        let in_plane = if m.n_psi > 0 {
            format!(" + {} in-plane", m.n_psi)
        } else {
            String::new()
        };
        // The band above the simulation (its modes run to 20 kHz or 0.45 of the host rate).
        let band_above = if m.above_modes > 0 {
            format!(", {} above", m.above_modes)
        } else {
            String::new()
        };
        // On a dark plate of its own, so it reads over any bar colour.
        let galley = painter.layout_no_wrap(
            format!(
                "{} modes{in_plane} to {:.1} kHz{band_above} · {db:.0} dB",
                m.n_phi,
                m.top_mode_hz / 1000.0
            ),
            font.clone(),
            Color32::WHITE,
        );
        let text = Align2::RIGHT_CENTER
            .anchor_size(full.right_center() - Vec2::new(3.0, 0.0), galley.size());
        painter.rect_filled(text.expand(2.0), 2.0, Color32::from_black_alpha(200));
        painter.galley(text.min, galley, Color32::WHITE);
        // The nonlinear (in-plane or contact) share as a tick on the same scale, over the label
        // (the label's plate would hide it at high levels).
        let nl = energy_db(v.energy.nonlinear);
        if nl > DB_MIN {
            let x = scale_x(bars, nl);
            painter.line_segment(
                [
                    Pos2::new(x, full.top() - 2.0),
                    Pos2::new(x, full.bottom() + 2.0),
                ],
                Stroke::new(2.0, Color32::WHITE),
            );
        }
        // The band above the simulation's share (a plate whose closure passes energy on), as a
        // cyan tick.
        let above = energy_db(v.energy.above);
        if above > DB_MIN {
            let x = scale_x(bars, above);
            painter.line_segment(
                [
                    Pos2::new(x, full.top() - 2.0),
                    Pos2::new(x, full.bottom() + 2.0),
                ],
                Stroke::new(2.0, ABOVE_TICK),
            );
        }
    }
    let footer = bars.bottom() + 0.5 * ROW_H;
    let footer_text = match active.len() {
        0 => "no voice sounding".to_string(),
        n if n > ROWS => format!(
            "+{} more · white tick: nonlinear / contact energy · cyan: band above",
            n - ROWS
        ),
        _ => "bar: total energy · white tick: nonlinear / contact energy · cyan: band above"
            .to_string(),
    };
    painter.text(
        Pos2::new(rect.left() + 6.0, footer),
        Align2::LEFT_CENTER,
        footer_text,
        font.clone(),
        Color32::from_gray(170),
    );
    // Strip chart: time runs left to right over the last HISTORY_S seconds; energy upwards,
    // 0 dB at the top, -120 dB at the bottom.
    let chart = Rect::from_min_max(
        Pos2::new(bars.left(), bars.bottom() + ROW_H),
        Pos2::new(bars.right(), rect.bottom() - 4.0),
    );
    painter.rect_stroke(
        chart,
        1.0,
        Stroke::new(1.0, Color32::from_gray(60)),
        StrokeKind::Inside,
    );
    painter.text(
        Pos2::new(rect.left() + 6.0, chart.center().y),
        Align2::LEFT_CENTER,
        format!("last {HISTORY_S:.0} s\n0 to -120 dB"),
        font,
        Color32::from_gray(170),
    );
    let Some(&(now, _)) = history.samples.back() else {
        return;
    };
    for slot in 0..MAX_VOICES {
        let points: Vec<Pos2> = history
            .samples
            .iter()
            .filter_map(|(ts, row)| {
                let db = row[slot]?;
                let x = chart.right() - ((now - ts) / HISTORY_S) as f32 * chart.width();
                let y = chart.top() + (1.0 - fraction(db)) * chart.height();
                Some(Pos2::new(x, y))
            })
            .collect();
        if points.len() >= 2 {
            painter.line(points, Stroke::new(1.5, slot_colour(slot)));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One scale for every voice: 4e-8 J and 1e-2 J land at -74 and -20 dB (not both full).
    #[test]
    fn shared_absolute_scale() {
        assert!((energy_db(4e-8) - (-73.98)).abs() < 0.01);
        assert!((energy_db(1e-2) - (-20.0)).abs() < 1e-4);
        assert!(fraction(energy_db(4e-8)) < 0.4);
        assert!(fraction(energy_db(1e-2)) > 0.8);
        assert_eq!(energy_db(0.0), DB_MIN);
        assert_eq!(energy_db(f64::NAN), DB_MIN);
        assert_eq!(energy_db(10.0), DB_MAX);
    }
}
