//! The on-screen keyboard and the computer-keyboard mapping (GUI thread only).
//!
//! Mouse: pressing a key plays it with a velocity set by the height of the click (top of the
//! key soft, bottom loud); dragging across keys glides from note to note (a note-off for the
//! old key, a note-on for the new one); releasing the button anywhere, or leaving the
//! keyboard while dragging, sends the note-off, so no note sticks. Keys sounding in the engine
//! (from the telemetry's voice keys) are highlighted, held ones brighter than released ones.
//!
//! Computer keyboard (when no text field has the focus): the usual DAW mapping, A W S E D F T
//! G Y H U J K play C to the next C, Z / X shift that octave down / up, C / V lower / raise
//! the velocity. Every note goes to the engine through the GUI command queue
//! (`GuiCommand::Event`), like MIDI input.

use crate::format::note_name;
use egui::{Align2, Color32, FontId, Key, Pos2, Rect, Sense, Stroke, StrokeKind, Ui, Vec2};
use noether_core::engine::EventKind;

/// Lowest and highest key the on-screen keyboard can show (C0 and C8).
const LOWEST: i32 = 12;
const HIGHEST: i32 = 108;

/// Semitone offsets from C of the computer keys, in the usual DAW layout.
pub const COMPUTER_KEYS: [(Key, i32); 13] = [
    (Key::A, 0),
    (Key::W, 1),
    (Key::S, 2),
    (Key::E, 3),
    (Key::D, 4),
    (Key::F, 5),
    (Key::T, 6),
    (Key::G, 7),
    (Key::Y, 8),
    (Key::H, 9),
    (Key::U, 10),
    (Key::J, 11),
    (Key::K, 12),
];

/// Whether semitone `s` (0..12 from C) is a black key.
fn is_black(s: i32) -> bool {
    matches!(s.rem_euclid(12), 1 | 3 | 6 | 8 | 10)
}

/// Geometry of the keyboard drawn in `rect`: `octaves` octaves from the C key `first`.
#[derive(Debug, Clone, Copy)]
pub struct KeyLayout {
    /// Where the keys are drawn (points).
    pub rect: Rect,
    /// MIDI key of the lowest C shown.
    pub first: i32,
    /// Octaves shown (plus the top C).
    pub octaves: i32,
}

impl KeyLayout {
    fn white_width(&self) -> f32 {
        self.rect.width() / (7 * self.octaves + 1) as f32
    }

    /// The rectangle of `key` and whether it is black; `None` if it is not shown.
    pub fn key_rect(&self, key: i32) -> Option<(Rect, bool)> {
        let rel = key - self.first;
        if !(0..=12 * self.octaves).contains(&rel) {
            return None;
        }
        let w = self.white_width();
        let octave = rel.div_euclid(12);
        let s = rel.rem_euclid(12);
        // White keys before this one in its octave (C D E F G A B).
        let whites_before = [0, 1, 1, 2, 2, 3, 4, 4, 5, 5, 6, 6][s as usize];
        let x = self.rect.left() + (7 * octave + whites_before) as f32 * w;
        if is_black(s) {
            let bw = 0.6 * w;
            Some((
                Rect::from_min_size(
                    Pos2::new(x - 0.5 * bw, self.rect.top()),
                    Vec2::new(bw, 0.62 * self.rect.height()),
                ),
                true,
            ))
        } else {
            Some((
                Rect::from_min_size(
                    Pos2::new(x, self.rect.top()),
                    Vec2::new(w, self.rect.height()),
                ),
                false,
            ))
        }
    }

