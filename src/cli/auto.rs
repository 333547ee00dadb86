//! `noether auto SCENE [--tolerance-db X] [--write reduced.toml]`: run the `quality = "auto"`
//! selection of a plate or string scene (whatever its `[quality]` table says) without
//! rendering the whole scene: print what was kept and why, the verified error and the
//! speed-up, and optionally write the reduced scene and the JSON of the selection. The work is
//! [`noether::render::auto::select`].

use clap::Args;
use noether::render::auto::{reduced_toml, select, AutoReport};
use noether::scene::Scene;
use noether::Error;
use std::path::PathBuf;

/// Arguments of `noether auto`.
#[derive(Debug, Args)]
pub struct AutoArgs {
    /// Scene file (TOML); its sizes (plate: n_phi, n_psi, symmetry; string: modes) and
    /// sim_rate are the full model.
    pub scene: PathBuf,
    /// Largest log-spectral distance to the full model, dB (sets quality.tolerance_db).
    #[arg(long, allow_negative_numbers = true)]
    pub tolerance_db: Option<f64>,
    /// Largest relative L2 error over the first 50 ms (sets quality.l2_tolerance).
    #[arg(long, allow_negative_numbers = true)]
    pub l2_tolerance: Option<f64>,
    /// Length of the verification renders in seconds (sets quality.excerpt_seconds).
    #[arg(long, allow_negative_numbers = true)]
    pub excerpt_seconds: Option<f64>,
    /// Write the reduced scene (TOML, no [quality] table) here.
    #[arg(long)]
    pub write: Option<PathBuf>,
    /// Write the selection (the report's `auto` section) as JSON here.
    #[arg(long)]
    pub report: Option<PathBuf>,
    /// Override a scene field by its dotted path (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub set: Vec<String>,
}

/// Prints the summary of a selection (shared with `noether render`).
pub fn print_summary(r: &AutoReport) {
    eprintln!(
        "  auto: {} of full {} ({}), LSD {:.4} dB (tolerance {} dB), L2(50 ms) {:.3e}, over {} s",
        r.chosen.label(),
        r.full.label(),
        if r.chosen_is_full {
            "no candidate passed: full model kept"
        } else {
            "verified"
        },
        r.lsd_db,
        r.tolerance_db,
        r.l2_50ms,
        r.excerpt_seconds
    );
    eprintln!(
        "  auto: excerpt wall {:.3} s full -> {:.3} s chosen (speed-up {:.2}); {} candidates tried, {} untried; selection took {:.2} s",
        r.full_wall_seconds,
        r.chosen_wall_seconds,
        r.speedup,
        r.candidates.len(),
        r.untried,
        r.selection_wall_seconds
    );
}

/// A float as a TOML literal (`nan`, `inf` and `-inf` included, so a non-finite value reaches
/// the scene's range check and its error names the field).
fn toml_float(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.into()
    } else {
        format!("{x:e}")
    }
}

/// Runs `noether auto`.
pub fn run(a: AutoArgs) -> Result<(), Error> {
    let mut set = vec!["quality.mode=auto".to_string()];
    if let Some(t) = a.tolerance_db {
        set.push(format!("quality.tolerance_db={}", toml_float(t)));
    }
    if let Some(t) = a.l2_tolerance {
        set.push(format!("quality.l2_tolerance={}", toml_float(t)));
    }
    if let Some(t) = a.excerpt_seconds {
        set.push(format!("quality.excerpt_seconds={}", toml_float(t)));
    }
    set.extend(a.set.iter().cloned());
    let scene = Scene::load(&a.scene, &set)?;
    let (report, reduced) = select(&scene, |l| eprintln!("  {l}"))?;
    for r in &report.reasons {
        eprintln!("  - {r}");
    }
    print_summary(&report);
    if let Some(path) = &a.write {
        let text = reduced_toml(&reduced, &report, &a.scene.display().to_string())?;
        super::files::write_text(path, &text)?;
        eprintln!("  wrote {}", path.display());
    }
    if let Some(path) = &a.report {
        let json = serde_json::to_string_pretty(&report)?;
        super::files::write_text(path, &(json + "\n"))?;
        eprintln!("  wrote {}", path.display());
    }
    Ok(())
}
