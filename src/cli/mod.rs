//! Command-line interface of the `noether` binary (argument parsing and dispatch only; the
//! work is done by the library).

mod accuracy;
mod accuracy_bands;
mod auto;
mod files;
mod glide;
mod lab;
mod modes;
mod play;
mod render;
mod stress;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

/// Noether: physical-model sound synthesis with energy-conserving schemes.
#[derive(Debug, Parser)]
#[command(name = "noether", version, about, long_about = None)]
pub struct Cli {
    /// What to do (default: render assets/scenes/gong.toml with its plots into `out/`).
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// Top-level subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// The integrator lab: the lecture's experiments on one oscillator and on N-DOF systems.
    Lab(lab::LabArgs),
    /// Play a factory or user preset through the real-time engine, headless, as the plugin
    /// plays it: notes or a MIDI file to WAV, a JSON report (per-note model, CPU load) and
    /// (with --plot) PNG figures.
    Play(play::PlayArgs),
    /// Render a scene file offline to WAV, a JSON report and (with --plot) PNG figures.
    Render(render::RenderArgs),
    /// Measure accuracy against cost: render a scene under several settings (e.g. simulation
    /// rates) and against a reference; write a table and a PNG of error against wall time.
    Accuracy(accuracy::AccuracyArgs),
    /// Choose the cheapest plate model within a tolerance of the scene's (quality = "auto"),
    /// verified against it on a short excerpt; print why, optionally write the reduced scene.
    Auto(auto::AutoArgs),
    /// Measure the pitch glide of one partial of a WAV file in Hz/s (the opera gongs' rising
    /// or falling fundamental), with a PNG of its track and a zoomed spectrogram.
    Glide(glide::GlideArgs),
    /// List a plate's transverse modes: labels, dimensionless lambda^2, frequencies in Hz.
    Modes(modes::ModesArgs),
    /// Sweep every model and scheme over extreme parameters and print the summary table.
    Stress(stress::StressArgs),
}

/// Parses the process arguments and runs the command.
pub fn main() -> ExitCode {
    let cli = Cli::parse();
    // Offline, nothing waits on the audio thread: tuning a tanpura or a sitar by ear may
    // take every core (a plugin leaves one to its audio thread).
    if let Ok(cores) = std::thread::available_parallelism() {
        noether::models::tanpura::tune::set_tuning_threads(cores.get());
    }
    let result = match cli.command {
        Some(Command::Accuracy(args)) => accuracy::run(args),
        Some(Command::Auto(args)) => auto::run(args),
        Some(Command::Glide(args)) => glide::run(args),
        Some(Command::Lab(args)) => lab::run(args),
        Some(Command::Modes(args)) => modes::run(args),
        Some(Command::Play(args)) => play::run(args),
        Some(Command::Render(args)) => render::run(args),
        Some(Command::Stress(args)) => stress::run(args),
        None => render::run_default(),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(2)
        }
    }
}
