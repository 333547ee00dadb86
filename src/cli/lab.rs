//! `noether lab ...`: run, figure, figures, ndof, table.

use clap::{Args, Subcommand, ValueEnum};
use noether::lab::figures::{self, Experiment};
use noether::lab::report::write_report;
use noether::lab::table::{format_table, theta_table};
use noether::lab::{Duration, NdofExperiment, OscillatorExperiment, Summary, Trace};
use noether::schemes::ndof::SystemSpec;
use noether::schemes::OscillatorSpec;
use noether::{Error, ParamError};
use std::path::{Path, PathBuf};

/// Arguments of `noether lab`.
#[derive(Debug, Args)]
pub struct LabArgs {
    /// Lab subcommand.
    #[command(subcommand)]
    pub command: LabCommand,
}

/// Lab subcommands.
#[derive(Debug, Subcommand)]
pub enum LabCommand {
    /// Run one oscillator scheme (theta-family, exact, Duffing, impact) and report it.
    Run(RunArgs),
    /// Run an N-degree-of-freedom system (FPU chain, pendulum, linear chain) with one method.
    Ndof(NdofArgs),
    /// Print the theta-family table: stability limit, omega_d and cents for a list of theta.
    Table(TableArgs),
    /// Reproduce one of the lecture's illustrations by name (`--list` shows them).
    Figure(FigureArgs),
    /// Reproduce every lecture illustration into one folder.
    Figures(OutArgs),
}

/// One-oscillator schemes.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum SchemeArg {
    /// theta-family for the linear oscillator (SEED 1.1).
    Theta,
    /// Exact scheme, undamped or damped (SEED 1.2).
    Exact,
    /// Stormer-Verlet on Duffing (not energy conserving).
    DuffingVerlet,
    /// Conservative (theta1, theta2) Duffing family (SEED 1.3).
    DuffingConservative,
    /// Impact oscillator with the discrete-gradient contact force (SEED 1.4).
    Impact,
}

/// Output options shared by the lab commands.
#[derive(Debug, Args)]
pub struct OutArgs {
    /// Folder for the CSV, JSON and PNG files.
    #[arg(long, default_value = "out/lab")]
    pub out: PathBuf,
    /// Print the summary as one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    /// Write no files (summary only).
    #[arg(long)]
    pub no_files: bool,
}

/// Duration options.
#[derive(Debug, Args)]
pub struct DurationArgs {
    /// Duration in periods of the linear natural frequency 2*pi/omega0 (default 50).
    #[arg(long, conflicts_with = "seconds")]
    pub periods: Option<f64>,
    /// Duration in time units (seconds).
    #[arg(long)]
    pub seconds: Option<f64>,
}

impl DurationArgs {
    fn get(&self) -> Duration {
        match (self.periods, self.seconds) {
            (_, Some(s)) => Duration::Seconds(s),
            (Some(p), None) => Duration::Periods(p),
            (None, None) => Duration::Periods(50.0),
        }
    }
}

/// Arguments of `noether lab run`.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub struct RunArgs {
    /// Scheme to run.
    #[arg(long, value_enum)]
    pub scheme: SchemeArg,
    /// Natural angular frequency omega0 (rad per time unit), > 0.
    #[arg(long, default_value_t = 1.0)]
    pub omega0: f64,
    /// theta of the theta-family (also the linear part of the impact scheme), in [0, 1].
    #[arg(long, default_value_t = 1.0)]
    pub theta: f64,
    /// Damping ratio xi of the exact scheme, >= 0 (1 = critical).
    #[arg(long, default_value_t = 0.0)]
    pub xi: f64,
    /// Duffing cubic coefficient gamma, >= 0.
    #[arg(long, default_value_t = 5.0)]
    pub gamma: f64,
    /// Duffing theta1 (linear part), in [0, 1].
    #[arg(long, default_value_t = 0.8)]
    pub theta1: f64,
    /// Duffing theta2 (1 explicit, < 1 implicit cubic), in [0, 1].
    #[arg(long, default_value_t = 1.0)]
    pub theta2: f64,
    /// Impact: mass m, > 0.
    #[arg(long, default_value_t = 1.0)]
    pub mass: f64,
    /// Impact: linear spring stiffness k, >= 0.
    #[arg(long, default_value_t = 1.0)]
    pub stiffness: f64,
    /// Impact: contact stiffness K, > 0.
    #[arg(long = "contact-stiffness", short = 'K', default_value_t = 1e13)]
    pub contact_stiffness: f64,
    /// Impact: contact exponent alpha.
    #[arg(long, default_value_t = 1.5)]
    pub alpha: f64,
    /// Impact: distance d from rest to the wall.
    #[arg(long = "gap", short = 'd', default_value_t = 0.5)]
    pub gap: f64,
    /// Time step h (time units), > 0.
    #[arg(long, default_value_t = 0.125)]
    pub h: f64,
    /// Initial displacement u0.
    #[arg(long, default_value_t = 1.0)]
    pub u0: f64,
    /// Initial velocity v0.
    #[arg(long, default_value_t = 0.0)]
    pub v0: f64,
    /// Duration.
    #[command(flatten)]
    pub duration: DurationArgs,
    /// Output.
    #[command(flatten)]
    pub out: OutArgs,
}

