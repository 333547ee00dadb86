//! The user's presets: one TOML file per preset in a folder of the user's, in exactly the
//! factory presets' format ([`Preset`]: `name`, `description`, `[params]`), written with every
//! parameter's value so a preset keeps its sound if a later version changes a default.
//!
//! The folder is `$NOETHER_PRESET_DIR` if that is set, else `noether/presets` in the
//! platform's data folder (the `dirs` crate): `$XDG_DATA_HOME/noether/presets` or
//! `~/.local/share/noether/presets` on Linux, `~/Library/Application Support/noether/presets`
//! on macOS, `%APPDATA%\noether\presets` on Windows. It is created on the first save.
//!
//! A preset's file is `<name>.toml`; names are compared ignoring case (two presets whose names
//! differ only in case would share a file on macOS and Windows). A file that does not parse, or
//! whose values the engine refuses, is listed as broken with its error and never loaded.
//! Files are written to a hidden temporary file first and then renamed over the target, so a
//! crash never leaves a half-written preset.
//!
//! Threads: the GUI thread (file I/O, allocation); never the audio thread.

use noether_core::engine::{ParamValues, Preset};
use noether_core::ParamError;
use std::ffi::OsString;
use std::fs;
use std::path::{Path, PathBuf};

/// The environment variable that overrides the user preset folder (tests, CI, portable use).
pub const DIR_ENV: &str = "NOETHER_PRESET_DIR";

/// Longest preset name accepted, in characters.
pub const MAX_NAME_CHARS: usize = 64;

/// Characters refused in a preset name: path separators, and the characters Windows refuses
/// in file names (so a preset folder can be copied between systems).
const FORBIDDEN: &[char] = &['/', '\\', ':', '*', '?', '"', '<', '>', '|'];

/// What a preset name may be (the `allowed` text of a refused name's error).
fn allowed_names() -> String {
    format!(
        "1 to {MAX_NAME_CHARS} characters, not starting with a dot or a space, with no control \
         character and none of / \\ : * ? \" < > |"
    )
}

/// Checks a preset name typed by the user; returns it trimmed of trailing spaces.
pub fn check_name(name: &str) -> Result<&str, ParamError> {
    let trimmed = name.trim_end();
    let bad = trimmed.is_empty()
        || trimmed.chars().count() > MAX_NAME_CHARS
        || trimmed.starts_with('.')
        || trimmed.starts_with(char::is_whitespace)
        || trimmed
            .chars()
            .any(|c| c.is_control() || FORBIDDEN.contains(&c));
    if bad {
        Err(ParamError::new(
            "preset name",
            format!("{name:?}"),
            allowed_names(),
        ))
    } else {
        Ok(trimmed)
    }
}

/// The folder from the override variable's value `env` or the platform's data folder `data`
/// (`None` if neither is known).
pub fn resolve_dir(env: Option<OsString>, data: Option<PathBuf>) -> Option<PathBuf> {
    match env {
        Some(dir) if !dir.is_empty() => Some(PathBuf::from(dir)),
        _ => data.map(|d| d.join("noether").join("presets")),
    }
}

/// A loadable user preset.
#[derive(Debug, Clone, PartialEq)]
pub struct UserPreset {
    /// File stem (the name the preset was saved under; the key for rename and delete).
    pub stem: String,
    /// Display name (the file's `name`).
    pub name: String,
    /// The file's description.
    pub description: String,
    /// Every parameter's value (defaults where the file names none).
    pub values: ParamValues,
}

/// A `.toml` file of the folder that cannot be loaded.
#[derive(Debug, Clone, PartialEq)]
pub struct BrokenPreset {
    /// File stem.
    pub stem: String,
    /// Why it cannot be loaded (names the field, the value and what is allowed).
    pub error: String,
}

/// The folder's content.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Listing {
    /// Loadable presets, sorted by name ignoring case.
    pub presets: Vec<UserPreset>,
    /// Files that failed to load, sorted by stem ignoring case.
    pub broken: Vec<BrokenPreset>,
}

/// The user preset folder and the operations on it.
#[derive(Debug, Clone, PartialEq)]
pub struct UserPresetStore {
    dir: PathBuf,
}

fn io_error(path: &Path, what: &str, e: std::io::Error) -> ParamError {
    ParamError::new("preset file", path.display(), format!("{what} ({e})"))
}

/// Sort key: the name in lower case, then as written (a stable total order).
fn sort_key(name: &str) -> (String, String) {
    (name.to_lowercase(), name.to_string())
}

impl UserPresetStore {
    /// The store in `dir` (created on the first save).
    pub fn at(dir: impl Into<PathBuf>) -> Self {
        Self { dir: dir.into() }
    }

    /// The store in the user's folder (see the module documentation); `None` if the platform
    /// has no data folder and the override is unset.
    pub fn user() -> Option<Self> {
        resolve_dir(std::env::var_os(DIR_ENV), dirs::data_dir()).map(Self::at)
    }

