//! The preset bar (GUI thread): previous/next arrows, the current preset's name with its
//! edited mark as a menu (Factory and User sections, broken user files greyed with their
//! error, Save, Save as, Rename, Delete, the user folder), a Save button, and the A/B compare
//! buttons with the copy button. Save over an existing preset, rename over one and delete ask
//! for confirmation in a modal dialog.
//!
//! Loads and A/B switches write the parameters through nice-plug's `ParamSetter`
//! ([`crate::preset_ops::apply`]), so the host records them; the preset state lives in
//! [`NoetherParams::preset`] and is persisted with the plugin state.

use crate::params::NoetherParams;
use crate::preset_state::{AbSlot, CurrentPreset, Origin, PresetState};
use crate::presets::FactoryPreset;
use crate::user_presets::{Listing, UserPresetStore};
use egui::{Color32, RichText, Ui};
use nice_plug::prelude::*;
use noether_core::engine::ParamValues;
use std::sync::Arc;

/// A preset the arrows and the menu can load.
struct Entry {
    origin: Origin,
    name: String,
    values: ParamValues,
}

/// A modal dialog of the bar.
#[derive(Debug, Clone, PartialEq)]
enum Dialog {
    /// Asks for a new preset's name.
    SaveAs { name: String, error: Option<String> },
    /// Asks for a user preset's new name.
    Rename {
        stem: String,
        name: String,
        error: Option<String>,
    },
    /// Confirms replacing the user preset `name` by a save (`rename_from: None`) or a rename.
    Overwrite {
        name: String,
        rename_from: Option<String>,
    },
    /// Confirms deleting the user preset file `stem`.
    Delete { stem: String, name: String },
}

/// What the user asked for in this frame (applied after drawing).
enum Action {
    Load(usize),
    Step(isize),
    Save,
    Open(Dialog),
    SaveNamed {
        name: String,
        overwrite: bool,
    },
    Rename {
        stem: String,
        name: String,
        overwrite: bool,
    },
    Delete(String),
    Switch(AbSlot),
    Copy,
    Refresh,
}

/// The preset bar's state (the editor owns one).
pub struct PresetBar {
    factory: Arc<Vec<FactoryPreset>>,
    store: Option<UserPresetStore>,
    listing: Option<Listing>,
    dialog: Option<Dialog>,
    /// The last operation's result: text and whether it is an error.
    message: Option<(String, bool)>,
}

/// The index `step` places from the entry with `origin` in a list of `len`, wrapping around;
/// from a preset not in the list, forward starts at the first entry and back at the last.
fn neighbour(position: Option<usize>, len: usize, step: isize) -> Option<usize> {
    if len == 0 {
        return None;
    }
    let len = len as isize;
    Some(match position {
        Some(i) => (i as isize + step).rem_euclid(len) as usize,
        None if step > 0 => 0,
        None => (len - 1) as usize,
    })
}

impl PresetBar {
    /// A bar over the factory presets and the user folder `store` (`None`: no user folder).
    pub fn new(factory: Arc<Vec<FactoryPreset>>, store: Option<UserPresetStore>) -> Self {
        Self {
            factory,
            store,
            listing: None,
            dialog: None,
            message: None,
        }
    }

    fn refresh(&mut self) {
        self.listing = self.store.as_ref().map(UserPresetStore::list);
    }

    fn entries(&self) -> Vec<Entry> {
        let factory = self.factory.iter().map(|p| Entry {
            origin: Origin::Factory(p.stem.to_string()),
            name: p.name.clone(),
            values: p.values,
        });
        let user = self.listing.iter().flat_map(|l| &l.presets).map(|p| Entry {
            origin: Origin::User(p.stem.clone()),
            name: p.name.clone(),
            values: p.values,
        });
        factory.chain(user).collect()
    }

    fn description_of(&self, origin: &Origin) -> String {
        match origin {
            Origin::Factory(stem) => self.factory.iter().find(|p| p.stem == stem.as_str()),
            _ => None,
        }
        .map(|p| p.description.clone())
        .or_else(|| match origin {
            Origin::User(stem) => self
                .listing
                .iter()
                .flat_map(|l| &l.presets)
                .find(|p| &p.stem == stem)
                .map(|p| p.description.clone()),
            _ => None,
        })
        .unwrap_or_default()
    }

