//! The parameter sections (GUI thread only): one grid for every slider (a fixed label column,
//! one slider width, the value text after it), grouped by what a player reaches for (model and
//! material, mallet or pluck, damping, bridge, pickups and output, quality), showing only the
//! sections and rows the current model reads.
//!
//! Sliders map their travel logarithmically for the parameters the engine table marks `log`
//! (stiffnesses, times, forces, lengths spanning decades), so every part of the travel is
//! useful; hosts' own controls keep nice-plug's skewed map (see `params::log_like_skew`).
//! The value text is the parameter's own formatter ([`crate::format`]), and typing into it
//! reads the same units. A double click resets the default.

use crate::format::{format_value, parse_value, typing_unit};
use crate::params::{NoetherParams, Slot};
use egui::{Layout, Ui, Vec2};
use nice_plug::prelude::*;
use noether_core::engine::{ModelKind, ParamId, ParamKind};

/// Width of the label column (points).
pub const LABEL_W: f32 = 150.0;
/// Width of the value text after each slider (points).
pub const VALUE_W: f32 = 100.0;
/// Height of a row (points).
const ROW_H: f32 = 22.0;

/// A section of the panel: its title and its parameters in display order.
struct Section {
    title: &'static str,
    params: &'static [ParamId],
    open: bool,
    /// The models it is shown for.
    models: Models,
}

/// Which models a section is shown for (its rows are also filtered by what the model reads).
#[derive(Clone, Copy, PartialEq, Eq)]
enum Models {
    /// Every model.
    All,
    /// The plates.
    Plates,
    /// The single strings (sitar, tanpura).
    Strings,
    /// The tanpura drone.
    Drone,
    /// The sitar with its taraf.
    SitarTaraf,
}

impl Models {
    /// Whether `model` is one of them.
    fn show(self, model: ModelKind) -> bool {
        match self {
            Models::All => true,
            Models::Plates => model.is_plate(),
            Models::Strings => model.is_string(),
            Models::Drone => model.is_drone(),
            Models::SitarTaraf => model.is_sitar_taraf(),
        }
    }
}

const SECTIONS: [Section; 9] = {
    use ParamId::*;
    [
        Section {
            title: "Model and material",
            params: &[
                Model,
                Size,
                Thickness,
                Aspect,
                Dome,
                Boss,
                BossRadius,
                Material,
                YoungsModulus,
                Density,
                Poisson,
                Tension,
                LinearDensity,
                Inharmonicity,
            ],
            open: true,
            models: Models::All,
        },
        Section {
            title: "Strike",
            params: &[
                Exciter,
                StrikeDuration,
                StrikeForce,
                MalletHead,
                MalletMass,
                MalletHardness,
                MalletSpeed,
                StrikeRadius,
                StrikeAngle,
                VelocityCurve,
            ],
            open: true,
            models: Models::Plates,
        },
        Section {
            title: "Pluck",
            params: &[PluckPosition, PluckAmplitude, VelocityCurve],
            open: true,
            models: Models::Strings,
        },
        Section {
            title: "Drone",
            params: &[
                DroneTuning,
                DroneStrings,
                Jivari,
                DroneCycle,
                DroneSync,
                DroneBeats,
                DronePattern,
                DroneVariation,
                DroneLatch,
                VelocityCurve,
            ],
            open: true,
            models: Models::Drone,
        },
        Section {
            title: "Sitar",
            params: &[
                SitarThaat,
                TarafStrings,
                ChikariStrings,
                ChikariStroke,
                PluckAmplitude,
                VelocityCurve,
            ],
            open: true,
            models: Models::SitarTaraf,
        },
        Section {
            title: "Damping",
            params: &[DampingScale, ReleaseT60, DampingA, DampingB, DampingC0],
            open: true,
            models: Models::All,
        },
        Section {
            title: "Bridge",
            params: &[
                BridgeCurvature,
                BridgePosition,
                ContactStiffness,
                ContactAlpha,
            ],
            open: true,
            models: Models::All,
        },
        Section {
            title: "Pickups and output",
            params: &[
                PickupLeftPos,
                PickupLeftAngle,
                PickupRightPos,
                PickupRightAngle,
                Gain,
                KeyLevel,
                LowCut,
                Limiter,
                RootKey,
                TuningA4,
                PitchBendRange,
                ModWheelDepth,
            ],
            open: false,
            models: Models::All,
        },
        Section {
            title: "Quality",
            params: &[
                Modes,
                InPlaneModes,
                BandLimit,
                Closure,
                BandAbove,
                StrikeAbove,
                SimRate,
                Scheme,
                Polyphony,
                Threads,
                CpuBudget,
                MemoryCap,
                DroneEar,
            ],
            open: false,
            models: Models::All,
        },
    ]
};

/// The label of a row: the host's name, with symbols for the long physics names.
fn short_name(id: ParamId) -> &'static str {
    match id {
        ParamId::ContactAlpha => "Contact exponent α",
        ParamId::LinearDensity => "Linear density μ",
        ParamId::YoungsModulus => "Young's modulus E",
        ParamId::Poisson => "Poisson ratio ν",
        _ => id.info().name,
    }
}

