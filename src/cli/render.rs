//! `noether render SCENE`: offline render of a scene file to WAV, JSON report and plots.

use super::files::OutputArgs;
use clap::Args;
use noether::render::auto::select;
use noether::render::report::write_plots;
use noether::render::scene::render_scene_on;
use noether::render::wav::{write_wav, WavFormat};
use noether::scene::Scene;
use noether::Error;
use std::path::PathBuf;

/// The scene `noether` renders when run without arguments.
pub const DEFAULT_SCENE: &str = "assets/scenes/gong.toml";

/// Arguments of `noether render`.
#[derive(Debug, Args)]
pub struct RenderArgs {
    /// Scene file (TOML), e.g. assets/scenes/gong.toml.
    pub scene: PathBuf,
    /// Output files and progress.
    #[command(flatten)]
    pub out: OutputArgs,
    /// Override a scene field by its dotted path, e.g. --set plate.excitation.peak_force=80
    /// (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub set: Vec<String>,
    /// Threads for one render (1 to 2; 0 = the machine's cores, at most 2): with 2, the step
    /// of a plate with the `sav` scheme and a large coupling tensor (at least 150 000 stored
    /// entries) is shared between two threads.
    #[arg(long, default_value_t = 0, value_parser = clap::value_parser!(u16).range(0..=2))]
    pub threads: u16,
}

/// Runs `noether render`.
pub fn run(a: RenderArgs) -> Result<(), Error> {
    let loaded = Scene::load(&a.scene, &a.set)?;
    // quality = "auto": choose and verify the reduced model first, then render it.
    let (scene, auto) = if loaded.is_auto() {
        eprintln!("quality = \"auto\": selecting the model of {}", loaded.name);
        let (r, reduced) = select(&loaded, |l| eprintln!("  {l}"))?;
        (reduced, Some(r))
    } else {
        (loaded, None)
    };
    let (wav, report_path) = a.out.wav_and_report(&format!("{}.wav", scene.name))?;
    eprintln!(
        "rendering {} ({} s at {} Hz output)",
        scene.name, scene.output.seconds, scene.output.sample_rate
    );
    let bar = a.out.progress_bar();
    let threads = match a.threads {
        0 => std::thread::available_parallelism().map_or(1, |n| n.get()),
        n => usize::from(n),
    };
    let (rendered, mut report) =
        render_scene_on(&scene, threads, |f| bar.set_position((f * 1000.0) as u64))?;
    report.auto = auto;
    bar.finish_and_clear();
    write_wav(
        &wav,
        &rendered.out,
        scene.output.sample_rate,
        WavFormat::Float32,
    )?;
    let json = serde_json::to_string_pretty(&report)?;
    super::files::write_text(&report_path, &(json + "\n"))?;
    eprintln!(
        "{}: {} s, scheme {}, N_phi = {}, N_psi = {}, sim {} Hz -> {} Hz",
        report.scene,
        report.seconds,
        report.scheme,
        report.n_phi,
        report.n_psi,
        report.sim_rate,
        report.sample_rate
    );
    eprintln!(
        "  energy: max {:.4e} J, drift {:.3e}, balance error {:.3e} (relative to max); nan {}",
        report.energy.max,
        report.energy.max_rel_drift,
        report.energy.max_balance_error,
        report.nan_count
    );
    eprintln!(
        "  peak {:.4e}, wall {:.2} s, real-time factor {:.3}",
        report.peak, report.wall_seconds, report.realtime_factor
    );
    if let Some(r) = &report.auto {
        super::auto::print_summary(r);
    }
    if let Some(c) = &report.contact {
        eprintln!(
            "  contact: max penetration {:.3e} m, Newton max {} iterations, {} failures (cap {}), histogram {:?}",
            c.max_penetration,
            c.newton_max_iterations,
            c.newton_failures,
            c.newton_cap,
            c.newton_histogram
        );
    }
    for w in &report.warnings {
        eprintln!("  warning: {w}");
    }
    eprintln!("  wrote {} and {}", wav.display(), report_path.display());
    if let Some(dir) = &a.out.plot {
        // The output holds only modal frequencies: show the model's band (a log axis up to
        // 1.25x its highest mode, so the band's top stays visible), capped at Nyquist.
        let f_max = report
            .details
            .get("f_max")
            .and_then(|v| v.as_f64())
            .unwrap_or(f64::INFINITY);
        for p in write_plots(
            dir,
            &scene.name,
            &rendered,
            report.sim_rate,
            scene.output.sample_rate,
            1.25 * f_max,
        )? {
            eprintln!("  wrote {}", p.display());
        }
    }
    if report.nan_count > 0 {
        return Err(Error::Diverged {
            non_finite: report.nan_count,
        });
    }
    Ok(())
}

/// The main job: render the default gong scene with its plots into `out/`.
pub fn run_default() -> Result<(), Error> {
    run(RenderArgs {
        scene: PathBuf::from(DEFAULT_SCENE),
        out: OutputArgs {
            output: None,
            report: None,
            plot: Some(PathBuf::from("out")),
            quiet: false,
        },
        set: Vec::new(),
        threads: 0,
    })
}
