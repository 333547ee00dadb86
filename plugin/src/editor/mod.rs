//! The egui editor (GUI thread only), laid out for players: a top bar with the preset bar
//! (factory and user presets, A/B compare), CPU load and the model state (a clear "rebuilding
//! model" banner while the worker builds a voice bank), the tuning row ([`tuning_row`]), four macro controls (hardness, brightness, decay, size), the parameter
//! sections on the left ([`grid`]), live views on the right (energy meters on one dB scale
//! with a strip chart, the mode spectrum, the displacement of the watched voice) and an
//! on-screen keyboard across the bottom, also played from the computer keyboard.
//!
//! Data flow: parameters go through nice-plug's `ParamSetter` (so hosts record automation);
//! telemetry frames come from the engine through [`EngineLink`]; notes from the keyboard go
//! through the engine's GUI command queue; preset loads set every parameter through the setter
//! as one gesture per parameter.

mod drone_view;
pub mod grid;
pub mod keyboard;
pub mod macros;
pub mod meters;
mod plots;
mod preset_bar;
pub mod tuning_row;

use crate::format::plural;
use crate::link::EngineLink;
use crate::params::NoetherParams;
use crate::presets::FactoryPreset;
use crate::user_presets::UserPresetStore;
use egui::{Color32, RichText, Vec2};
use keyboard::Keyboard;
use meters::EnergyHistory;
use nice_plug::context::gui::GuiContext;
use nice_plug::prelude::*;
use nice_plug_egui::{Frame, NiceEguiApp};
use noether_core::engine::{DroneTuning, EventKind, FitReason, ParamId, Telemetry, MODEL_NAMES};
use preset_bar::PresetBar;
use std::sync::Arc;
use std::time::Duration;
use tuning_row::TuningRow;