    /// The key under `pos` (black keys first, they lie on top) and the velocity of a press
    /// there: 0.1 at the top of the key to 1.0 at its bottom, linear in the height.
    pub fn key_at(&self, pos: Pos2) -> Option<(u8, f32)> {
        if !self.rect.contains(pos) {
            return None;
        }
        let keys = self.first..=self.first + 12 * self.octaves;
        let hit = keys
            .clone()
            .filter(|&k| is_black(k))
            .chain(keys.filter(|&k| !is_black(k)))
            .find_map(|k| {
                let (r, _) = self.key_rect(k)?;
                r.contains(pos).then_some((k, r))
            })?;
        let (k, r) = hit;
        let t = ((pos.y - r.top()) / r.height()).clamp(0.0, 1.0);
        Some((k.clamp(0, 127) as u8, 0.1 + 0.9 * t))
    }
}

/// The note the mouse plays, and the events that follow from the pointer's state.
#[derive(Debug, Default, Clone, Copy, PartialEq)]
pub struct MouseNote {
    /// Key sounding from the mouse, if any.
    pub key: Option<u8>,
}

impl MouseNote {
    /// Updates from one frame: `down` whether the button is held on the keyboard (a press that
    /// started on it), `target` the key under the pointer with its velocity. Sends a note-off
    /// for a key left or released and a note-on for a new key.
    pub fn update(
        &mut self,
        down: bool,
        target: Option<(u8, f32)>,
        send: &mut dyn FnMut(EventKind),
    ) {
        let want = if down { target } else { None };
        if want.map(|(k, _)| k) == self.key {
            return;
        }
        if let Some(key) = self.key.take() {
            send(EventKind::NoteOff { key });
        }
        if let Some((key, velocity)) = want {
            send(EventKind::NoteOn { key, velocity });
            self.key = Some(key);
        }
    }
}

/// State of the keyboard between frames.
#[derive(Debug, Clone)]
pub struct Keyboard {
    /// MIDI key of the lowest C shown on screen.
    pub first: i32,
    /// The mouse's note.
    pub mouse: MouseNote,
    /// MIDI key of the C the computer key A plays.
    pub computer_c: i32,
    /// Velocity of computer-key notes (0..1).
    pub computer_velocity: f32,
    /// Key each computer key is playing (index as in [`COMPUTER_KEYS`]).
    computer_held: [Option<u8>; 13],
}

impl Default for Keyboard {
    fn default() -> Self {
        Self {
            first: 36,
            mouse: MouseNote::default(),
            computer_c: 60,
            computer_velocity: 0.8,
            computer_held: [None; 13],
        }
    }
}

/// Colours of keys sounding in the engine (held, released) and played from the editor.
const HELD: Color32 = Color32::from_rgb(255, 170, 60);
const RELEASED: Color32 = Color32::from_rgb(150, 110, 60);
const PLAYED: Color32 = Color32::from_rgb(90, 170, 255);

