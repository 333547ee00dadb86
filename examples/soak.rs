//! The long real-time soak: the driver of `tests/robustness/soak.rs`
//! (`noether_testkit::soak`) for as long as asked, with `assert_no_alloc` around every
//! `process_events` call (live in release too: this crate's dev-dependency turns off the crate's
//! `disable_release` feature, so an allocation inside `process` aborts the run).
//!
//! `cargo run --release --example soak -- --blocks 200000 --seed 7` (a fixed amount of work: the
//! seed names the same main sequence of blocks on any machine); `--help` lists the quality
//! limits (by default those of `tests/robustness/soak.rs`). Prints the summary (blocks, notes,
//! rebuilds, rate changes, worst block time over block duration, largest output level);
//! exits with code 1 and the failed check on failure.

use assert_no_alloc::{assert_no_alloc, AllocDisabler};
use clap::Parser;
use noether_testkit::soak::{self, SoakConfig};
use std::process::ExitCode;
use std::time::Duration;

#[global_allocator]
static A: AllocDisabler = AllocDisabler;

/// Soak the engine with random automation, note storms, rebuilds and host rate changes.
#[derive(Debug, Parser)]
struct Args {
    /// Blocks of the main sequence to play (blocks played while a rebuild is pending are not
    /// counted). The default, 20 times the test's, is about 20 minutes of audio and 5 to 8
    /// minutes of CPU (1.6 to 2.4 ms a block in the test profile).
    #[arg(long, default_value_t = 200_000, value_parser = clap::value_parser!(u64).range(1..))]
    blocks: u64,
    /// Safety timeout (s): a run still going after it fails. Default: 10 ms a block plus
    /// 2 minutes.
    #[arg(long)]
    wall_limit: Option<f64>,
    /// Seed of the random choices.
    #[arg(long, default_value_t = 7)]
    seed: u64,
    /// Mean note-ons per second of audio.
    #[arg(long, default_value_t = 300.0)]
    notes_per_second: f64,
    /// Largest number of modes a rebuild sets (table: 4..400).
    #[arg(long, value_parser = clap::value_parser!(u64).range(4..=400))]
    max_modes: Option<u64>,
    /// Largest number of in-plane modes a rebuild sets (table: 0..200).
    #[arg(long, value_parser = clap::value_parser!(u64).range(0..=200))]
    max_in_plane: Option<u64>,
    /// Largest polyphony a rebuild sets (table: 1..16).
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..=16))]
    max_polyphony: Option<u64>,
    /// Load budget: modes x polyphony x simulation rate (mode-steps per second of audio).
    #[arg(long)]
    budget: Option<f64>,
    /// Longest wait for a requested rebuild (s).
    #[arg(long, default_value_t = 60.0)]
    rebuild_timeout: f64,
}

fn main() -> ExitCode {
    let a = Args::parse();
    for (field, x) in [
        ("--wall-limit", a.wall_limit.unwrap_or(1.0)),
        ("--notes-per-second", a.notes_per_second),
        ("--rebuild-timeout", a.rebuild_timeout),
        ("--budget", a.budget.unwrap_or(1.0)),
    ] {
        if !(x.is_finite() && x > 0.0) {
            eprintln!("error: invalid value for `{field}`: {x} (allowed: finite number > 0)");
            return ExitCode::from(2);
        }
    }
    let mut cfg = SoakConfig::quick(a.seed, a.blocks);
    cfg.wall_limit = a.wall_limit.map_or(cfg.wall_limit, Duration::from_secs_f64);
    cfg.notes_per_second = a.notes_per_second;
    cfg.rebuild_timeout = Duration::from_secs_f64(a.rebuild_timeout);
    cfg.max_modes = a.max_modes.map_or(cfg.max_modes, |x| x as usize);
    cfg.max_in_plane = a.max_in_plane.map_or(cfg.max_in_plane, |x| x as usize);
    cfg.max_polyphony = a.max_polyphony.map_or(cfg.max_polyphony, |x| x as usize);
    cfg.budget = a.budget.unwrap_or(cfg.budget);
    println!("{cfg:?}");
    match soak::run(&cfg, |e, ev, l, r| {
        assert_no_alloc(|| e.process_events(ev, l, r))
    }) {
        Ok(s) => {
            println!("{s}");
            ExitCode::SUCCESS
        }
        Err(f) => {
            eprintln!("{f}");
            ExitCode::FAILURE
        }
    }
}