/// N-DOF test systems.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum SystemArg {
    /// Chain of masses with linear + cubic springs between fixed walls.
    Fpu,
    /// Simple pendulum H = p^2/2 - omega0^2 cos q.
    Pendulum,
    /// Chain of masses with linear springs.
    LinearChain,
}

/// Arguments of `noether lab ndof`.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub struct NdofArgs {
    /// Test system.
    #[arg(long, value_enum)]
    pub system: SystemArg,
    /// Method: stormer-verlet, midpoint, heun, rk4, rk38, gauss1, gauss2.
    #[arg(long, default_value = "stormer-verlet")]
    pub method: String,
    /// Chain: number of masses, >= 1.
    #[arg(long, default_value_t = 8)]
    pub n: usize,
    /// Chain: linear spring stiffness k, > 0.
    #[arg(long, default_value_t = 1.0)]
    pub k: f64,
    /// FPU: cubic spring coefficient beta, >= 0.
    #[arg(long, default_value_t = 1.0)]
    pub beta: f64,
    /// Pendulum: small-angle angular frequency omega0, > 0.
    #[arg(long, default_value_t = 1.0)]
    pub omega0: f64,
    /// Time step h, > 0.
    #[arg(long, default_value_t = 0.1)]
    pub h: f64,
    /// Initial amplitude (pendulum angle, or amplitude of the chain's lowest mode shape).
    #[arg(long, default_value_t = 1.0)]
    pub amplitude: f64,
    /// Initial momentum scale.
    #[arg(long, default_value_t = 0.0)]
    pub momentum: f64,
    /// Duration.
    #[command(flatten)]
    pub duration: DurationArgs,
    /// Output.
    #[command(flatten)]
    pub out: OutArgs,
}

/// Arguments of `noether lab table`.
#[derive(Debug, Args)]
#[command(allow_negative_numbers = true)]
pub struct TableArgs {
    /// Time step h, > 0.
    #[arg(long, default_value_t = 0.125)]
    pub h: f64,
    /// Natural angular frequency omega0, > 0.
    #[arg(long, default_value_t = 1.0)]
    pub omega0: f64,
    /// Comma-separated theta values in [0, 1].
    #[arg(long, value_delimiter = ',', default_values_t = [0.0, 0.25, 0.5, 0.6, 0.8, 1.0])]
    pub thetas: Vec<f64>,
    /// Print JSON instead of text.
    #[arg(long)]
    pub json: bool,
}

/// Arguments of `noether lab figure`.
#[derive(Debug, Args)]
pub struct FigureArgs {
    /// Illustration name (see --list).
    #[arg(required_unless_present = "list")]
    pub name: Option<String>,
    /// List the illustrations and exit.
    #[arg(long)]
    pub list: bool,
    /// Output.
    #[command(flatten)]
    pub out: OutArgs,
}