/// Sets `slot` to the plain `value` as one host gesture (begin, set, end).
pub fn set_slot(setter: &ParamSetter, slot: &Slot, value: f32) {
    begin(setter, slot);
    set(setter, slot, value);
    end(setter, slot);
}

/// Begins a host gesture on `slot`.
pub fn begin(setter: &ParamSetter, slot: &Slot) {
    match slot {
        Slot::Float(p) => setter.begin_set_parameter(p),
        Slot::Int(p) => setter.begin_set_parameter(p),
    }
}

/// Sets `slot` inside a gesture.
pub fn set(setter: &ParamSetter, slot: &Slot, value: f32) {
    match slot {
        Slot::Float(p) => setter.set_parameter(p, value),
        Slot::Int(p) => setter.set_parameter(p, value.round() as i32),
    }
}

/// Ends a host gesture on `slot`.
pub fn end(setter: &ParamSetter, slot: &Slot) {
    match slot {
        Slot::Float(p) => setter.end_set_parameter(p),
        Slot::Int(p) => setter.end_set_parameter(p),
    }
}

/// The slider of parameter `id` over `value` (plain units): logarithmic travel for the
/// table's `log` parameters, the parameter's formatter and parser for the value text.
pub fn param_slider(id: ParamId, value: &mut f64) -> egui::Slider<'_> {
    let info = id.info();
    let log = matches!(info.kind, ParamKind::Float { log: true }) && info.min > 0.0;
    let int = !matches!(info.kind, ParamKind::Float { .. });
    let s = egui::Slider::new(value, f64::from(info.min)..=f64::from(info.max))
        .logarithmic(log)
        .clamping(egui::SliderClamping::Always)
        .custom_formatter(move |v, _| format_value(id, v as f32))
        .custom_parser(move |t| parse_value(id, t).map(f64::from));
    if int {
        s.integer()
    } else {
        s
    }
}

/// Applies a control's response to `targets` (`(slot, new value)` pairs) as host gestures:
/// a begin when the pointer goes down on the control, sets while it moves, the end when it is
/// released (a typed value or a click without a press in progress is one begin / set / end).
/// The open-gesture flag lives in egui's memory under the control's id, so every begin gets
/// exactly one end.
pub fn apply_gesture(ui: &Ui, r: &egui::Response, setter: &ParamSetter, targets: &[(&Slot, f32)]) {
    let id = r.id.with("gesture");
    let open = ui.data(|d| d.get_temp::<bool>(id)).unwrap_or(false);
    let down = r.is_pointer_button_down_on();
    if down && !open {
        for (slot, _) in targets {
            begin(setter, slot);
        }
        ui.data_mut(|d| d.insert_temp(id, true));
    }
    if r.changed() {
        for &(slot, v) in targets {
            if down || open {
                set(setter, slot, v);
            } else {
                set_slot(setter, slot, v);
            }
        }
    }
    if open && !down {
        for (slot, _) in targets {
            end(setter, slot);
        }
        ui.data_mut(|d| d.remove::<bool>(id));
    }
}

/// One slider row's control (after its label): moves `slot` with host gestures.
fn slider_row(ui: &mut Ui, id: ParamId, slot: &Slot, setter: &ParamSetter) {
    let info = id.info();
    let mut v = f64::from(slot.value());
    let r = ui.add(param_slider(id, &mut v));
    let r = if typing_unit(id).is_empty() {
        r.on_hover_text("double click: default")
    } else {
        r.on_hover_text(format!(
            "type a value (plain numbers are in {}); double click: default",
            typing_unit(id)
        ))
    };
    if r.double_clicked() {
        set_slot(setter, slot, info.default);
    } else {
        apply_gesture(ui, &r, setter, &[(slot, v as f32)]);
    }
}

fn enum_menu(ui: &mut Ui, setter: &ParamSetter, p: &IntParam, names: &[&str], key: &str, w: f32) {
    let current = p.value().max(0) as usize;
    let mut chosen = None;
    egui::ComboBox::from_id_salt(key)
        .width(w)
        .selected_text(names.get(current).copied().unwrap_or("?"))
        .show_ui(ui, |ui| {
            for (i, name) in names.iter().enumerate() {
                if ui.selectable_label(i == current, *name).clicked() {
                    chosen = Some(i);
                }
            }
        });
    if let Some(i) = chosen {
        setter.begin_set_parameter(p);
        setter.set_parameter(p, i as i32);
        setter.end_set_parameter(p);
    }
}