    /// Draws the bar and carries out what was asked (GUI thread).
    pub fn show(&mut self, ui: &mut Ui, params: &NoetherParams, setter: &ParamSetter) {
        if self.listing.is_none() {
            self.refresh();
        }
        let Ok(mut state) = params.preset.write() else {
            ui.colored_label(Color32::RED, "preset state unavailable");
            return;
        };
        let mut action = None;
        ui.horizontal(|ui| self.draw(ui, params, &state, &mut action));
        if let Some(dialog) = self.dialog.clone() {
            self.draw_dialog(ui, dialog, &mut action);
        }
        if let Some(action) = action {
            self.act(action, params, setter, &mut state);
        }
    }

    fn draw(
        &self,
        ui: &mut Ui,
        params: &NoetherParams,
        state: &PresetState,
        act: &mut Option<Action>,
    ) {
        if ui
            .small_button(RichText::new("◀").monospace())
            .on_hover_text("previous preset")
            .clicked()
        {
            *act = Some(Action::Step(-1));
        }
        if ui
            .small_button(RichText::new("▶").monospace())
            .on_hover_text("next preset")
            .clicked()
        {
            *act = Some(Action::Step(1));
        }
        let current = &state.current;
        let is_user = matches!(current.origin, Origin::User(_));
        let menu = ui.menu_button(RichText::new(current.display(params)).strong(), |ui| {
            ui.set_min_width(260.0);
            ui.label(RichText::new("Factory").strong());
            let entries = self.entries();
            for (i, e) in entries.iter().enumerate() {
                if i == self.factory.len() {
                    ui.separator();
                    ui.label(RichText::new("User").strong());
                }
                let chosen = ui
                    .selectable_label(e.origin == current.origin, &e.name)
                    .on_hover_text(self.description_of(&e.origin));
                if chosen.clicked() {
                    *act = Some(Action::Load(i));
                    ui.close();
                }
            }
            if entries.len() == self.factory.len() {
                ui.separator();
                ui.label(RichText::new("User").strong());
                ui.weak("none saved yet");
            }
            for b in self.listing.iter().flat_map(|l| &l.broken) {
                ui.add_enabled(
                    false,
                    egui::Label::new(RichText::new(format!("{} (broken)", b.stem)).italics()),
                )
                .on_disabled_hover_text(b.error.as_str());
            }
            ui.separator();
            if ui.button("Save").clicked() {
                *act = Some(Action::Save);
                ui.close();
            }
            if ui.button("Save as…").clicked() {
                *act = Some(Action::Open(Dialog::SaveAs {
                    name: current.name.clone(),
                    error: None,
                }));
                ui.close();
            }
            if let Origin::User(stem) = &current.origin {
                if ui.button("Rename…").clicked() {
                    *act = Some(Action::Open(Dialog::Rename {
                        stem: stem.clone(),
                        name: current.name.clone(),
                        error: None,
                    }));
                    ui.close();
                }
                if ui.button("Delete…").clicked() {
                    *act = Some(Action::Open(Dialog::Delete {
                        stem: stem.clone(),
                        name: current.name.clone(),
                    }));
                    ui.close();
                }
            }
            if ui.button("Refresh user presets").clicked() {
                *act = Some(Action::Refresh);
            }
            match &self.store {
                Some(s) => ui.weak(format!("user folder: {}", s.dir().display())),
                None => ui.weak("no user folder (set NOETHER_PRESET_DIR)"),
            };
        });
        if menu.response.clicked() {
            *act = Some(Action::Refresh);
        }
        let save_tip = if is_user {
            "overwrite this user preset (asks first)"
        } else {
            "save as a new user preset"
        };
        if ui.button("Save").on_hover_text(save_tip).clicked() {
            *act = Some(Action::Save);
        }
        ui.separator();
        for slot in [AbSlot::A, AbSlot::B] {
            if ui
                .selectable_label(state.active == slot, slot.label())
                .on_hover_text(format!("compare: make slot {} active", slot.label()))
                .clicked()
            {
                *act = Some(Action::Switch(slot));
            }
        }
        let (from, to) = (state.active.label(), state.active.other().label());
        if ui
            .small_button(RichText::new(format!("{from}→{to}")).monospace())
            .on_hover_text(format!("copy slot {from} into slot {to}"))
            .clicked()
        {
            *act = Some(Action::Copy);
        }
        if let Some((text, error)) = &self.message {
            let color = if *error {
                Color32::from_rgb(230, 80, 60)
            } else {
                Color32::from_rgb(120, 220, 120)
            };
            ui.label(RichText::new(text).small().color(color));
        }
    }