/// The editor application; moved into nice-plug-egui when the editor is created.
pub struct EditorApp {
    /// The plugin's parameters (shared with the host and the audio thread).
    params: Arc<NoetherParams>,
    /// Telemetry and GUI commands (shared with the plugin, which (re)connects the engine).
    link: Arc<EngineLink>,
    /// The preset bar (factory and user presets, A/B compare).
    preset_bar: PresetBar,
    /// nice-plug's GUI context (parameter setter), set in `build`.
    gui: Option<GuiContext>,
    /// The latest telemetry frame received.
    telemetry: Telemetry,
    /// The worker's last model-build error (names the parameter, value and range).
    build_error: Option<String>,
    /// Voice slot chosen for the spectrum and displacement views (`None`: the loudest).
    watched: Option<u8>,
    /// The on-screen keyboard and the computer keys' state.
    keyboard: Keyboard,
    /// Recent total energies of the voices for the meters' strip chart.
    history: EnergyHistory,
    /// Height of the live views' column in the last frame (points), which sizes the plots.
    views_h: f32,
    /// The tuning row (path field, Scala loads).
    tuning: TuningRow,
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
            preset_bar: PresetBar::new(presets, UserPresetStore::user()),
            gui: None,
            telemetry: Telemetry::default(),
            build_error: None,
            watched: None,
            keyboard: Keyboard::default(),
            history: EnergyHistory::default(),
            views_h: 400.0,
            tuning: TuningRow::default(),
        }
    }

    fn top_bar(&mut self, ui: &mut egui::Ui, setter: &ParamSetter) {
        ui.horizontal_wrapped(|ui| {
            ui.heading("Noether");
            ui.separator();
            self.preset_bar.show(ui, &self.params, setter);
            ui.separator();
            if self.telemetry.rebuilding {
                ui.spinner();
                // Bank 0: nothing built yet at this activation (silent until it is ready);
                // a preview bank: a small model of the instrument plays; otherwise the last
                // good model plays meanwhile.
                let text = if self.telemetry.bank == 0 {
                    "BUILDING MODEL · silent until it is ready"
                } else if self.telemetry.preview {
                    "BUILDING MODEL · a smaller preview plays until it is ready"
                } else {
                    "REBUILDING MODEL · the last model plays"
                };
                ui.label(
                    RichText::new(text)
                        .strong()
                        .color(Color32::from_rgb(255, 170, 40)),
                );
            } else {
                let model = self.params.slot(ParamId::Model).value() as usize;
                ui.label(
                    RichText::new(format!(
                        "{} ready · {:.1} kHz simulation",
                        MODEL_NAMES.get(model).copied().unwrap_or("model"),
                        self.telemetry.sim_rate / 1000.0
                    ))
                    .color(Color32::from_rgb(120, 220, 120)),
                );
            }
            ui.separator();
            // The load of every thread working on the audio, as a fraction of the threads
            // sharing the voices (1: all of them busy all the time).
            let t = &self.telemetry;
            plots::cpu_bar(ui, t.cpu_load / f32::from(t.threads.max(1)), 110.0).on_hover_text(
                format!(
                    "{:.2} cores busy on {} · peak block {:.0} % · {} late · tensors {:.1} MB",
                    t.cpu_load,
                    plural(usize::from(t.threads), "thread", "threads"),
                    100.0 * t.cpu_peak,
                    plural(t.late_jobs as usize, "job", "jobs"),
                    t.memory_bytes as f64 / 1048576.0,
                ),
            );
            // The CPU governor's reductions (the `cpu_budget` parameter).
            if t.governor_reduced + t.governor_shed > 0 {
                ui.label(
                    RichText::new(format!(
                        "CPU budget: {} narrowed, {} ended",
                        plural(t.governor_reduced as usize, "note", "notes"),
                        plural(t.governor_shed as usize, "voice", "voices"),
                    ))
                    .color(Color32::from_rgb(255, 170, 40)),
                )
                .on_hover_text(
                    "Notes started with a narrower band, and voices ended, to keep within the \
                     CPU budget (Quality panel)",
                );
            }
            if let Some(f) = t.modes_fitted {
                let (what, why) = match f.reason {
                    FitReason::Cpu => (
                        "CPU budget",
                        "One voice of this string with all its modes would cost more than its \
                         share of the CPU budget (Quality panel): the model was built with fewer",
                    ),
                    FitReason::Memory => (
                        "Memory cap",
                        "This plate's coupling tensors with all its modes would take more memory \
                         than the memory cap (Quality panel): the model was built with fewer",
                    ),
                };
                ui.label(
                    RichText::new(format!("{what}: {} of {} modes", f.built, f.wanted))
                        .color(Color32::from_rgb(255, 170, 40)),
                )
                .on_hover_text(why);
            }
            match t.drone_tuning {
                Some(tuning @ (DroneTuning::RootOnly | DroneTuning::Tensions { asked: true })) => {
                    ui.label(
                        RichText::new("Tuning by ear: reduced")
                            .color(Color32::from_rgb(255, 170, 40)),
                    )
                    .on_hover_text(format!("The strings were {tuning}."));
                }
                Some(DroneTuning::Tensions { asked: false }) if t.preview => {
                    ui.label(RichText::new("Tuning by ear…")).on_hover_text(
                        "The strings play tuned by their tensions while the worker tunes \
                             every string by ear (done once per drone or sitar, then kept)",
                    );
                }
                _ => {}
            }
        });
        if let Some(e) = &self.build_error {
            ui.colored_label(
                Color32::from_rgb(230, 80, 60),
                format!("model build refused: {e}"),
            );
        }
        ui.horizontal_wrapped(|ui| {
            let t = &self.telemetry;
            let active = t.voices.iter().filter(|v| v.active).count();
            ui.label(format!("{} sounding", plural(active, "voice", "voices")));
            ui.separator();
            let db = |p: f32| {
                if p > 0.0 {
                    format!("{:+.1} dB", 20.0 * p.log10())
                } else {
                    "-inf dB".to_string()
                }
            };
            ui.label(format!("out peak L {} R {}", db(t.peak[0]), db(t.peak[1])));
            ui.separator();
            ui.label(format!(
                "{} · {}",
                plural(
                    t.newton_cap_hits as usize,
                    "Newton cap hit",
                    "Newton cap hits"
                ),
                plural(t.diverged as usize, "diverged voice", "diverged voices"),
            ));
            ui.separator();
            if ui.button("panic (all sound off)").clicked() {
                self.link.all_sound_off();
            }
        });
        self.tuning.show(ui, &self.params);
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
        meters::energy_meters(ui, &self.telemetry, &self.history, width);
        // The plots share what the meters leave (the titles and gaps take about 60 points).
        let rest = self.views_h - (ui.min_rect().height() + 60.0);
        let spectrum_h = (rest / 1.7).clamp(110.0, 320.0);
        ui.add_space(6.0);
        if let Some(view) = self.telemetry.drone {
            // The drone: its strings and its cycle, in the place of the spectrum and the
            // displacement of one string.
            ui.horizontal(|ui| {
                ui.label(RichText::new("Strings and cycle of").strong());
                self.watch_selector(ui);
            });
            drone_view::drone(ui, &view, Vec2::new(width, 1.7 * spectrum_h + 4.0));
            return;
        }
        ui.horizontal(|ui| {
            ui.label(RichText::new("Modes and displacement of").strong());
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
            Vec2::new(width, spectrum_h),
        );
        ui.add_space(4.0);
        let model = self.params.slot(ParamId::Model).value() as usize;
        let label = match model {
            0 | 1 => "plate, along a diameter",
            2 => "plate, along the diagonal",
            _ => "string, along its length",
        };
        plots::displacement(
            ui,
            &self.telemetry.displacement,
            label,
            Vec2::new(width, 0.7 * spectrum_h),
        );
    }
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
        let now = ui.input(|i| i.time);
        self.history.push(&self.telemetry, now);
        let Some(gui) = self.gui.clone() else {
            return;
        };
        let setter = gui.param_setter();
        let link = self.link.clone();
        let mut send = |e: EventKind| link.note(e);
        self.keyboard.computer_keys(ui, &mut send);
        egui::Frame::default().inner_margin(8.0).show(ui, |ui| {
            self.top_bar(ui, &setter);
            ui.horizontal_wrapped(|ui| {
                let w = ((ui.available_width() - 4.0 * 90.0) / 4.0).clamp(60.0, 150.0);
                macros::macro_row(ui, &self.params, &setter, w);
            });
            ui.separator();
            let area = ui.available_rect_before_wrap();
            let keys_h = (0.15 * area.height()).clamp(72.0, 130.0);
            let keyboard_h = keys_h + 26.0;
            let middle_bottom = (area.bottom() - keyboard_h - 8.0).max(area.top() + 60.0);
            let left_w = (0.5 * area.width())
                .clamp(300.0, 470.0)
                .min(area.width() * 0.6);
            let gap = 10.0;
            let left =
                egui::Rect::from_min_max(area.min, egui::pos2(area.left() + left_w, middle_bottom));
            let right = egui::Rect::from_min_max(
                egui::pos2(left.right() + gap, area.top()),
                egui::pos2(area.right(), middle_bottom),
            );
            let keys =
                egui::Rect::from_min_max(egui::pos2(area.left(), middle_bottom + 8.0), area.max);
            let params = self.params.clone();
            ui.scope_builder(egui::UiBuilder::new().max_rect(left), |ui| {
                egui::ScrollArea::vertical()
                    .id_salt("params")
                    .auto_shrink([false, false])
                    .show(ui, |ui| grid::parameter_panels(ui, &params, &setter));
            });
            self.views_h = right.height();
            ui.scope_builder(egui::UiBuilder::new().max_rect(right), |ui| {
                egui::ScrollArea::vertical()
                    .id_salt("views")
                    .auto_shrink([false, false])
                    .show(ui, |ui| self.live_views(ui));
            });
            let sounding: Vec<(u8, bool)> = self
                .telemetry
                .voices
                .iter()
                .filter(|v| v.active)
                .map(|v| (v.key, v.held))
                .collect();
            ui.scope_builder(egui::UiBuilder::new().max_rect(keys), |ui| {
                self.keyboard.show(ui, keys_h, &sounding, &mut send);
            });
            ui.advance_cursor_after_rect(area);
        });
        // Live views: redraw about 30 times a second while the window is open.
        ui.ctx().request_repaint_after(Duration::from_millis(33));
    }

    fn editor_closed(&mut self) {
        // No note outlives the editor: release the mouse's and the computer keys' notes.
        let link = self.link.clone();
        let mut send = |e: EventKind| link.note(e);
        self.keyboard.mouse.update(false, None, &mut send);
        self.keyboard.release_computer_keys(&mut send);
        self.gui = None;
    }
}
