//! Microtuning in the plugin: the Scala scale (`.scl`) and keyboard mapping (`.kbm`) the user
//! loaded, saved with the plugin state as text, and the key table they give published to the
//! engine ([`SharedParams::tuning`]).
//!
//! One code path publishes a table: [`TuningState::apply`]. State loading
//! ([`crate::params::NoetherParams`]'s `deserialize_fields`) and the editor's Load and Reset
//! buttons both call it, so a state and a file loaded by hand give the engine the same table.
//! A stored tuning that no longer parses (an edited or corrupt state, a file a later version
//! refuses) is reported (logged and kept as [`TuningState::error`] for the editor) and 12-TET
//! is published instead; the stored text is kept so that saving again does not lose it.
//!
//! Threads: `apply` takes the engine table's writers' lock ([`SharedTuning::set`]), so it runs
//! on the host's main thread (state load: nice-plug calls `deserialize_fields` from CLAP
//! `state.load`, VST3 `setState` and the standalone's state restore, all on the main thread;
//! the plugin never hands nice-plug a state from the GUI, the one path where nice-plug restores
//! a state at the end of a process call) or on the GUI thread (the editor), never the audio
//! thread, which picks the table up lock-free at its next block.
//!
//! [`SharedTuning::set`]: noether_core::engine::SharedTuning::set

use noether_core::engine::{scala_tuning, KeyTuning, ScalaError, SharedParams};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The text of one tuning file and the name it had (for display and error messages).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct TuningFile {
    /// The file's name (no directory), as shown in the editor and named in errors.
    pub name: String,
    /// The file's whole text.
    pub text: String,
}

impl TuningFile {
    /// Reads `path` (GUI thread). The error names the file.
    pub fn read(path: &Path) -> Result<Self, ScalaError> {
        let text = std::fs::read_to_string(path).map_err(|e| ScalaError {
            file: path.display().to_string(),
            message: e.to_string(),
        })?;
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into(),
        );
        Ok(Self { name, text })
    }
}

/// What the plugin state saves about the tuning (persisted field `tuning`, JSON). Both absent:
/// 12-tone equal temperament.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct StoredTuning {
    /// The Scala scale, if one was loaded.
    #[serde(default)]
    pub scl: Option<TuningFile>,
    /// The Scala keyboard mapping, if one was loaded (without a scale it maps 12-TET).
    #[serde(default)]
    pub kbm: Option<TuningFile>,
}

/// The scale a `.kbm` loaded on its own maps: 12-tone equal temperament as a Scala scale.
const TWELVE_TET_SCL: &str = "12-TET\n12\n100.\n200.\n300.\n400.\n500.\n600.\n700.\n800.\n\
                              900.\n1000.\n1100.\n2/1\n";

impl StoredTuning {
    /// The key table and its description, or the parser's error naming the file. Any thread
    /// but the audio thread (allocates).
    pub fn parse(&self) -> Result<(KeyTuning, String), ScalaError> {
        if self.scl.is_none() && self.kbm.is_none() {
            return Ok((KeyTuning::equal(), "12-TET".to_string()));
        }
        let (scl_text, scl_name) = match &self.scl {
            Some(f) => (f.text.as_str(), f.name.as_str()),
            None => (TWELVE_TET_SCL, "12-TET"),
        };
        let kbm = self.kbm.as_ref();
        let t = scala_tuning(
            scl_text,
            kbm.map(|f| f.text.as_str()),
            scl_name,
            kbm.map_or("", |f| f.name.as_str()),
        )?;
        let files = match kbm {
            Some(k) => format!("{scl_name}, {}", k.name),
            None => scl_name.to_string(),
        };
        let description = if t.description.trim().is_empty() {
            files
        } else {
            format!("{} ({files})", t.description.trim())
        };
        Ok((t.table, description))
    }
}

/// The tuning the plugin plays: what is saved, what the engine got, and the last error.
#[derive(Debug, Clone)]
pub struct TuningState {
    /// Saved with the plugin state.
    pub stored: StoredTuning,
    /// The table published to the engine (12-TET when `stored` does not parse).
    pub table: KeyTuning,
    /// What the engine plays, for the editor: "12-TET" or the scale's description and files.
    pub description: String,
    /// Why the stored tuning is not playing (a [`ScalaError`]'s message naming the file), or
    /// why the last load from the editor was refused.
    pub error: Option<String>,
}

impl TuningState {
    /// Parses `stored`, publishes its table to `shared` (12-TET, with [`Self::error`] set and
    /// the error logged, when it does not parse) and keeps `stored` for saving. The one path
    /// that publishes a table: state loads and the editor both use it. Main or GUI thread.
    pub fn apply(stored: StoredTuning, shared: &SharedParams) -> Self {
        let (table, description, error) = match stored.parse() {
            Ok((table, description)) => (table, description, None),
            Err(e) => {
                nice_plug::nice_error!("{e}: playing 12-TET instead");
                (
                    KeyTuning::equal(),
                    "12-TET".to_string(),
                    Some(format!("{e}: playing 12-TET instead")),
                )
            }
        };
        shared.tuning().set(&table);
        Self {
            stored,
            table,
            description,
            error,
        }
    }