/// Runs `noether lab ...`.
pub fn run(args: LabArgs) -> Result<(), Error> {
    match args.command {
        LabCommand::Run(a) => {
            let exp = oscillator_experiment(&a);
            let run = exp.run()?;
            emit(&run.trace, &run.summary, &a.out, exp.spec.scheme_name())
        }
        LabCommand::Ndof(a) => {
            let exp = ndof_experiment(&a);
            let (trace, summary) = exp.run()?;
            emit(
                &trace,
                &summary,
                &a.out,
                &format!("{}-{}", summary.system, summary.scheme),
            )
        }
        LabCommand::Table(a) => {
            let rows = theta_table(a.h, a.omega0, &a.thetas)?;
            if a.json {
                println!("{}", serde_json::to_string(&rows)?);
            } else {
                print!("{}", format_table(a.h, a.omega0, &rows));
            }
            Ok(())
        }
        LabCommand::Figure(a) => {
            if a.list {
                for f in figures::all() {
                    println!("{:<22} {}", f.name, f.caption);
                }
                return Ok(());
            }
            let name = a.name.unwrap_or_default();
            let fig = figures::find(&name).ok_or_else(|| {
                let names: Vec<_> = figures::all().iter().map(|f| f.name).collect();
                ParamError::new("NAME", &name, names.join(", "))
            })?;
            run_figure(&fig, &a.out)
        }
        LabCommand::Figures(out) => run_all_figures(&out.out),
    }
}

/// Runs every lecture illustration into `dir`.
pub fn run_all_figures(dir: &Path) -> Result<(), Error> {
    let out = OutArgs {
        out: dir.to_path_buf(),
        json: false,
        no_files: false,
    };
    for fig in figures::all() {
        eprintln!("== {}: {}", fig.name, fig.caption);
        run_figure(&fig, &out)?;
    }
    eprintln!("figures written to {}", dir.display());
    Ok(())
}

fn run_figure(fig: &figures::Figure, out: &OutArgs) -> Result<(), Error> {
    let (trace, summary) = match &fig.experiment {
        Experiment::Oscillator(e) => {
            let r = e.run()?;
            (r.trace, r.summary)
        }
        Experiment::Ndof(e) => e.run()?,
    };
    emit(&trace, &summary, out, fig.name)
}

fn emit(trace: &Trace, summary: &Summary, out: &OutArgs, stem: &str) -> Result<(), Error> {
    if out.json {
        println!("{}", serde_json::to_string(summary)?);
    } else {
        print!("{}", summary.to_text());
    }
    if !out.no_files {
        let written = write_report(&out.out, stem, trace, summary)?;
        if !out.json {
            for f in written.files {
                eprintln!("  wrote {}", f.display());
            }
        }
    }
    Ok(())
}

fn oscillator_experiment(a: &RunArgs) -> OscillatorExperiment {
    let spec = match a.scheme {
        SchemeArg::Theta => OscillatorSpec::Theta {
            omega0: a.omega0,
            theta: a.theta,
        },
        SchemeArg::Exact => OscillatorSpec::Exact {
            omega0: a.omega0,
            xi: a.xi,
        },
        SchemeArg::DuffingVerlet => OscillatorSpec::DuffingVerlet {
            omega0: a.omega0,
            gamma: a.gamma,
        },
        SchemeArg::DuffingConservative => OscillatorSpec::DuffingConservative {
            omega0: a.omega0,
            gamma: a.gamma,
            theta1: a.theta1,
            theta2: a.theta2,
        },
        SchemeArg::Impact => OscillatorSpec::Impact {
            mass: a.mass,
            stiffness: a.stiffness,
            contact_stiffness: a.contact_stiffness,
            alpha: a.alpha,
            gap: a.gap,
            theta: a.theta,
        },
    };
    OscillatorExperiment {
        spec,
        h: a.h,
        u0: a.u0,
        v0: a.v0,
        duration: a.duration.get(),
    }
}

fn ndof_experiment(a: &NdofArgs) -> NdofExperiment {
    let system = match a.system {
        SystemArg::Fpu => SystemSpec::Fpu {
            n: a.n,
            k: a.k,
            beta: a.beta,
        },
        SystemArg::Pendulum => SystemSpec::Pendulum { omega0: a.omega0 },
        SystemArg::LinearChain => SystemSpec::LinearChain { n: a.n, k: a.k },
    };
    NdofExperiment {
        system,
        method: a.method.clone(),
        h: a.h,
        amplitude: a.amplitude,
        momentum: a.momentum,
        duration: a.duration.get(),
    }
}
