//! Bad command lines: missing and truncated scene files, malformed and out-of-range
//! `--set` values, conditionally unstable lab settings. Each must exit with failure (status 2
//! for refused input) and an error naming the file, field or argument, never panic.

use std::process::Command;

fn noether(args: &[&str]) -> (Option<i32>, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_noether"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .env("NOETHER_CACHE", noether_testkit::env::test_cache_dir())
        .output()
        .expect("run noether");
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
    (out.status.code(), stderr)
}

/// Runs `args`, expects exit status 2 and every fragment in stderr.
fn refused(args: &[&str], fragments: &[&str]) {
    let (code, stderr) = noether(args);
    assert_eq!(code, Some(2), "{args:?}: {stderr}");
    for f in fragments {
        assert!(stderr.contains(f), "{args:?}: `{f}` not in: {stderr}");
    }
}

const GONG: &str = "assets/scenes/gong.toml";

#[test]
fn missing_scene_file_names_the_path() {
    refused(
        &["render", "no/such/scene.toml", "-q"],
        &["reading scene", "no/such/scene.toml"],
    );
}

#[test]
fn truncated_scene_file_names_the_location() {
    let text = std::fs::read_to_string(GONG).unwrap();
    let dir = std::env::temp_dir().join(format!("noether-cli-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Cut inside the `excitation = { ... }` inline table: a TOML syntax error with a location.
    let cut = text.find("duration").unwrap();
    let path = dir.join("truncated.toml");
    std::fs::write(&path, &text[..cut]).unwrap();
    refused(
        &["render", path.to_str().unwrap(), "-q"],
        &["truncated.toml", "line"],
    );
    // Cut before the excitation field: the scene is syntactically fine but incomplete.
    let cut = text.find("excitation").unwrap();
    std::fs::write(&path, &text[..cut]).unwrap();
    refused(&["render", path.to_str().unwrap(), "-q"], &["excitation"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_set_values_name_the_field() {
    let cases: &[(&str, &[&str])] = &[
        ("plate.n_phi=abc", &["plate.n_phi"]),
        ("plate.n_phi=1e400", &["plate.n_phi"]),
        ("plate.n_phi=-5", &["plate.n_phi"]),
        ("plate.n_phi=999999999", &["plate.n_phi", "1 to 4000"]),
        ("plate.thickness=nan", &["plate.thickness", "NaN"]),
        ("plate.thickness=-inf", &["plate.thickness", "-inf"]),
        ("plate.radius=0", &["plate.radius", "0.01"]),
        ("plate.sim_rate=1e300", &["plate.sim_rate"]),
        ("plate.scheme=runge-kutta", &["plate.scheme", "runge-kutta"]),
        ("plate.bogus=1", &["bogus"]),
        ("plate.radius.x=1", &["invalid --set", "plate.radius"]),
        ("=3", &["invalid --set"]),
        ("plate.radius", &["invalid --set", "dotted.path=value"]),
        ("output.sample_rate=-48000", &["output.sample_rate"]),
    ];
    for (set, fragments) in cases {
        refused(&["render", GONG, "-q", "--set", set], fragments);
    }
}

#[test]
fn unstable_lab_settings_are_refused() {
    // θ = 1 at h ω0 = 3 > 2: the explicit scheme would explode.
    refused(
        &[
            "lab",
            "run",
            "--scheme",
            "theta",
            "--theta",
            "1",
            "--omega0",
            "1",
            "--h",
            "3",
            "--periods",
            "10",
        ],
        &["`h`", "3", "theta"],
    );
    // Störmer-Verlet on Duffing: linearly stable step, but the amplitude makes it explode.
    refused(
        &[
            "lab",
            "run",
            "--scheme",
            "duffing-verlet",
            "--omega0",
            "1",
            "--gamma",
            "1e4",
            "--u0",
            "10",
            "--h",
            "0.1",
            "--periods",
            "10",
        ],
        &["`u0`", "10", "Störmer-Verlet"],
    );
    refused(
        &[
            "lab",
            "run",
            "--scheme",
            "theta",
            "--h",
            "nan",
            "--periods",
            "1",
        ],
        &["h", "NaN"],
    );
}
