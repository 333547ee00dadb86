//! The conformance run's cases: each one runs, is timed in process CPU time and prints its
//! `PASS` or `FAIL` line; the run counts them (`conform.rs` and its groups in
//! `conform_live.rs` and `conform_params.rs`).

use crate::conform_render::process_cpu_seconds;

/// Counts the cases and prints each one's line.
#[derive(Debug, Default)]
pub(crate) struct Runner {
    /// Cases passed.
    pub passed: usize,
    /// Names of the cases failed.
    pub failed: Vec<String>,
}

impl Runner {
    /// Runs one case and prints `PASS name: figures [CPU]` or `FAIL name: why [CPU]`.
    pub(crate) fn case(&mut self, name: &str, f: impl FnOnce() -> Result<String, String>) {
        let c0 = process_cpu_seconds();
        let r = f();
        let cpu = process_cpu_seconds() - c0;
        match r {
            Ok(figures) => {
                self.passed += 1;
                println!("PASS {name}: {figures} [{cpu:.2} s CPU]");
            }
            Err(why) => {
                self.failed.push(name.to_string());
                println!("FAIL {name}: {why} [{cpu:.2} s CPU]");
            }
        }
    }
}
