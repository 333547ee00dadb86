//! The egui editor (GUI thread only): a top bar with the preset menu, CPU load and the model
//! state (a clear "rebuilding model" banner while the worker builds a voice bank), parameter
//! panels on the left, and live views on the right: per-voice energy meters, the mode spectrum
//! and the displacement of the watched voice.
//!
//! Data flow: parameters go through nice-plug's `ParamSetter` (so hosts record automation);
//! telemetry frames come from the engine through [`EngineLink`]; preset loads set every
//! parameter through the setter as one gesture per parameter.

mod panels;
mod plots;

use crate::link::EngineLink;
use crate::params::NoetherParams;
use crate::presets::FactoryPreset;
use egui::{Color32, RichText, Vec2};
use nice_plug::context::gui::GuiContext;
use nice_plug::prelude::*;
use nice_plug_egui::{Frame, NiceEguiApp};
use noether_core::engine::{EventKind, ParamId, Telemetry, MODEL_NAMES};
use std::sync::Arc;
use std::time::Duration;

/// The editor application; moved into nice-plug-egui when the editor is created.
pub struct EditorApp {
    /// The plugin's parameters (shared with the host and the audio thread).
    params: Arc<NoetherParams>,
    /// Telemetry and GUI commands (shared with the plugin, which (re)connects the engine).
    link: Arc<EngineLink>,
    /// The factory presets, parsed once.
    presets: Arc<Vec<FactoryPreset>>,
    /// nice-plug's GUI context (parameter setter), set in `build`.
    gui: Option<GuiContext>,
    /// The latest telemetry frame received.
    telemetry: Telemetry,
    /// The worker's last model-build error (names the parameter, value and range).
    build_error: Option<String>,
    /// Voice slot chosen for the spectrum and displacement views (`None`: the loudest).
    watched: Option<u8>,
    /// Key sounding from the audition button while it is held (released with the button).
    auditioning: Option<u8>,
}

impl EditorApp {
    /// A new editor over the plugin's parameters, engine link and presets.
    pub fn new(
        params: Arc<NoetherParams>,
        link: Arc<EngineLink>,
        presets: Arc<Vec<FactoryPreset>>,
    ) -> Self {
        Self {
            params,
            link,
            presets,
            gui: None,
            telemetry: Telemetry::default(),
            build_error: None,
            watched: None,
            auditioning: None,
        }
    }

    fn load_preset(&mut self, index: usize, setter: &ParamSetter) {
        let Some(preset) = self.presets.get(index) else {
            return;
        };
        for info in noether_core::engine::PARAMS {
            let v = preset.values.get(info.id);
            panels::set_slot(setter, self.params.slot(info.id), v);
        }
        if let Ok(mut n) = self.params.preset_name.write() {
            n.clone_from(&preset.name);
        }
    }

    fn top_bar(&mut self, ui: &mut egui::Ui, setter: &ParamSetter) {
        ui.horizontal(|ui| {
            ui.heading("Noether");
            ui.separator();
            let current = self
                .params
                .preset_name
                .read()
                .map(|n| n.clone())
                .unwrap_or_default();
            let mut chosen = None;
            egui::ComboBox::from_id_salt("preset")
                .width(220.0)
                .selected_text(if current.is_empty() {
                    "factory presets".to_string()
                } else {
                    current
                })
                .show_ui(ui, |ui| {
                    for (i, p) in self.presets.iter().enumerate() {
                        if ui
                            .selectable_label(false, &p.name)
                            .on_hover_text(&p.description)
                            .clicked()
                        {
                            chosen = Some(i);
                        }
                    }
                });
            if let Some(i) = chosen {
                self.load_preset(i, setter);
            }
            ui.separator();
            // The load of every thread working on the audio, as a fraction of the threads
            // sharing the voices (1: all of them busy all the time).
            let t = &self.telemetry;
            plots::cpu_bar(ui, t.cpu_load / f32::from(t.threads.max(1)), 130.0);
            ui.label(
                RichText::new(format!(
                    "{:.2} cores on {} threads · peak {:.0} % · {} late",
                    t.cpu_load,
                    t.threads,
                    100.0 * t.cpu_peak,
                    t.late_jobs
                ))
                .small(),
            );
            ui.separator();
            if self.telemetry.rebuilding {
                ui.spinner();
                ui.label(
                    RichText::new("REBUILDING MODEL")
                        .strong()
                        .color(Color32::from_rgb(255, 170, 40)),
                );
            } else {
                let model = self.params.slot(ParamId::Model).value() as usize;
                ui.label(
                    RichText::new(format!(
                        "{} ready, {:.0} Hz simulation",
                        MODEL_NAMES.get(model).copied().unwrap_or("model"),
                        self.telemetry.sim_rate
                    ))
                    .color(Color32::from_rgb(120, 220, 120)),
                );
            }
        });
        if let Some(e) = &self.build_error {
            ui.colored_label(
                Color32::from_rgb(230, 80, 60),
                format!("model build refused: {e}"),
            );
        }
        ui.horizontal(|ui| {
            let t = &self.telemetry;
            ui.label(format!("voices {}", t.active_voices));
            ui.separator();
            ui.label(format!("out peak L {:.2} R {:.2}", t.peak[0], t.peak[1]));
            ui.separator();
            ui.label(format!("Newton cap hits {}", t.newton_cap_hits));
            ui.separator();
            ui.label(format!("diverged voices {}", t.diverged));
            ui.separator();
            if ui.button("panic (all sound off)").clicked() {
                self.link.all_sound_off();
            }
            ui.separator();
            self.audition(ui);
        });
    }

