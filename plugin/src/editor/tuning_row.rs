//! The editor's tuning row (GUI thread): what the engine plays ("12-TET" or the scale's
//! description, files and mapped-key count), a path field with a picker over the `.scl` and
//! `.kbm` files of the path's folder, Load .scl / Load .kbm / Reset to 12-TET, and the last
//! error inline. Loads go through [`TuningState::load`] and [`TuningState::apply`], the path a
//! state load takes, so a file loaded here and a saved state publish the same table.

use crate::params::NoetherParams;
use crate::tuning::{StoredTuning, TuningFile, TuningState};
use egui::{Color32, RichText};
use std::path::{Path, PathBuf};

/// The row's own state: the path being typed.
#[derive(Debug, Default)]
pub struct TuningRow {
    /// The path field's text (a `.scl`/`.kbm` file, or a folder to pick from).
    path: String,
}

/// The `.scl` and `.kbm` files in `dir`, sorted (empty when it cannot be read). GUI thread,
/// only while the picker is open.
fn tuning_files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.extension()
                .and_then(|x| x.to_str())
                .is_some_and(|x| x.eq_ignore_ascii_case("scl") || x.eq_ignore_ascii_case("kbm"))
        })
        .collect();
    files.sort();
    files
}

impl TuningRow {
    /// The folder the picker lists: the path itself if it is a folder, else its parent.
    fn folder(&self) -> PathBuf {
        let p = PathBuf::from(self.path.trim());
        if p.is_dir() {
            p
        } else {
            p.parent()
                .filter(|d| !d.as_os_str().is_empty())
                .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
        }
    }

    /// Draws the row and acts on its buttons.
    pub fn show(&mut self, ui: &mut egui::Ui, params: &NoetherParams) {
        let (description, keys, error, stored) = match params.tuning.read() {
            Ok(t) => (
                t.description.clone(),
                t.table.mapped_keys(),
                t.error.clone(),
                t.stored.clone(),
            ),
            Err(_) => return,
        };
        ui.horizontal_wrapped(|ui| {
            ui.label(RichText::new("Tuning").strong());
            let status = if keys == 128 {
                description
            } else {
                format!("{description} · {keys} of 128 keys mapped")
            };
            ui.label(RichText::new(status).color(Color32::from_rgb(150, 200, 255)))
                .on_hover_text("Saved with the plugin state: the .scl and .kbm texts");
            ui.separator();
            ui.add(
                egui::TextEdit::singleline(&mut self.path)
                    .hint_text("path to a .scl or .kbm file, or a folder")
                    .desired_width(260.0),
            );
            let folder = self.folder();
            egui::ComboBox::from_id_salt("tuning_files")
                .selected_text("files…")
                .show_ui(ui, |ui| {
                    let files = tuning_files(&folder);
                    if files.is_empty() {
                        ui.label(format!("no .scl or .kbm in {}", folder.display()));
                    }
                    for f in files {
                        let name = f.file_name().map(|n| n.to_string_lossy().to_string());
                        if ui
                            .selectable_label(false, name.unwrap_or_default())
                            .clicked()
                        {
                            self.path = f.display().to_string();
                        }
                    }
                });
            let path = PathBuf::from(self.path.trim());
            let load = |kbm: bool| {
                let file = TuningFile::read(&path);
                if let Ok(mut t) = params.tuning.write() {
                    t.load(file, kbm, &params.engine);
                }
            };
            if ui.button("Load .scl").clicked() {
                load(false);
            }
            if ui.button("Load .kbm").clicked() {
                load(true);
            }
            let default = StoredTuning::default();
            if ui
                .add_enabled(
                    stored != default || error.is_some(),
                    egui::Button::new("Reset to 12-TET"),
                )
                .clicked()
            {
                params.set_tuning(TuningState::apply(default, &params.engine));
            }
        });
        if let Some(e) = error {
            ui.colored_label(Color32::from_rgb(230, 80, 60), e);
        }
    }
}