impl Keyboard {
    /// Keys the editor itself holds (mouse and computer keys).
    fn editor_keys(&self) -> impl Iterator<Item = u8> + '_ {
        self.mouse
            .key
            .into_iter()
            .chain(self.computer_held.iter().flatten().copied())
    }

    /// Reads the computer keys of this frame (unless a text field has the focus) and sends
    /// their notes. A lost window focus releases every computer key.
    pub fn computer_keys(&mut self, ui: &Ui, send: &mut dyn FnMut(EventKind)) {
        let typing = ui.ctx().text_edit_focused();
        let events = ui.input(|i| i.events.clone());
        for e in events {
            match e {
                egui::Event::WindowFocused(false) => self.release_computer_keys(send),
                egui::Event::Key {
                    key,
                    pressed,
                    repeat: false,
                    modifiers,
                    ..
                } if !typing && !modifiers.ctrl && !modifiers.command && !modifiers.alt => {
                    self.computer_key(key, pressed, send);
                }
                _ => {}
            }
        }
    }

    fn computer_key(&mut self, key: Key, pressed: bool, send: &mut dyn FnMut(EventKind)) {
        if let Some(i) = COMPUTER_KEYS.iter().position(|&(k, _)| k == key) {
            if pressed && self.computer_held[i].is_none() {
                let note = (self.computer_c + COMPUTER_KEYS[i].1).clamp(0, 127) as u8;
                send(EventKind::NoteOn {
                    key: note,
                    velocity: self.computer_velocity,
                });
                self.computer_held[i] = Some(note);
            } else if !pressed {
                if let Some(note) = self.computer_held[i].take() {
                    send(EventKind::NoteOff { key: note });
                }
            }
            return;
        }
        if !pressed {
            return;
        }
        match key {
            Key::Z => self.computer_c = (self.computer_c - 12).max(LOWEST),
            Key::X => self.computer_c = (self.computer_c + 12).min(HIGHEST - 12),
            Key::C => self.computer_velocity = (self.computer_velocity - 0.1).max(0.1),
            Key::V => self.computer_velocity = (self.computer_velocity + 0.1).min(1.0),
            _ => {}
        }
    }

    /// Sends a note-off for every computer key held.
    pub fn release_computer_keys(&mut self, send: &mut dyn FnMut(EventKind)) {
        for held in &mut self.computer_held {
            if let Some(key) = held.take() {
                send(EventKind::NoteOff { key });
            }
        }
    }

    /// Draws the octave buttons, the help line and the keys in the full width of `ui`
    /// (`height` points for the keys); `sounding` lists `(key, held)` of the engine's voices.
    /// Returns where the keys were drawn.
    pub fn show(
        &mut self,
        ui: &mut Ui,
        height: f32,
        sounding: &[(u8, bool)],
        send: &mut dyn FnMut(EventKind),
    ) -> KeyLayout {
        let width = ui.available_width();
        let octaves = ((width / (7.0 * 16.0)) as i32).clamp(2, 7);
        self.first = self.first.clamp(LOWEST, HIGHEST - 12 * octaves);
        ui.horizontal(|ui| {
            if ui.small_button("octave −").clicked() {
                self.first = (self.first - 12).max(LOWEST);
            }
            if ui.small_button("octave +").clicked() {
                self.first = (self.first + 12).min(HIGHEST - 12 * octaves);
            }
            ui.label(
                egui::RichText::new(format!(
                    "{}–{} · click height = velocity (top soft, bottom loud) · computer keys A W S E D F T G Y H U J K from {} (Z/X octave), velocity {:.0} % (C/V)",
                    note_name(self.first),
                    note_name(self.first + 12 * octaves),
                    note_name(self.computer_c),
                    100.0 * self.computer_velocity
                ))
                .small(),
            );
        });
        let (response, painter) =
            ui.allocate_painter(Vec2::new(width, height), Sense::click_and_drag());
        let layout = KeyLayout {
            rect: response.rect,
            first: self.first,
            octaves,
        };
        let down = response.is_pointer_button_down_on();
        let target = ui
            .input(|i| i.pointer.interact_pos())
            .and_then(|p| layout.key_at(p));
        self.mouse.update(down, target, send);

        let colour_of = |k: i32| -> Option<Color32> {
            let k8 = k as u8;
            if self.editor_keys().any(|e| e == k8) {
                Some(PLAYED)
            } else if sounding.iter().any(|&(s, held)| s == k8 && held) {
                Some(HELD)
            } else if sounding.iter().any(|&(s, _)| s == k8) {
                Some(RELEASED)
            } else {
                None
            }
        };
        let keys = layout.first..=layout.first + 12 * octaves;
        for black in [false, true] {
            for k in keys.clone().filter(|&k| is_black(k) == black) {
                let Some((r, _)) = layout.key_rect(k) else {
                    continue;
                };
                let base = if black {
                    Color32::from_gray(25)
                } else {
                    Color32::from_gray(230)
                };
                painter.rect_filled(r, 2.0, colour_of(k).unwrap_or(base));
                painter.rect_stroke(
                    r,
                    2.0,
                    Stroke::new(1.0, Color32::from_gray(70)),
                    StrokeKind::Inside,
                );
                if k.rem_euclid(12) == 0 {
                    painter.text(
                        Pos2::new(r.center().x, r.bottom() - 3.0),
                        Align2::CENTER_BOTTOM,
                        note_name(k),
                        FontId::proportional(10.0),
                        Color32::from_gray(40),
                    );
                }
            }
        }
        layout
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::{Event, Modifiers, PointerButton, RawInput};

    fn layout() -> KeyLayout {
        KeyLayout {
            rect: Rect::from_min_size(Pos2::new(0.0, 100.0), Vec2::new(290.0, 80.0)),
            first: 48,
            octaves: 2,
        }
    }

    /// Velocity grows linearly with the height of the click on the key: 0.1 at its top, 1.0
    /// at its bottom (exact up to f32 rounding, 1e-5).
    #[test]
    fn velocity_from_click_height() {
        let l = layout();
        // Low on the first white key (below the black keys): C3.
        let w = l.rect.width() / 15.0;
        let (k, v_top) = l.key_at(Pos2::new(0.5 * w, 100.0)).unwrap();
        assert_eq!(k, 48);
        assert!((v_top - 0.1).abs() < 1e-5, "{v_top}");
        let (_, v_mid) = l.key_at(Pos2::new(0.5 * w, 140.0)).unwrap();
        assert!((v_mid - 0.55).abs() < 1e-5, "{v_mid}");
        let (_, v_bottom) = l.key_at(Pos2::new(0.5 * w, 180.0)).unwrap();
        assert!((v_bottom - 1.0).abs() < 1e-5, "{v_bottom}");
        // The black key C#3 lies over the boundary of C3 and D3.
        let (k, _) = l.key_at(Pos2::new(w, 110.0)).unwrap();
        assert_eq!(k, 49);
        // Below the black key, the same x is a white key.
        let (k, _) = l.key_at(Pos2::new(w + 1.0, 175.0)).unwrap();
        assert_eq!(k, 50);
        assert_eq!(l.key_at(Pos2::new(10.0, 50.0)), None);
    }

    /// Runs the keyboard for one frame with `events`, collecting the note events sent.
    fn frame(ctx: &egui::Context, kb: &mut Keyboard, t: f64, events: Vec<Event>) -> Vec<EventKind> {
        frame_layout(ctx, kb, t, events).0
    }

    /// As [`frame`], also returning the keys' layout.
    fn frame_layout(
        ctx: &egui::Context,
        kb: &mut Keyboard,
        t: f64,
        events: Vec<Event>,
    ) -> (Vec<EventKind>, KeyLayout) {
        let input = RawInput {
            time: Some(t),
            screen_rect: Some(Rect::from_min_size(Pos2::ZERO, Vec2::new(600.0, 200.0))),
            events,
            ..RawInput::default()
        };
        let mut sent = vec![];
        let mut layout = None;
        let mut out = ctx.run_ui(input, |ui| {
            let mut send = |e| sent.push(e);
            kb.computer_keys(ui, &mut send);
            layout = Some(kb.show(ui, 100.0, &[], &mut send));
        });
        // Font textures were created; nothing uploads them here.
        out.textures_delta.clear();
        (sent, layout.unwrap())
    }

    /// Two points low on white keys (loud) a few keys apart.
    fn two_keys(l: &KeyLayout) -> (Pos2, Pos2) {
        let y = l.rect.bottom() - 5.0;
        let w = l.rect.width() / (7 * l.octaves + 1) as f32;
        (
            Pos2::new(l.rect.left() + 0.5 * w, y),
            Pos2::new(l.rect.left() + 4.5 * w, y),
        )
    }

    fn button(pos: Pos2, pressed: bool) -> Event {
        Event::PointerButton {
            pos,
            button: PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        }
    }

    /// Press, hold for 2 s, glide to another key, release outside the keyboard: one note-on
    /// per key, a note-off for the first key at the glide and for the second at the release,
    /// nothing left sounding. A broken keyboard that ignored the release would fail the last
    /// check (the mouse note would stay set); a click-only keyboard fails the first (egui lets
    /// go of a click-only press after its 0.8 s `max_click_duration`, so the note-off came
    /// while the button was still held: checked by hand with `Sense::click()`).
    #[test]
    fn press_glide_release_sends_matching_note_offs() {
        let ctx = egui::Context::default();
        let mut kb = Keyboard::default();
        let (_, l) = frame_layout(&ctx, &mut kb, 0.0, vec![]);
        let (a, b) = two_keys(&l);
        let mut all = frame(
            &ctx,
            &mut kb,
            0.1,
            vec![Event::PointerMoved(a), button(a, true)],
        );
        for i in 1..60 {
            all.extend(frame(&ctx, &mut kb, 0.1 + f64::from(i) / 30.0, vec![]));
        }
        assert_eq!(all.len(), 1, "{all:?}");
        let EventKind::NoteOn { key: first, .. } = all[0] else {
            panic!("{all:?}")
        };
        let glide = frame(&ctx, &mut kb, 2.2, vec![Event::PointerMoved(b)]);
        assert!(
            matches!(glide[..], [EventKind::NoteOff { key }, EventKind::NoteOn { key: k2, .. }] if key == first && k2 != first),
            "{glide:?}"
        );
        let out = Pos2::new(b.x, l.rect.top() - 15.0);
        let _ = frame(&ctx, &mut kb, 2.3, vec![Event::PointerMoved(out)]);
        let release = frame(&ctx, &mut kb, 2.4, vec![button(out, false)]);
        assert!(release.is_empty() || matches!(release[..], [EventKind::NoteOff { .. }]));
        assert_eq!(kb.mouse.key, None, "a note is left sounding");
    }

    /// Releasing the button anywhere ends the note (the press that started on a key).
    #[test]
    fn release_anywhere_sends_note_off() {
        let ctx = egui::Context::default();
        let mut kb = Keyboard::default();
        let (_, l) = frame_layout(&ctx, &mut kb, 0.0, vec![]);
        let (a, _) = two_keys(&l);
        let on = frame(
            &ctx,
            &mut kb,
            0.1,
            vec![Event::PointerMoved(a), button(a, true)],
        );
        let EventKind::NoteOn { key, velocity } = on[0] else {
            panic!("{on:?}")
        };
        assert!(velocity > 0.8, "a low click is loud: {velocity}");
        let off = frame(&ctx, &mut kb, 0.5, vec![button(a, false)]);
        assert_eq!(off, vec![EventKind::NoteOff { key }]);
    }

    /// Computer keys: A plays C4, its release the note-off, X shifts the octave, a held key
    /// keeps its own note through an octave change.
    #[test]
    fn computer_keys_map_like_a_daw() {
        let ctx = egui::Context::default();
        let mut kb = Keyboard::default();
        let key = |key, pressed| Event::Key {
            key,
            physical_key: None,
            pressed,
            repeat: false,
            modifiers: Modifiers::NONE,
        };
        let on = frame(&ctx, &mut kb, 0.0, vec![key(Key::A, true)]);
        assert_eq!(
            on,
            vec![EventKind::NoteOn {
                key: 60,
                velocity: 0.8
            }]
        );
        let _ = frame(
            &ctx,
            &mut kb,
            0.1,
            vec![key(Key::X, true), key(Key::X, false)],
        );
        let off = frame(&ctx, &mut kb, 0.2, vec![key(Key::A, false)]);
        assert_eq!(off, vec![EventKind::NoteOff { key: 60 }]);
        let on = frame(&ctx, &mut kb, 0.3, vec![key(Key::K, true)]);
        assert_eq!(
            on,
            vec![EventKind::NoteOn {
                key: 84,
                velocity: 0.8
            }]
        );
        let off = frame(&ctx, &mut kb, 0.4, vec![Event::WindowFocused(false)]);
        assert_eq!(off, vec![EventKind::NoteOff { key: 84 }]);
    }
}
