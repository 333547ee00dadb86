//! `noether accuracy SCENE --vary rate|scheme --values a,b,c [--reference-rate R]`: render a
//! scene under several settings and against a reference, write a CSV and JSON table and a PNG of
//! the error against wall time. The metrics are those of [`noether::render::accuracy`]
//! (stated in docs/ACCURACY.md).

use clap::{Args, ValueEnum};
use noether::plot::{write_png, Mark, Panel, Scale, Series};
use noether::render::accuracy::{study_rate, study_scheme, AccuracyStudy};
use noether::scene::Scene;
use std::path::{Path, PathBuf};

/// The setting a study varies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Vary {
    /// The simulation rate (Hz); the reference is the same scene at `--reference-rate`.
    Rate,
    /// The string's contact scheme (newton, quadratised), each at every `--values` rate (Hz);
    /// the reference is the Newton scheme at `--reference-rate`. String scenes only.
    Scheme,
}

/// Arguments of `noether accuracy`.
#[derive(Debug, Args)]
pub struct AccuracyArgs {
    /// Scene file (TOML).
    pub scene: PathBuf,
    /// Which setting to vary.
    #[arg(long, value_enum)]
    pub vary: Vary,
    /// The values to render, comma separated (for `rate` and `scheme`: simulation rates in Hz).
    #[arg(long, value_delimiter = ',', required = true)]
    pub values: Vec<f64>,
    /// Simulation rate of the reference render (Hz) [default: twice the largest value].
    #[arg(long)]
    pub reference_rate: Option<f64>,
    /// Override a scene field by its dotted path (repeatable), e.g. --set output.seconds=0.2.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub set: Vec<String>,
    /// Folder for the table and the figure.
    #[arg(long, default_value = "out/accuracy")]
    pub out: PathBuf,
}

/// Runs `noether accuracy`.
pub fn run(a: AccuracyArgs) -> Result<(), String> {
    let scene = Scene::load(&a.scene, &a.set).map_err(|e| e.to_string())?;
    if a.values.is_empty() || a.values.iter().any(|v| !v.is_finite() || *v <= 0.0) {
        return Err(format!(
            "invalid value for `--values`: {:?} (allowed: positive finite numbers)",
            a.values
        ));
    }
    let study = match a.vary {
        Vary::Rate => {
            let top = a.values.iter().copied().fold(0.0, f64::max);
            let reference = a.reference_rate.unwrap_or(2.0 * top);
            eprintln!(
                "accuracy of {} against sim_rate {} Hz ({} s)",
                scene.name, reference, scene.output.seconds
            );
            study_rate(&scene, &a.values, reference, |l| eprintln!("  {l}"))?
        }
        Vary::Scheme => {
            let top = a.values.iter().copied().fold(0.0, f64::max);
            let reference = a.reference_rate.unwrap_or(2.0 * top);
            eprintln!(
                "accuracy of each contact scheme of {} against newton at sim_rate {} Hz ({} s)",
                scene.name, reference, scene.output.seconds
            );
            study_scheme(&scene, &a.values, reference, |l| eprintln!("  {l}"))?
        }
    };
    std::fs::create_dir_all(&a.out).map_err(|e| format!("creating {}: {e}", a.out.display()))?;
    let stem = a
        .out
        .join(format!("{}-accuracy-{}", study.scene, study.vary));
    let csv_path = stem.with_extension("csv");
    write_csv(&csv_path, &study)?;
    let json_path = stem.with_extension("json");
    let json = serde_json::to_string_pretty(&study).map_err(|e| e.to_string())?;
    std::fs::write(&json_path, json + "\n")
        .map_err(|e| format!("writing {}: {e}", json_path.display()))?;
    let png_path = stem.with_extension("png");
    write_figure(&png_path, &study)?;
    println!(
        "reference: {} ({:.2} s wall, balance error {:.2e})",
        study.reference, study.reference_wall_seconds, study.reference_energy_balance_error
    );
    println!(
        "{:>12} {:>12} {:>10} {:>12} {:>10} {:>12}",
        "value", "scheme", "wall (s)", "L2 (50 ms)", "LSD (dB)", "balance err"
    );
    for r in &study.rows {
        println!(
            "{:>12} {:>12} {:>10.3} {:>12.3e} {:>10.3} {:>12.2e}",
            r.value,
            r.scheme.as_deref().unwrap_or("-"),
            r.wall_seconds,
            r.l2_50ms,
            r.lsd_db,
            r.energy_balance_error
        );
    }
    for p in [&csv_path, &json_path, &png_path] {
        println!("  wrote {}", p.display());
    }
    Ok(())
}

fn write_csv(path: &Path, study: &AccuracyStudy) -> Result<(), String> {
    let ctx = |e: csv::Error| format!("writing {}: {e}", path.display());
    let mut w = csv::Writer::from_path(path).map_err(ctx)?;
    for row in &study.rows {
        w.serialize(row).map_err(ctx)?;
    }
    w.flush()
        .map_err(|e| format!("writing {}: {e}", path.display()))
}

fn write_figure(path: &Path, study: &AccuracyStudy) -> Result<(), String> {
    // One curve per scheme in a `scheme` study (rows carry the scheme), one curve otherwise.
    let mut groups: Vec<Option<String>> = Vec::new();
    for r in &study.rows {
        if !groups.contains(&r.scheme) {
            groups.push(r.scheme.clone());
        }
    }
    let unit = if study.vary == "rate" || study.vary == "scheme" {
        " (Hz)"
    } else {
        ""
    };
    let axis = if study.vary == "scheme" {
        "sim_rate".to_string()
    } else {
        study.vary.clone()
    };
    let mut panels = [
        Panel::new(
            "waveform error against cost",
            "wall time (s)",
            "relative L2, first 50 ms",
        )
        .scales(Scale::Log10, Scale::Log10),
        Panel::new(
            "spectral error against cost",
            "wall time (s)",
            "log-spectral distance (dB)",
        )
        .scales(Scale::Log10, Scale::Log10),
        Panel::new(
            "errors against the setting",
            format!("{axis}{unit}"),
            "error",
        )
        .scales(Scale::Log10, Scale::Log10),
    ];
    for g in &groups {
        let rows: Vec<_> = study.rows.iter().filter(|r| &r.scheme == g).collect();
        let wall: Vec<f64> = rows.iter().map(|r| r.wall_seconds).collect();
        let value: Vec<f64> = rows.iter().map(|r| r.value).collect();
        let l2: Vec<f64> = rows.iter().map(|r| r.l2_50ms).collect();
        let lsd: Vec<f64> = rows.iter().map(|r| r.lsd_db).collect();
        let tag = g.as_deref().map(|s| format!(" {s}")).unwrap_or_default();
        let [a, b, c] = panels;
        panels = [
            a.push(
                Series::line(format!("L2{tag}"), wall.clone(), l2.clone())
                    .with_mark(Mark::LinePoints),
            ),
            b.push(
                Series::line(format!("LSD{tag}"), wall, lsd.clone()).with_mark(Mark::LinePoints),
            ),
            c.push(
                Series::line(format!("L2 (50 ms){tag}"), value.clone(), l2)
                    .with_mark(Mark::LinePoints),
            )
            .push(Series::line(format!("LSD (dB){tag}"), value, lsd).with_mark(Mark::LinePoints)),
        ];
    }
    write_png(
        path,
        &format!(
            "{}: accuracy against {} (reference: {})",
            study.scene, study.vary, study.reference
        ),
        &panels,
        3,
        (560, 420),
    )
    .map_err(|e| e.to_string())
}