/// Draws the sections relevant to the current model in the width of `ui`.
pub fn parameter_panels(ui: &mut Ui, params: &NoetherParams, setter: &ParamSetter) {
    // What the instrument reads decides the rows (the table's `reads` column).
    let values = params.plain_values();
    let model = values.model();
    // One slider width for every row: what the panel leaves after the label and value
    // columns (and the collapsing header's indent).
    let indent = ui.spacing().indent;
    let gaps = 3.0 * ui.spacing().item_spacing.x + ui.spacing().slider_rail_height;
    let slider_w = (ui.available_width() - indent - LABEL_W - VALUE_W - gaps).clamp(60.0, 260.0);
    ui.spacing_mut().slider_width = slider_w;
    ui.spacing_mut().interact_size.x = VALUE_W;
    for section in &SECTIONS {
        if !section.models.show(model) {
            continue;
        }
        let rows: Vec<ParamId> = section
            .params
            .iter()
            .copied()
            .filter(|&id| values.reads(id))
            .collect();
        if rows.is_empty() {
            continue;
        }
        egui::CollapsingHeader::new(section.title)
            .default_open(section.open)
            .show(ui, |ui| {
                for id in rows {
                    let info = id.info();
                    ui.horizontal(|ui| {
                        ui.allocate_ui_with_layout(
                            Vec2::new(LABEL_W, ROW_H),
                            Layout::left_to_right(egui::Align::Center),
                            |ui| {
                                ui.set_min_width(LABEL_W);
                                ui.add(egui::Label::new(short_name(id)).truncate())
                                    .on_hover_text(format!("{}\n{}", info.name, info.help));
                            },
                        );
                        match (params.slot(id), info.kind) {
                            (Slot::Int(p), ParamKind::Enum { names, .. }) => {
                                enum_menu(ui, setter, p, names, info.key, slider_w + VALUE_W);
                            }
                            (slot, _) => slider_row(ui, id, slot, setter),
                        }
                    });
                }
            });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use egui::{Event, Modifiers, PointerButton, Pos2, RawInput, Rect};

    /// Clicks the slider of `id` (value text hidden) at the fraction `at` of its rail and
    /// returns the value it takes.
    fn click_slider(id: ParamId, at: f32) -> f64 {
        let ctx = egui::Context::default();
        let mut v = f64::from(id.info().default);
        let run = |events: Vec<Event>, t: f64, v: &mut f64| {
            let input = RawInput {
                time: Some(t),
                screen_rect: Some(Rect::from_min_size(Pos2::ZERO, Vec2::new(400.0, 100.0))),
                events,
                ..RawInput::default()
            };
            let mut rect = Rect::NOTHING;
            let mut out = ctx.run_ui(input, |ui| {
                ui.spacing_mut().slider_width = 300.0;
                // Without egui's "smart aim", which rounds a click to the simplest number
                // within the pixel (3e9 for 3.16e9 where a pixel spans 10 %): the test
                // measures the mapping itself.
                let s = param_slider(id, v).show_value(false).smart_aim(false);
                rect = ui.add(s).rect;
            });
            // Font textures were created; nothing uploads them here.
            out.textures_delta.clear();
            rect
        };
        let rect = run(vec![], 0.0, &mut v);
        // The rail spans the rectangle minus the handle's radius at each end.
        let r = rect.height() / 2.5;
        let x = rect.left() + r + at * (rect.width() - 2.0 * r);
        let pos = Pos2::new(x, rect.center().y);
        let press = |pressed| Event::PointerButton {
            pos,
            button: PointerButton::Primary,
            pressed,
            modifiers: Modifiers::NONE,
        };
        run(vec![Event::PointerMoved(pos), press(true)], 0.1, &mut v);
        run(vec![press(false)], 0.2, &mut v);
        v
    }

    /// The middle of a log parameter's slider is the geometric mean of its range (within
    /// 1 %), and the first 16 % of the contact stiffness travel spans two decades, not the
    /// 1000 to 1000.1 of a power-law skew. The check fails for a linear slider (its middle is
    /// the arithmetic mean, 5e15 for the contact stiffness).
    #[test]
    fn log_slider_midpoint_is_the_geometric_mean() {
        for id in [
            ParamId::ContactStiffness,
            ParamId::ReleaseT60,
            ParamId::StrikeDuration,
            ParamId::StrikeForce,
            ParamId::Size,
        ] {
            let info = id.info();
            let gm = (f64::from(info.min) * f64::from(info.max)).sqrt();
            let mid = click_slider(id, 0.5);
            assert!((mid / gm - 1.0).abs() < 0.01, "{}: {mid} vs {gm}", info.key);
        }
        let k = ParamId::ContactStiffness.info();
        let at16 = click_slider(ParamId::ContactStiffness, 0.16);
        let decades = (at16 / f64::from(k.min)).log10();
        let expect = 0.16 * (f64::from(k.max) / f64::from(k.min)).log10();
        assert!((decades - expect).abs() < 0.1, "{decades} vs {expect}");
    }

    /// Every parameter sits in some section (which rows a model shows is the core's
    /// `param_meta` column, tested there and in tests/engine/param_meta.rs).
    #[test]
    fn every_parameter_has_a_section() {
        // Every parameter sits in some section.
        for info in noether_core::engine::PARAMS {
            assert!(
                SECTIONS.iter().any(|s| s.params.contains(&info.id)),
                "{} in no section",
                info.key
            );
        }
    }
}