    /// "Hold to play": a note at the root key (velocity 0.8) while the button is held, so the
    /// standalone can be played without a MIDI device.
    fn audition(&mut self, ui: &mut egui::Ui) {
        let held = audition_button(ui).is_pointer_button_down_on();
        match (held, self.auditioning) {
            (true, None) => {
                let key = self.params.slot(ParamId::RootKey).value().clamp(0.0, 127.0) as u8;
                self.link.note(EventKind::NoteOn { key, velocity: 0.8 });
                self.auditioning = Some(key);
            }
            (false, Some(key)) => {
                self.link.note(EventKind::NoteOff { key });
                self.auditioning = None;
            }
            _ => {}
        }
    }

    fn watch_selector(&mut self, ui: &mut egui::Ui) {
        let name = |w: Option<u8>| w.map_or("loudest voice".to_string(), |v| format!("voice #{v}"));
        let mut chosen = self.watched;
        egui::ComboBox::from_id_salt("watch")
            .selected_text(name(self.watched))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut chosen, None, name(None));
                for (i, v) in self.telemetry.voices.iter().enumerate() {
                    if v.active {
                        let slot = Some(i as u8);
                        ui.selectable_value(&mut chosen, slot, name(slot));
                    }
                }
            });
        if chosen != self.watched {
            self.watched = chosen;
            self.link.watch(chosen);
        }
    }

    fn live_views(&mut self, ui: &mut egui::Ui) {
        let width = ui.available_width();
        ui.label(RichText::new("Energy per voice").strong());
        let voices: Vec<(String, [f32; 4])> = self
            .telemetry
            .voices
            .iter()
            .enumerate()
            .filter(|(_, v)| v.active)
            .map(|(i, v)| {
                let e = v.energy;
                (
                    format!(
                        "#{i} key {}{} · {} modes{} to {:.1} kHz",
                        v.key,
                        if v.held { "" } else { " rel." },
                        v.model.n_phi,
                        if v.model.n_psi > 0 {
                            format!(" + {} in-plane", v.model.n_psi)
                        } else {
                            String::new()
                        },
                        v.model.top_mode_hz / 1000.0
                    ),
                    [
                        e.kinetic as f32,
                        e.linear as f32,
                        e.nonlinear as f32,
                        e.total() as f32,
                    ],
                )
            })
            .collect();
        plots::energy_meters(ui, &voices, width);
        ui.add_space(6.0);
        ui.horizontal(|ui| {
            ui.label(RichText::new("Mode spectrum and displacement of").strong());
            self.watch_selector(ui);
        });
        let f_max = self
            .telemetry
            .mode_freq
            .iter()
            .copied()
            .filter(|f| f.is_finite())
            .fold(1_000.0f32, f32::max)
            * 1.2;
        plots::mode_spectrum(
            ui,
            &self.telemetry.mode_freq,
            &self.telemetry.mode_amplitude,
            f_max,
            Vec2::new(width, 120.0),
        );
        ui.add_space(6.0);
        let model = self.params.slot(ParamId::Model).value() as usize;
        let (title, label) = match model {
            0 | 1 => ("Displacement along a diameter", "plate"),
            2 => ("Displacement along the diagonal", "plate"),
            _ => ("Displacement along the string", "string"),
        };
        ui.label(RichText::new(title).strong());
        plots::displacement(
            ui,
            &self.telemetry.displacement,
            label,
            Vec2::new(width, 130.0),
        );
    }
}