    fn draw_dialog(&mut self, ui: &mut Ui, dialog: Dialog, act: &mut Option<Action>) {
        let modal = egui::Modal::new(ui.make_persistent_id("noether preset dialog")).show(ui.ctx(), |ui| {
            ui.set_width(360.0);
            match dialog {
                Dialog::SaveAs { mut name, error } | Dialog::Rename { mut name, error, .. } => {
                    let title = if matches!(self.dialog, Some(Dialog::SaveAs { .. })) {
                        "Save as a user preset"
                    } else {
                        "Rename the user preset"
                    };
                    ui.heading(title);
                    let edit = ui.text_edit_singleline(&mut name);
                    // Enter means OK (the text field gives up its focus on Enter, so its
                    // focus is asked for again only when no Enter came).
                    let enter = ui.input(|i| i.key_pressed(egui::Key::Enter));
                    if !edit.has_focus() && !enter {
                        edit.request_focus();
                    }
                    if let Some(e) = &error {
                        ui.colored_label(Color32::from_rgb(230, 80, 60), e.as_str());
                    }
                    let (ok, cancel) = ui
                        .horizontal(|ui| (ui.button("OK").clicked(), ui.button("Cancel").clicked()))
                        .inner;
                    match &mut self.dialog {
                        Some(Dialog::SaveAs { name: n, .. }) | Some(Dialog::Rename { name: n, .. }) => {
                            n.clone_from(&name)
                        }
                        _ => {}
                    }
                    if ok || enter {
                        *act = Some(match self.dialog.clone() {
                            Some(Dialog::Rename { stem, .. }) => Action::Rename {
                                stem,
                                name,
                                overwrite: false,
                            },
                            _ => Action::SaveNamed {
                                name,
                                overwrite: false,
                            },
                        });
                    }
                    cancel
                }
                Dialog::Overwrite { name, rename_from } => {
                    ui.heading("Replace a user preset?");
                    ui.label(match &rename_from {
                        None => format!("Replace the user preset \"{name}\" with the current values?"),
                        Some(stem) => format!(
                            "A user preset named \"{name}\" exists: replace it with \"{stem}\" renamed?"
                        ),
                    });
                    let (ok, cancel) = ui
                        .horizontal(|ui| {
                            (ui.button("Replace").clicked(), ui.button("Cancel").clicked())
                        })
                        .inner;
                    if ok {
                        *act = Some(match rename_from {
                            Some(stem) => Action::Rename {
                                stem,
                                name,
                                overwrite: true,
                            },
                            None => Action::SaveNamed {
                                name,
                                overwrite: true,
                            },
                        });
                    }
                    cancel
                }
                Dialog::Delete { stem, name } => {
                    ui.heading("Delete a user preset?");
                    ui.label(format!("Delete \"{name}\" ({stem}.toml) from the user folder?"));
                    let (ok, cancel) = ui
                        .horizontal(|ui| (ui.button("Delete").clicked(), ui.button("Cancel").clicked()))
                        .inner;
                    if ok {
                        *act = Some(Action::Delete(stem));
                    }
                    cancel
                }
            }
        });
        if modal.inner || modal.should_close() {
            self.dialog = None;
        }
    }

