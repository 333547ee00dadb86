//! The process environment the tests share.
//!
//! Tests of one binary run on parallel threads of one process and share its environment, so
//! changing a variable from a test (let alone from every proptest case) races with the tests
//! that read it. [`test_cache_dir`] sets `NOETHER_CACHE` once per process, before it returns
//! to any caller, and never again.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

static CACHE: OnceLock<PathBuf> = OnceLock::new();

/// The modal cache of the tests, `$TMPDIR/noether-test-cache` (so the tests neither read nor
/// fill the user's cache): on the first call `NOETHER_CACHE` is set to it for the whole
/// process; later calls (from any thread) wait for that and return the same path. Call it
/// before building anything that reads the cache (a circular plate); child processes
/// (`CARGO_BIN_EXE_noether`) inherit it.
pub fn test_cache_dir() -> &'static Path {
    CACHE.get_or_init(|| {
        let dir = std::env::temp_dir().join("noether-test-cache");
        // The only write to the environment in the test suites, done once under the lock of
        // `OnceLock`; std's own environment lock orders it against `std::env::var` readers.
        std::env::set_var("NOETHER_CACHE", &dir);
        dir
    })
}
