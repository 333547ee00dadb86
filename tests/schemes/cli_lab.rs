//! The `noether lab` command line end to end: JSON summaries agree with closed forms, files are
//! written, bad arguments are refused with a message naming the argument and its range.

use std::process::Command;

fn noether(args: &[&str]) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_noether"))
        .args(args)
        .output()
        .expect("run noether");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn json(args: &[&str]) -> serde_json::Value {
    let (ok, stdout, stderr) = noether(args);
    assert!(ok, "{args:?} failed: {stderr}");
    serde_json::from_str(stdout.trim()).unwrap_or_else(|e| panic!("{e}: {stdout}"))
}

/// θ = 0.8 at h = 0.125: the measured frequency equals the closed form
/// `ω_d = arccos((1 - θh²ω0²/2)/(1 + (1-θ)h²ω0²/2))/h` and the energy is conserved, both to
/// round-off. Measured (printed): ω_d 4.2e-15 relative, cents 6.9e-12 absolute, energy 3.5e-15,
/// period 4.0e-15 relative (at ω h = 0.125 the degree-7 crossing interpolant is exact to
/// (ωh)⁸/8! ≈ 1e-12 of a period per crossing, divided by the 200 periods). Tolerances: 2e-14
/// relative on ω_d and the period, 3e-11 cents (1200/ln 2 × 2e-14), 2e-14 on the energy, about
/// five times each measured figure.
#[test]
fn theta_run_json_matches_the_closed_form() {
    let v = json(&[
        "lab",
        "run",
        "--scheme",
        "theta",
        "--theta",
        "0.8",
        "--h",
        "0.125",
        "--periods",
        "200",
        "--json",
        "--no-files",
    ]);
    let (h, w0, theta): (f64, f64, f64) = (0.125, 1.0, 0.8);
    let x = h * h * w0 * w0;
    let closed = ((1.0 - theta * x / 2.0) / (1.0 + (1.0 - theta) * x / 2.0)).acos() / h;
    let measured = v["omega_d"].as_f64().unwrap();
    let cents = v["cents"].as_f64().unwrap();
    let energy = v["max_rel_energy_error"].as_f64().unwrap();
    let period = v["period"].as_f64().unwrap();
    eprintln!(
        "theta 0.8 h 0.125: omega_d rel {:.2e}, cents abs {:.2e}, energy {energy:.2e}, period rel {:.2e}",
        measured / closed - 1.0,
        cents - 1200.0 * (closed / w0).log2(),
        period / (std::f64::consts::TAU / closed) - 1.0
    );
    assert!(
        (measured / closed - 1.0).abs() < 2e-14,
        "{measured} vs {closed}"
    );
    assert!((cents - 1200.0 * (closed / w0).log2()).abs() < 3e-11);
    assert!(energy < 2e-14, "{energy}");
    assert_eq!(v["steps"].as_u64().unwrap(), 10053);
    assert!((period / (std::f64::consts::TAU / closed) - 1.0).abs() < 2e-14);
}

/// Duffing: cents are measured against the exact nonlinear period 4K(m)/Ω; energy to
/// round-off. The conservative scheme's frequency error is O(h²): measured -6.0044 cents at
/// h = 0.0628 and -1.5060 at h/2 (ratio 3.987; -0.3768 at h/4, ratio 3.997 again). The
/// crossing measurement places ω to about 1e-12 relative (`analysis::frequency`: 2e-9 cents),
/// and the run is deterministic floating point, so the value is held to 1e-6 relative
/// (6e-6 cents, far above round-off and far below any change of the scheme). The halving
/// ratio is held to 4 ± 0.05: the next term, c(h) = C h² (1 + a h²), moves it to
/// 4 (1 + ¾ a h²), with a h² ≈ -4e-3 from the two measured ratios (shift -0.013).
#[test]
fn duffing_cents_are_against_the_exact_nonlinear_frequency() {
    let run = |h: &str| {
        let v = json(&[
            "lab",
            "run",
            "--scheme",
            "duffing-conservative",
            "--h",
            h,
            "--periods",
            "100",
            "--json",
            "--no-files",
        ]);
        assert!(v["omega_ref_kind"]
            .as_str()
            .unwrap()
            .contains("exact nonlinear"));
        assert!(v["max_rel_energy_error"].as_f64().unwrap() < 1e-12);
        v["cents"].as_f64().unwrap()
    };
    let (cents, half) = (run("0.0628"), run("0.0314"));
    println!(
        "cents at h = 0.0628: {cents:.6}; at h/2: {half:.6}; ratio {:.4}",
        cents / half
    );
    const MEASURED: f64 = -6.004_399;
    assert!(((cents - MEASURED) / MEASURED).abs() < 1e-6, "{cents}");
    assert!((cents / half - 4.0).abs() < 0.05, "{cents} / {half}");
}