    /// Loads a file from the editor: `stored` with `file` as its scale (`kbm == false`) or
    /// mapping, applied if it parses. A file that does not parse (or cannot be read) changes
    /// nothing but [`Self::error`]. GUI thread.
    pub fn load(&mut self, file: Result<TuningFile, ScalaError>, kbm: bool, shared: &SharedParams) {
        let file = match file {
            Ok(f) => f,
            Err(e) => {
                self.error = Some(e.to_string());
                return;
            }
        };
        let mut stored = self.stored.clone();
        *(if kbm {
            &mut stored.kbm
        } else {
            &mut stored.scl
        }) = Some(file);
        match stored.parse() {
            Ok(_) => *self = Self::apply(stored, shared),
            Err(e) => self.error = Some(format!("{e}: not loaded, the tuning is unchanged")),
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// 19 equal steps of 1200/19 cents, in the Scala format.
    pub(crate) fn edo19() -> String {
        let mut s = String::from("! 19edo.scl\n19-EDO\n19\n");
        for i in 1..19 {
            s.push_str(&format!("{:.6}\n", 1200.0 * f64::from(i) / 19.0));
        }
        s.push_str("2/1\n");
        s
    }

    fn file(name: &str, text: &str) -> TuningFile {
        TuningFile {
            name: name.into(),
            text: text.into(),
        }
    }

    /// A 19-EDO scale publishes a table whose key 79 is an octave above key 60 (Scala's default
    /// mapping puts degree 0 on key 60), read back from the engine's shared table. Tolerances:
    /// the octave is the scale's exact `2/1`, so 1e-9 semitone covers the `log2` of the
    /// frequencies (a few ulps of 79); one step is written to 1e-6 cent in the file, so 1e-8
    /// semitone (1e-6 cent).
    #[test]
    fn a_19_edo_scale_reaches_the_engine() {
        let shared = SharedParams::new();
        let stored = StoredTuning {
            scl: Some(file("19edo.scl", &edo19())),
            kbm: None,
        };
        let s = TuningState::apply(stored, &shared);
        assert!(s.error.is_none(), "{:?}", s.error);
        assert_eq!(s.description, "19-EDO (19edo.scl)");
        let t = shared.tuning().get();
        assert_eq!(t, s.table);
        assert!(
            (t.pitch(79) - t.pitch(60) - 12.0).abs() < 1e-9,
            "{}",
            t.pitch(79)
        );
        assert!((t.pitch(61) - t.pitch(60) - 12.0 / 19.0).abs() < 1e-8);
        assert_eq!(t.mapped_keys(), 128);
    }

    /// A stored scale that does not parse: 12-TET is published (replacing the table before),
    /// the error names the file, and the text is kept for saving.
    #[test]
    fn a_bad_stored_scale_falls_back_to_12_tet() {
        let shared = SharedParams::new();
        TuningState::apply(
            StoredTuning {
                scl: Some(file("19edo.scl", &edo19())),
                kbm: None,
            },
            &shared,
        );
        assert!(!shared.tuning().get().is_equal());
        let bad = StoredTuning {
            scl: Some(file("broken.scl", "Broken\n3\n100.0\nnot a pitch\n")),
            kbm: None,
        };
        let s = TuningState::apply(bad.clone(), &shared);
        assert!(shared.tuning().get().is_equal());
        let e = s.error.expect("an error");
        assert!(e.contains("broken.scl") && e.contains("12-TET"), "{e}");
        assert_eq!(s.description, "12-TET");
        assert_eq!(s.stored, bad);
    }

    /// Scala's white-key mapping of 12-TET: the black keys are `x`, unmapped.
    pub(crate) const WHITE_KEYS_KBM: &str = "! white.kbm\n12\n0\n127\n60\n69\n440.0\n12\n\
                                             0\nx\n2\nx\n4\n5\nx\n7\nx\n9\nx\n11\n";

    /// A mapping loaded without a scale maps 12-TET: the white keys keep their 12-TET pitch
    /// (to 1e-9 semitone, the `log2` of the frequencies), the 53 black keys of 128 play
    /// nothing, and the description names the mapping.
    #[test]
    fn a_mapping_alone_maps_12_tet() {
        let shared = SharedParams::new();
        let s = TuningState::apply(
            StoredTuning {
                scl: None,
                kbm: Some(file("white.kbm", WHITE_KEYS_KBM)),
            },
            &shared,
        );
        assert!(s.error.is_none(), "{:?}", s.error);
        let t = shared.tuning().get();
        assert_eq!(t.mapped_keys(), 75);
        for k in [0u8, 21, 60, 69, 72, 127] {
            assert!(
                (t.pitch(k) - f64::from(k)).abs() < 1e-9,
                "key {k}: {}",
                t.pitch(k)
            );
        }
        assert!(!t.is_mapped(61) && !t.is_mapped(70));
        assert!(s.description.contains("white.kbm"), "{}", s.description);
    }

    /// Loading from the editor: a bad file changes nothing but the error; a good one applies;
    /// a mapping loads on top of the scale.
    #[test]
    fn editor_loads_keep_the_tuning_on_error() {
        let shared = SharedParams::new();
        let mut s = TuningState::apply(StoredTuning::default(), &shared);
        s.load(Ok(file("19edo.scl", &edo19())), false, &shared);
        let t19 = shared.tuning().get();
        assert!((t19.pitch(79) - 72.0).abs() < 1e-9);
        s.load(Ok(file("bad.kbm", "garbage")), true, &shared);
        assert!(
            s.error.as_deref().unwrap().contains("bad.kbm"),
            "{:?}",
            s.error
        );
        assert_eq!(shared.tuning().get(), t19);
        assert!(s.stored.kbm.is_none());
        let missing = TuningFile::read(Path::new("/nonexistent/x.scl"));
        s.load(missing, false, &shared);
        assert!(s.error.as_deref().unwrap().contains("/nonexistent/x.scl"));
        assert_eq!(shared.tuning().get(), t19);
        s = TuningState::apply(StoredTuning::default(), &shared);
        assert!(shared.tuning().get().is_equal() && s.error.is_none());
    }
}
