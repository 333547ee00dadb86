//! File output shared by the subcommands: errors name the path.

use noether::Error;
use std::path::Path;

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