#[test]
fn lab_writes_csv_json_and_plots() {
    let dir = std::env::temp_dir().join(format!("noether-cli-{}", std::process::id()));
    let d = dir.to_str().unwrap();
    let (ok, _, err) = noether(&["lab", "figure", "theta0-50", "--out", d]);
    assert!(ok, "{err}");
    for f in [
        "theta0-50.csv",
        "theta0-50.json",
        "theta0-50-waveform.png",
        "theta0-50-energy.png",
        "theta0-50-phase.png",
    ] {
        let len = std::fs::metadata(dir.join(f)).map(|m| m.len()).unwrap_or(0);
        assert!(len > 100, "{f}: {len} bytes");
    }
    let csv = std::fs::read_to_string(dir.join("theta0-50.csv")).unwrap();
    assert!(csv.starts_with("t,u,v,energy,dissipated,reference\n"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn table_lists_limits_and_frequencies() {
    let (ok, out, err) = noether(&[
        "lab", "table", "--h", "0.5", "--thetas", "0,0.5,1", "--json",
    ]);
    assert!(ok, "{err}");
    let rows: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(rows.as_array().unwrap().len(), 3);
    assert!(rows[0]["h_omega0_limit"].is_null());
    assert!((rows[2]["h_omega0_limit"].as_f64().unwrap() - 2.0).abs() < 1e-15);
}

#[test]
fn bad_arguments_name_the_field_and_range() {
    let cases: &[(&[&str], &[&str])] = &[
        (
            &[
                "lab",
                "run",
                "--scheme",
                "theta",
                "--theta",
                "1.5",
                "--no-files",
            ],
            &["theta", "1.5", "[0, 1]"],
        ),
        (
            &["lab", "run", "--scheme", "theta", "--h", "0", "--no-files"],
            &["h", "0"],
        ),
        (
            &["lab", "run", "--scheme", "theta", "--h", "abc"],
            &["--h", "abc"],
        ),
        (
            &[
                "lab",
                "run",
                "--scheme",
                "exact",
                "--xi",
                "-1",
                "--no-files",
            ],
            &["xi", "-1"],
        ),
        (
            &[
                "lab",
                "run",
                "--scheme",
                "impact",
                "--alpha",
                "0.2",
                "--no-files",
            ],
            &["alpha", "0.2"],
        ),
        (
            &[
                "lab",
                "run",
                "--scheme",
                "theta",
                "--periods",
                "1e12",
                "--no-files",
            ],
            &["periods"],
        ),
        (&["lab", "run", "--scheme", "warp"], &["warp"]),
        (
            &[
                "lab",
                "ndof",
                "--system",
                "fpu",
                "--method",
                "rk5",
                "--no-files",
            ],
            &["method", "rk5", "rk4"],
        ),
        (&["lab", "figure", "nope"], &["nope", "theta1-150"]),
        (&["lab", "table", "--thetas", "2"], &["theta", "2"]),
    ];
    for (args, fragments) in cases {
        let (ok, _, err) = noether(args);
        assert!(!ok, "{args:?} succeeded");
        for f in *fragments {
            assert!(err.contains(f), "{args:?}: `{err}` lacks `{f}`");
        }
    }
}

#[test]
fn every_subcommand_has_help() {
    for args in [
        &["--help"][..],
        &["lab", "--help"],
        &["lab", "run", "--help"],
        &["lab", "ndof", "--help"],
        &["lab", "table", "--help"],
        &["lab", "figure", "--help"],
        &["modes", "--help"],
    ] {
        let (ok, out, _) = noether(args);
        assert!(ok && out.contains("Usage"), "{args:?}");
    }
}

/// `noether modes`: the gong's first elastic modes are the (2,0) cos/sin pair (λ² = 5.3583 for
/// ν = 0.3, Leissa's free-plate table rounds to 5.36 at ν = 0.33 and our own root is checked to
/// 1e-13 in tests/modal_circular.rs); the lecture's 0.4 × 0.6 m plate has f_100 = 1400 Hz
/// (SEED.md 3.1, closed form π²((m/Lx)² + (n/Ly)²) √(D/ρh) / 2π, to the lecture's 4 digits).
#[test]
fn modes_lists_labels_and_frequencies() {
    let (ok, out, err) = noether(&[
        "modes",
        "--plate",
        "circular-free",
        "--count",
        "5",
        "--json",
    ]);
    assert!(ok, "{err}");
    let rows: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    assert_eq!(rows[0]["label"], "(2,0) cos");
    assert_eq!(rows[1]["label"], "(2,0) sin");
    assert!((rows[0]["lambda2"].as_f64().unwrap() - 5.35833).abs() < 1e-5);
    let (ok, out, err) = noether(&[
        "modes", "--plate", "rect-ss", "--lx", "0.4", "--aspect", "1.5", "--count", "100", "--json",
    ]);
    assert!(ok, "{err}");
    let rows: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
    let f100 = rows[99]["frequency_hz"].as_f64().unwrap();
    assert!((f100 - 1400.0).abs() < 1.0, "{f100}");
    let (ok, _, err) = noether(&["modes", "--plate", "rect-ss", "--aspect", "0"]);
    assert!(
        !ok && err.contains("--aspect") && err.contains("0"),
        "{err}"
    );
}
