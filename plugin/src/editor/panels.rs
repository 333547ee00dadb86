//! Parameter panels (GUI thread): one collapsible group per [`group_of`] name, a slider per
//! continuous or integer parameter and a menu per enumeration; parameters the current model
//! does not read are shown disabled.

use crate::params::{group_of, NoetherParams, Slot};
use egui::Ui;
use nice_plug::prelude::*;
use nice_plug_egui::widgets::ParamSlider;
use noether_core::engine::{ParamId, ParamKind, PARAMS};

/// Group names in display order (the values [`group_of`] returns).
const GROUPS: [&str; 7] = [
    "Model and material",
    "Excitation",
    "String and bridge",
    "Damping and release",
    "Pickups",
    "Quality",
    "Tuning and output",
];

/// Whether the model with index `model` (see `MODEL_NAMES`) reads parameter `id`.
pub fn relevant(id: ParamId, model: usize) -> bool {
    use ParamId::*;
    let plate = model <= 2;
    let string = !plate;
    match id {
        Thickness | Material | YoungsModulus | Density | Poisson | DampingA | DampingB
        | DampingC0 | StrikeRadius | StrikeAngle | StrikeDuration | StrikeForce
        | PickupLeftAngle | PickupRightAngle | InPlaneModes | Scheme => plate,
        Aspect => model == 2,
        Tension | LinearDensity | Inharmonicity | BridgePosition | ContactStiffness
        | ContactAlpha | PluckPosition | PluckAmplitude => string,
        BridgeCurvature => model == 3,
        _ => true,
    }
}

/// Sets `slot` to the plain `value` as one host gesture (begin, set, end).
pub fn set_slot(setter: &ParamSetter, slot: &Slot, value: f32) {
    match slot {
        Slot::Float(p) => {
            setter.begin_set_parameter(p);
            setter.set_parameter(p, value);
            setter.end_set_parameter(p);
        }
        Slot::Int(p) => {
            setter.begin_set_parameter(p);
            setter.set_parameter(p, value.round() as i32);
            setter.end_set_parameter(p);
        }
    }
}

fn enum_menu(ui: &mut Ui, setter: &ParamSetter, p: &IntParam, names: &[&str], key: &str) {
    let current = p.value().max(0) as usize;
    let mut chosen = None;
    egui::ComboBox::from_id_salt(key)
        .width(230.0)
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

/// Draws every group of parameters.
pub fn parameter_panels(ui: &mut Ui, params: &NoetherParams, setter: &ParamSetter) {
    let model = params.slot(ParamId::Model).value() as usize;
    for group in GROUPS {
        egui::CollapsingHeader::new(group)
            .default_open(matches!(
                group,
                "Model and material" | "Excitation" | "Quality"
            ))
            .show(ui, |ui| {
                egui::Grid::new(group)
                    .num_columns(2)
                    .striped(true)
                    .show(ui, |ui| {
                        for info in PARAMS.iter().filter(|i| group_of(i.id) == group) {
                            let enabled = relevant(info.id, model);
                            ui.add_enabled(enabled, egui::Label::new(info.name))
                                .on_hover_text(info.help);
                            ui.add_enabled_ui(enabled, |ui| {
                                match (params.slot(info.id), info.kind) {
                                    (Slot::Int(p), ParamKind::Enum { names }) => {
                                        enum_menu(ui, setter, p, names, info.key);
                                    }
                                    (Slot::Int(p), _) => {
                                        ui.add(ParamSlider::for_param(p, setter).with_width(200.0));
                                    }
                                    (Slot::Float(p), _) => {
                                        ui.add(ParamSlider::for_param(p, setter).with_width(200.0));
                                    }
                                }
                            });
                            ui.end_row();
                        }
                    });
            });
    }
}
