//! `noether stress`: the extremes sweep of `tests/robustness/extremes.rs`, denser and longer, with the
//! summary table (runs, refusals, failures, worst energy error per family).

use clap::{Args, ValueEnum};
use noether::stress::{self, Density, Status};
use noether::Error;

/// Which families to sweep.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum FamilyArg {
    /// Every family.
    All,
    /// One-oscillator schemes (theta, exact, Duffing, impact).
    Oscillators,
    /// Plates (circular free/clamped, rectangular; every scheme).
    Plates,
    /// Stiff string with every obstacle kind.
    Strings,
}

/// Arguments of `noether stress`.
#[derive(Debug, Args)]
pub struct StressArgs {
    /// Families to sweep.
    #[arg(long, value_enum, default_value_t = FamilyArg::All)]
    pub only: FamilyArg,
    /// Run the bounded sweep of `cargo test` instead of the full one.
    #[arg(long)]
    pub quick: bool,
    /// Also list every refused (conditionally unstable) setting and every detected divergence.
    #[arg(long)]
    pub show_refused: bool,
}

/// Runs the sweep, prints the table; an error (exit code 2) when any case failed.
pub fn run(args: StressArgs) -> Result<(), Error> {
    let density = if args.quick {
        Density::Quick
    } else {
        Density::Full
    };
    let cases = match args.only {
        FamilyArg::All => stress::all_cases(density),
        FamilyArg::Oscillators => stress::oscillators::cases(density),
        FamilyArg::Plates => stress::plate::cases(density),
        FamilyArg::Strings => stress::string::cases(density),
    };
    let start = std::time::Instant::now();
    let (outcomes, summary) = stress::run(cases, |done, total| {
        if done % 50 == 0 || done == total {
            eprint!("\r{done}/{total} cases");
        }
    });
    eprintln!();
    if args.show_refused {
        for o in &outcomes {
            match &o.status {
                Status::Refused(why) => println!("refused [{}] {}: {why}", o.family, o.label),
                Status::Diverged(why) => println!("diverged [{}] {}: {why}", o.family, o.label),
                _ => {}
            }
        }
    }
    print!("{}", summary.table());
    println!(
        "{} cases in {:.1} s (energy tolerance {:e})",
        outcomes.len(),
        start.elapsed().as_secs_f64(),
        stress::ENERGY_TOLERANCE
    );
    match summary.failure_count() {
        0 => Ok(()),
        count => Err(Error::StressFailures { count }),
    }
}
