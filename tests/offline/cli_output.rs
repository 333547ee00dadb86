//! The command line as a Unix filter: a report written to stdout is the only thing on stdout
//! (valid JSON; progress and summaries go to stderr), and a reader that closes the pipe early
//! ends the tool quietly (no panic message).

use std::io::Read;
use std::process::{Command, Stdio};

/// `noether render ... --report /dev/stdout`: stdout parses as one JSON report.
#[test]
fn report_on_stdout_is_valid_json() {
    let dir = std::env::temp_dir().join(format!("noether-cli-output-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_noether"))
        .args([
            "render",
            "assets/scenes/gong.toml",
            "-q",
            "--report",
            "/dev/stdout",
            "-o",
        ])
        .arg(dir.join("gong.wav"))
        .args(["--set", "output.seconds=0.02", "--set", "plate.n_phi=12"])
        .args(["--set", "plate.n_psi=4"])
        .env("NOETHER_CACHE", dir.join("cache"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "stdout is not one JSON document ({e}):\n{}",
            String::from_utf8_lossy(&out.stdout)
        )
    });
    assert_eq!(report["nan_count"], 0);
    // The summary went to stderr.
    assert!(stderr.contains("balance error"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A reader that stops after a few bytes (`noether modes ... | head -c 100`): the tool ends
/// by SIGPIPE like `cat` would, without a panic message.
#[cfg(unix)]
#[test]
fn closed_pipe_ends_quietly() {
    use std::os::unix::process::ExitStatusExt;
    let mut child = Command::new(env!("CARGO_BIN_EXE_noether"))
        .args(["modes", "--plate", "circular-free", "--count", "3000"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = [0u8; 100];
    child.stdout.take().unwrap().read_exact(&mut first).unwrap(); // then the pipe is dropped
    let mut stderr = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    let status = child.wait().unwrap();
    assert!(!stderr.contains("panicked"), "{stderr}");
    // 3000 modes print far more than the pipe buffer holds, so the tool did meet the closed
    // pipe: it must have been ended by SIGPIPE (13), not have exited with an error.
    assert_eq!(
        status.signal(),
        Some(13),
        "status {status:?}, stderr {stderr}"
    );
}
