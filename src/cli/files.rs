//! File output shared by the subcommands: errors name the path.

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

/// The WAV and JSON report paths of a command that writes both: `output` or
/// `out/<default_name>`, and `report` or the WAV's path with the extension `json`. Creates the
/// WAV's folder.
pub(super) fn wav_and_report(
    output: Option<&Path>,
    default_name: &str,
    report: Option<&Path>,
) -> Result<(PathBuf, PathBuf), Error> {
    let wav = output.map_or_else(|| Path::new("out").join(default_name), Path::to_path_buf);
    let report = report.map_or_else(|| wav.with_extension("json"), Path::to_path_buf);
    if let Some(parent) = wav.parent().filter(|p| !p.as_os_str().is_empty()) {
        create_dir(parent)?;
    }
    Ok((wav, report))
}
