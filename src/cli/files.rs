//! File output shared by the subcommands: errors name the path; the output arguments of
//! `render` and `play`.

use clap::Args;
use indicatif::{ProgressBar, ProgressStyle};
use noether::Error;
use std::path::{Path, PathBuf};

/// Creates the folder `path` and its parents.
pub(super) fn create_dir(path: &Path) -> Result<(), Error> {
    std::fs::create_dir_all(path).map_err(|source| Error::CreateDir {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes `text` to the file `path`.
pub(super) fn write_text(path: &Path, text: &str) -> Result<(), Error> {
    std::fs::write(path, text).map_err(|source| Error::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// Writes `rows` as a CSV file with a header line (the fields of the rows' type).
pub(super) fn write_csv<T: serde::Serialize>(
    path: &Path,
    rows: impl IntoIterator<Item = T>,
) -> Result<(), Error> {
    let ctx = |source: csv::Error| Error::Csv {
        path: path.to_path_buf(),
        source,
    };
    let mut w = csv::Writer::from_path(path).map_err(ctx)?;
    for row in rows {
        w.serialize(row).map_err(ctx)?;
    }
    w.flush().map_err(|source| Error::Write {
        path: path.to_path_buf(),
        source,
    })
}

/// Where a render writes its files, and whether it shows progress: the arguments `noether
/// render` and `noether play` share.
#[derive(Debug, Args)]
pub struct OutputArgs {
    /// Output WAV (32-bit float) [default: out/<scene>.wav for a scene, out/play-<preset>.wav
    /// for a preset].
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// JSON report path [default: beside the WAV, <name>.json].
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Folder for the PNG figures (waveform and spectrogram; a scene's render adds its energy
    /// curves).
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// No progress bar.
    #[arg(long, short)]
    pub quiet: bool,
}

impl OutputArgs {
    /// The WAV and JSON report paths: `--output` or `out/<default_name>`, and `--report` or
    /// the WAV's path with the extension `json`. Creates the WAV's folder.
    pub fn wav_and_report(&self, default_name: &str) -> Result<(PathBuf, PathBuf), Error> {
        let wav = self
            .output
            .clone()
            .unwrap_or_else(|| Path::new("out").join(default_name));
        let report = self
            .report
            .clone()
            .unwrap_or_else(|| wav.with_extension("json"));
        if let Some(parent) = wav.parent().filter(|p| !p.as_os_str().is_empty()) {
            create_dir(parent)?;
        }
        Ok((wav, report))
    }

    /// A progress bar of 1000 steps (hidden with `--quiet`).
    pub fn progress_bar(&self) -> ProgressBar {
        let bar = if self.quiet {
            ProgressBar::hidden()
        } else {
            ProgressBar::new(1000)
        };
        // The template is a constant: it parses (the default bar would do otherwise).
        bar.set_style(
            ProgressStyle::with_template("{bar:40} {percent:>3}% elapsed {elapsed} eta {eta}")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar
    }
}
