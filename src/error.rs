//! Errors of the offline crate: the core's parameter validation ([`ParamError`] and the
//! `check_*` helpers, re-exported from [`noether_core::error`]) and [`Error`], the one error
//! type of the offline side (scene loading, rendering, file output, studies, the CLI).
//!
//! Every message names what was wrong: a field with its value and allowed range
//! ([`ParamError`]), or the file it concerns. Built on the thread doing the work (CLI main
//! thread or a worker), never on an audio thread.

pub use noether_core::error::*;

use std::path::PathBuf;

/// A `Result` whose error defaults to the offline crate's [`Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// The error of every fallible operation of the offline crate.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// A value out of its allowed range: names the field, the value and the range.
    #[error(transparent)]
    Param(#[from] ParamError),
    /// A scene file could not be read, parsed or validated.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A modal computation failed (a basis or an eigenproblem).
    #[error(transparent)]
    Modal(#[from] noether_core::modal::ModalError),
    /// A folder could not be created.
    #[error("creating {}: {source}", path.display())]
    CreateDir {
        /// The folder.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A file could not be written.
    #[error("writing {}: {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A WAV file could not be written.
    #[error("writing {}: {source}", path.display())]
    Wav {
        /// The file.
        path: PathBuf,
        /// The WAV writer's error.
        source: hound::Error,
    },
    /// A CSV file could not be written.
    #[error("writing {}: {source}", path.display())]
    Csv {
        /// The file.
        path: PathBuf,
        /// The CSV writer's error.
        source: csv::Error,
    },
    /// A value could not be serialised to JSON.
    #[error("JSON: {0}")]
    Json(#[from] serde_json::Error),
    /// A scene could not be serialised back to TOML.
    #[error("writing the reduced scene: {0}")]
    Toml(#[from] toml::ser::Error),
    /// A figure could not be drawn or written.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// The resampler could not be set up for this pair of rates.
    #[error("resampler {rate_in} Hz -> {rate_out} Hz: {source}")]
    ResamplerSetup {
        /// Input rate (Hz).
        rate_in: u32,
        /// Output rate (Hz).
        rate_out: u32,
        /// The resampler's error.
        source: rubato::ResamplerConstructionError,
    },
    /// The resampler failed while processing.
    #[error("resampling: {0}")]
    Resample(#[from] rubato::ResampleError),
    /// There was nothing to write or plot (`what`: for example "channels to write").
    #[error("no {what}")]
    Empty {
        /// What was missing, as a noun phrase.
        what: &'static str,
    },
    /// The scene lacks the model table an operation needs; the message says which.
    #[error("{0}")]
    WrongModel(&'static str),
    /// A preset override is not of the form `KEY=VALUE`.
    #[error("invalid override `{given}` (allowed: KEY=VALUE)")]
    OverrideSyntax {
        /// The override as given.
        given: String,
    },
    /// A preset override names no engine parameter.
    #[error(
        "invalid parameter key `{key}` in `{given}` (allowed: a key of the engine's parameter table)"
    )]
    UnknownParam {
        /// The key.
        key: String,
        /// The override as given.
        given: String,
    },
    /// The settings of an accuracy study do not share the output rate and duration.
    #[error(
        "accuracy study: setting `{setting}` changes the output rate or duration; compare at one output"
    )]
    StudyOutputMismatch {
        /// The offending setting.
        setting: String,
    },
    /// `quality = "auto"`: the full model diverged on the excerpt, so nothing can be verified.
    #[error(
        "quality = \"auto\": the full model diverged on the {excerpt_seconds} s excerpt ({non_finite} non-finite values)"
    )]
    AutoDiverged {
        /// Excerpt length (s).
        excerpt_seconds: f64,
        /// Non-finite output or energy values.
        non_finite: u64,
    },
    /// A render produced non-finite samples (the files were written; see the report).
    #[error("{non_finite} non-finite samples: the simulation diverged (see the report)")]
    Diverged {
        /// Non-finite output or energy values.
        non_finite: u64,
    },
    /// A tuning file (Scala `.scl` or `.kbm`) could not be read or parsed.
    #[error(transparent)]
    Tuning(#[from] noether_core::engine::ScalaError),
    /// Stress cases failed (`noether stress`; the cases are listed before).
    #[error("{count} stress case(s) failed (listed above)")]
    StressFailures {
        /// Failed cases.
        count: usize,
    },
}

/// Errors while loading a scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The file could not be read.
    #[error("reading scene {}: {source}", path.display())]
    Io {
        /// The scene file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// The TOML is malformed, has an unknown field or a value of the wrong type (the message
    /// starts with the file and names the line or field).
    #[error("{0}")]
    Parse(String),
    /// A `--set` override is malformed.
    #[error(transparent)]
    Set(#[from] SetError),
    /// A value is out of range.
    #[error(transparent)]
    Invalid(#[from] ParamError),
}

/// A malformed `--set dotted.path=value` override.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SetError {
    /// No `=`.
    #[error("invalid --set `{assignment}`: expected dotted.path=value")]
    NoValue {
        /// The override as given.
        assignment: String,
    },
    /// A key of the dotted path is empty.
    #[error("invalid --set `{assignment}`: empty key in `{path}`")]
    EmptyKey {
        /// The override as given.
        assignment: String,
        /// Its dotted path.
        path: String,
    },
    /// A prefix of the path names a value that is not a table.
    #[error("invalid --set `{assignment}`: `{prefix}` is a {kind}, not a table")]
    NotATable {
        /// The override as given.
        assignment: String,
        /// The dotted prefix naming the value.
        prefix: String,
        /// The value's TOML type.
        kind: &'static str,
    },
}

/// Errors while drawing or writing a figure (the plotting library's errors are generic: their
/// text is kept).
#[derive(Debug, thiserror::Error)]
#[error("plot error: {0}")]
pub struct PlotError(pub String);
