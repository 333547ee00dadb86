//! `noether-test-host`: a small CLAP host built on `clack-host` that loads
//! `noether-plugin.clap`, lists its parameters, sets some of them, plays notes with MIDI
//! expression (pitch bend, mod wheel, sustain) and renders a stereo WAV; plus `check`, which reads
//! any WAV (ours, `jack_rec`'s, pedalboard's) and checks it is finite, non-silent, still sounding
//! at the note-off and decaying after it; `compare`, which checks that two renders of the same
//! notes at different rates and block sizes agree (level, spectrum below 9 kHz, strongest
//! partial); and `conform`, the validators' checks (activation at unusual rates, block sizes,
//! random and extreme parameters, state) on the CLAP build; `expression`, CLAP note expressions
//! and MPE bends measured from the sound. CI runs them through `.ci/plugin`.
//!
//! Everything runs on the main thread: the host calls `process` itself, block after block, which
//! is what an offline bounce in a DAW does.

mod args;
mod check;
mod compare;
mod conform;
mod conform_live;
mod conform_params;
mod conform_render;
mod expression;
mod expression_setup;
mod host;
mod host_render;
mod hostile;
mod polymod;
mod runner;
mod state_load;
#[cfg(test)]
mod testwav;

use std::process::ExitCode;

/// Command line of the test host.
#[derive(Debug)]
enum Command {
    /// `render PLUGIN.clap OUT.wav [options]`.
    Render(host_render::RenderOptions),
    /// `check FILE.wav --note-off SECONDS [--from-onset] [--min-peak X] [--max-peak X]
    /// [--min-level X]`.
    Check(check::CheckOptions),
    /// `compare A.wav B.wav [--seconds S] [--max-freq HZ] [--max-level-db X] [--max-lsd-db X]
    /// [--max-cents X]`.
    Compare(compare::CompareOptions),
    /// `conform PLUGIN.clap [--seed N] [--permutations N] [--only GROUP,...]`.
    Conform(conform::ConformOptions),
    /// `expression PLUGIN.clap STATE [--out DIR] [--break WHAT]`.
    Expression(expression::ExpressionOptions),
}

use args::usage;

fn parse_args(args: &[String]) -> Result<Command, String> {
    let (cmd, rest) = args.split_first().ok_or_else(|| usage().to_string())?;
    match cmd.as_str() {
        "render" => host_render::RenderOptions::parse(rest).map(Command::Render),
        "check" => check::CheckOptions::parse(rest).map(Command::Check),
        "compare" => compare::CompareOptions::parse(rest).map(Command::Compare),
        "conform" => conform::ConformOptions::parse(rest).map(Command::Conform),
        "expression" => expression::ExpressionOptions::parse(rest).map(Command::Expression),
        other => Err(format!("unknown command `{other}`\n{}", usage())),
    }
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = parse_args(&args).and_then(|cmd| match cmd {
        Command::Render(opts) => host_render::render(&opts),
        Command::Check(opts) => check::check(&opts),
        Command::Compare(opts) => compare::compare(&opts),
        Command::Conform(opts) => conform::conform(&opts),
        Command::Expression(opts) => expression::expression(&opts),
    });
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("noether-test-host: {e}");
            ExitCode::FAILURE
        }
    }
}