    /// The folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn path_of(&self, stem: &str) -> PathBuf {
        self.dir.join(format!("{stem}.toml"))
    }

    /// Every preset file of the folder, loaded or listed as broken. A missing folder is an
    /// empty listing; an unreadable folder is one broken entry naming it.
    pub fn list(&self) -> Listing {
        let mut out = Listing::default();
        let entries = match fs::read_dir(&self.dir) {
            Ok(e) => e,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return out,
            Err(e) => {
                out.broken.push(BrokenPreset {
                    stem: self.dir.display().to_string(),
                    error: io_error(&self.dir, "a readable folder", e).to_string(),
                });
                return out;
            }
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let Some(stem) = path
                .file_name()
                .and_then(|n| n.to_str())
                .and_then(|n| n.strip_suffix(".toml"))
            else {
                continue;
            };
            if stem.starts_with('.') || !path.is_file() {
                continue;
            }
            let stem = stem.to_string();
            match Preset::load(&path).and_then(|p| p.values().map(|v| (p, v))) {
                Ok((p, values)) => out.presets.push(UserPreset {
                    stem,
                    name: p.name,
                    description: p.description,
                    values,
                }),
                Err(e) => out.broken.push(BrokenPreset {
                    stem,
                    error: e.to_string(),
                }),
            }
        }
        out.presets
            .sort_by_cached_key(|p| (sort_key(&p.name), sort_key(&p.stem)));
        out.broken.sort_by_cached_key(|b| sort_key(&b.stem));
        out
    }

    /// The stem of the file a preset named `name` would collide with (same name ignoring
    /// case), if there is one.
    pub fn existing(&self, name: &str) -> Option<String> {
        let wanted = name.trim_end().to_lowercase();
        fs::read_dir(&self.dir)
            .ok()?
            .flatten()
            .filter_map(|e| {
                let n = e.file_name().to_str()?.strip_suffix(".toml")?.to_string();
                (!n.starts_with('.')).then_some(n)
            })
            .find(|stem| stem.to_lowercase() == wanted)
    }

    /// Loads the preset saved as `stem`.
    pub fn load(&self, stem: &str) -> Result<UserPreset, ParamError> {
        let p = Preset::load(&self.path_of(stem))?;
        let values = p.values()?;
        Ok(UserPreset {
            stem: stem.to_string(),
            name: p.name,
            description: p.description,
            values,
        })
    }

    /// Writes `text` to `path` through a hidden temporary file in the same folder.
    fn write_atomically(&self, path: &Path, text: &str) -> Result<(), ParamError> {
        fs::create_dir_all(&self.dir)
            .map_err(|e| io_error(&self.dir, "a folder that can be created", e))?;
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or("preset");
        let tmp = self.dir.join(format!(".{name}.tmp"));
        fs::write(&tmp, text).map_err(|e| io_error(&tmp, "a writable file", e))?;
        fs::rename(&tmp, path).map_err(|e| {
            let _ = fs::remove_file(&tmp);
            io_error(path, "a writable file", e)
        })
    }

    /// Saves `values` as the preset `name` with `description`; returns the file's stem. An
    /// existing preset of that name (ignoring case) is replaced only if `overwrite` (the
    /// editor asks first); otherwise that is an error naming it.
    pub fn save(
        &self,
        name: &str,
        description: &str,
        values: &ParamValues,
        overwrite: bool,
    ) -> Result<String, ParamError> {
        let name = check_name(name)?;
        let old = self.existing(name);
        if old.is_some() && !overwrite {
            return Err(ParamError::new(
                "preset name",
                format!("{name:?}"),
                "a name no user preset has yet (or confirm overwriting it)",
            ));
        }
        let text = Preset::from_values(name, description, values).to_toml();
        // A name differing from the old file's only in case: remove the old file first, so
        // the folder keeps one file on case-sensitive file systems too.
        if let Some(old) = old.filter(|o| o != name) {
            let path = self.path_of(&old);
            fs::remove_file(&path).map_err(|e| io_error(&path, "a removable file", e))?;
        }
        self.write_atomically(&self.path_of(name), &text)?;
        Ok(name.to_string())
    }

    /// Renames the preset saved as `stem` to `new_name` (its file and its `name`); returns
    /// the new stem. Refuses a name another preset has (ignoring case) unless `overwrite`.
    pub fn rename(
        &self,
        stem: &str,
        new_name: &str,
        overwrite: bool,
    ) -> Result<String, ParamError> {
        let new_name = check_name(new_name)?;
        let mut preset = Preset::load(&self.path_of(stem))?;
        let other = self
            .existing(new_name)
            .filter(|o| o.to_lowercase() != stem.to_lowercase());
        if other.is_some() && !overwrite {
            return Err(ParamError::new(
                "preset name",
                format!("{new_name:?}"),
                "a name no other user preset has (or confirm overwriting it)",
            ));
        }
        preset.name = new_name.to_string();
        let text = preset.to_toml();
        // Write under a temporary name, remove the old file, then move into place: correct
        // when only the case changes on a case-insensitive file system.
        let tmp = self.dir.join(format!(".{new_name}.rename.tmp"));
        fs::write(&tmp, text).map_err(|e| io_error(&tmp, "a writable file", e))?;
        for old in std::iter::once(stem.to_string()).chain(other) {
            let path = self.path_of(&old);
            fs::remove_file(&path).map_err(|e| io_error(&path, "a removable file", e))?;
        }
        let target = self.path_of(new_name);
        fs::rename(&tmp, &target).map_err(|e| io_error(&target, "a writable file", e))?;
        Ok(new_name.to_string())
    }

    /// Deletes the preset file `stem` (loadable or broken).
    pub fn delete(&self, stem: &str) -> Result<(), ParamError> {
        let path = self.path_of(stem);
        fs::remove_file(&path).map_err(|e| io_error(&path, "an existing, removable file", e))
    }
}

#[cfg(test)]
#[path = "user_presets_tests.rs"]
pub(crate) mod tests;