    /// Carries out `action` and sets the message, the dialog and the listing it leads to.
    fn act(
        &mut self,
        action: Action,
        params: &NoetherParams,
        setter: &ParamSetter,
        state: &mut PresetState,
    ) {
        let entries = self.entries();
        let load = |state: &mut PresetState, e: &Entry| {
            let preset = CurrentPreset::new(&e.name, e.origin.clone(), e.values);
            state.load(params, setter, preset, &e.values);
        };
        match action {
            Action::Load(i) => {
                if let Some(e) = entries.get(i) {
                    load(state, e);
                    self.message = None;
                }
            }
            Action::Step(step) => {
                let here = entries
                    .iter()
                    .position(|e| e.origin == state.current.origin);
                if let Some(e) = neighbour(here, entries.len(), step).and_then(|i| entries.get(i)) {
                    load(state, e);
                    self.message = None;
                }
            }
            Action::Save => {
                self.dialog = Some(match &state.current.origin {
                    Origin::User(_) => Dialog::Overwrite {
                        name: state.current.name.clone(),
                        rename_from: None,
                    },
                    _ => Dialog::SaveAs {
                        name: state.current.name.clone(),
                        error: None,
                    },
                });
            }
            Action::Open(d) => self.dialog = Some(d),
            Action::Refresh => self.refresh(),
            Action::Switch(slot) => state.switch_to(slot, params, setter),
            Action::Copy => {
                state.copy_to_other(params);
                let (a, b) = (state.active.label(), state.active.other().label());
                self.message = Some((format!("copied {a} to {b}"), false));
            }
            Action::SaveNamed { name, overwrite } => self.save(name, overwrite, params, state),
            Action::Rename {
                stem,
                name,
                overwrite,
            } => self.rename(stem, name, overwrite, state),
            Action::Delete(stem) => {
                let Some(store) = &self.store else { return };
                self.message = Some(match store.delete(&stem) {
                    Ok(()) => {
                        if state.current.origin == Origin::User(stem.clone()) {
                            state.current.origin = Origin::Unsaved;
                        }
                        (format!("deleted {stem}"), false)
                    }
                    Err(e) => (e.to_string(), true),
                });
                self.dialog = None;
                self.refresh();
            }
        }
    }

    fn save(
        &mut self,
        name: String,
        overwrite: bool,
        params: &NoetherParams,
        state: &mut PresetState,
    ) {
        let Some(store) = &self.store else {
            self.message = Some(("no user preset folder: set NOETHER_PRESET_DIR".into(), true));
            self.dialog = None;
            return;
        };
        if !overwrite && store.existing(&name).is_some() {
            self.dialog = Some(Dialog::Overwrite {
                name,
                rename_from: None,
            });
            return;
        }
        let values = params.plain_values();
        // A user preset keeps its description; one saved from a factory preset says which
        // (the factory text describes the factory values, not the edited ones).
        let description = match &state.current.origin {
            Origin::User(_) => self.description_of(&state.current.origin),
            Origin::Factory(stem) => format!(
                "Saved from the factory preset \"{}\" ({stem}).",
                state.current.name
            ),
            Origin::Init | Origin::Unsaved => String::new(),
        };
        match store.save(&name, &description, &values, true) {
            Ok(stem) => {
                self.message = Some((format!("saved {stem}"), false));
                state.current = CurrentPreset::new(&stem, Origin::User(stem.clone()), values);
                self.dialog = None;
            }
            Err(e) => self.fail(e.to_string()),
        }
        self.refresh();
    }

    fn rename(&mut self, stem: String, name: String, overwrite: bool, state: &mut PresetState) {
        let Some(store) = &self.store else { return };
        let taken = store
            .existing(&name)
            .is_some_and(|o| o.to_lowercase() != stem.to_lowercase());
        if taken && !overwrite {
            self.dialog = Some(Dialog::Overwrite {
                name,
                rename_from: Some(stem),
            });
            return;
        }
        match store.rename(&stem, &name, overwrite) {
            Ok(new) => {
                if state.current.origin == Origin::User(stem.clone()) {
                    state.current.name.clone_from(&new);
                    state.current.origin = Origin::User(new.clone());
                }
                self.message = Some((format!("renamed {stem} to {new}"), false));
                self.dialog = None;
            }
            Err(e) => self.fail(e.to_string()),
        }
        self.refresh();
    }

    /// Shows `error` in the open name dialog, or in the bar if no name dialog is open.
    fn fail(&mut self, error: String) {
        match &mut self.dialog {
            Some(Dialog::SaveAs { error: e, .. }) | Some(Dialog::Rename { error: e, .. }) => {
                *e = Some(error);
            }
            _ => {
                self.message = Some((error, true));
                self.dialog = None;
            }
        }
    }
}

#[cfg(test)]
#[path = "preset_bar_tests.rs"]
mod tests;