/// The audition button. It senses drags as well as clicks: egui forgets a press on a
/// click-only widget once it has lasted `max_click_duration` (0.8 s) or moved a few points, so
/// `is_pointer_button_down_on` of a plain button turns false while the button is still held,
/// which released the note (the voice list showed "rel." under a held button). A drag-sensing
/// widget keeps the press until the pointer button is released. GUI thread.
fn audition_button(ui: &mut egui::Ui) -> egui::Response {
    ui.add(egui::Button::new("hold to play").sense(egui::Sense::click_and_drag()))
        .on_hover_text("plays the root key at velocity 0.8 while held")
}

impl NiceEguiApp for EditorApp {
    fn build(
        &mut self,
        _egui_ctx: egui::Context,
        nice_gui_ctx: GuiContext,
        _frame: &mut Frame,
    ) -> Result<(), nice_plug_egui::baseview::HandlerError> {
        self.gui = Some(nice_gui_ctx);
        Ok(())
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut Frame) {
        self.build_error = self.link.latest_telemetry(&mut self.telemetry);
        let Some(gui) = self.gui.clone() else {
            return;
        };
        let setter = gui.param_setter();
        egui::Frame::default().inner_margin(8.0).show(ui, |ui| {
            self.top_bar(ui, &setter);
            ui.separator();
            let params = self.params.clone();
            ui.columns(2, |cols| {
                egui::ScrollArea::vertical()
                    .id_salt("params")
                    .auto_shrink([false, false])
                    .show(&mut cols[0], |ui| {
                        panels::parameter_panels(ui, &params, &setter)
                    });
                self.live_views(&mut cols[1]);
            });
        });
        // Live views: redraw about 30 times a second while the window is open.
        ui.ctx().request_repaint_after(Duration::from_millis(33));
    }

    fn editor_closed(&mut self) {
        self.gui = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::{Event, Modifiers, PointerButton, Pos2, RawInput, Rect};

    /// Runs one egui frame at time `t` (s) with `events`; returns the button's rectangle and
    /// whether it reports the pointer button down on it.
    fn frame(
        ctx: &egui::Context,
        t: f64,
        events: Vec<Event>,
        button: fn(&mut egui::Ui) -> egui::Response,
    ) -> (Rect, bool) {
        let input = RawInput {
            time: Some(t),
            screen_rect: Some(Rect::from_min_size(Pos2::ZERO, Vec2::new(400.0, 200.0))),
            events,
            ..RawInput::default()
        };
        let mut out = (Rect::NOTHING, false);
        let _ = ctx.run_ui(input, |ui| {
            let r = button(ui);
            out = (r.rect, r.is_pointer_button_down_on());
        });
        out
    }

    /// Presses `button` at t = 0.1 s, holds it still until 3 s, releases it at 3.1 s; returns
    /// the held flag of every frame (30 frames a second) from the press to the release.
    fn hold(button: fn(&mut egui::Ui) -> egui::Response) -> Vec<(f64, bool)> {
        let ctx = egui::Context::default();
        let (rect, _) = frame(&ctx, 0.0, vec![], button);
        let pos = rect.center();
        let press = |pressed| Event::PointerButton {
            pos,
            button: PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        };
        let mut seen = vec![];
        let (_, down) = frame(
            &ctx,
            0.1,
            vec![Event::PointerMoved(pos), press(true)],
            button,
        );
        seen.push((0.1, down));
        for i in 1..=87 {
            let t = 0.1 + f64::from(i) / 30.0;
            seen.push((t, frame(&ctx, t, vec![], button).1));
        }
        let (_, down) = frame(&ctx, 3.1, vec![press(false)], button);
        seen.push((3.1, down));
        seen
    }

    #[test]
    fn audition_button_stays_down_while_held() {
        // The harness reproduces the reported bug: a click-only button lets go after egui's
        // 0.8 s `max_click_duration` although the pointer button is still down.
        let plain = hold(|ui| ui.button("hold to play"));
        assert!(plain[0].1, "plain button not down on the press frame");
        assert!(
            plain.iter().any(|&(t, down)| t < 3.0 && !down),
            "a click-only button no longer lets go of a long press: {plain:?}"
        );
        // The audition button is down on every frame from the press until the release
        // (exact: a boolean per frame), and up on the release frame.
        let fixed = hold(audition_button);
        let (last, held) = fixed.split_last().unwrap();
        for &(t, down) in held {
            assert!(down, "audition button up at t = {t:.2} s while held");
        }
        assert!(!last.1, "audition button still down after the release");
    }
}
