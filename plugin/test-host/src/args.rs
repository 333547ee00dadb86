//! The command line's usage text and the helpers that read an option's value (a number, a
//! path), naming the option on failure.

use std::path::PathBuf;

/// The command line's usage text (every command and option).
pub(crate) fn usage() -> &'static str {
    "usage:\n  noether-test-host render PLUGIN.clap OUT.wav [--rate HZ] [--block N] [--seconds S]\n      \
     [--note-off S] [--key K]... [--velocity V] [--set NAME=VALUE]... [--state-roundtrip] [--hostile-automation]\n      \
     [--load-state FILE [--expect-load ok|refused] [--expect NAME=VALUE]...]\n  \
     noether-test-host check FILE.wav --note-off S [--from-onset] [--min-peak X] [--max-peak X] [--min-level X]\n  \
     noether-test-host compare A.wav B.wav [--seconds S] [--max-freq HZ] [--max-level-db X] [--max-lsd-db X] [--max-cents X]\n  \
     noether-test-host conform PLUGIN.clap [--seed N] [--permutations N] [--only GROUP[,GROUP...]]\n  \
     noether-test-host expression PLUGIN.clap STATE [--out DIR] [--break tuning|volume|mpe-config|member-bend|poly-mod|note-off|pressure]"
}

/// Parses `value` for option `name` as a number, naming both on failure.
pub(crate) fn parse_num<T: std::str::FromStr>(
    name: &str,
    value: Option<&String>,
) -> Result<T, String> {
    let value = value.ok_or_else(|| format!("{name} needs a value"))?;
    value
        .parse()
        .map_err(|_| format!("{name}: `{value}` is not a valid number"))
}

/// Returns a path argument.
pub(crate) fn path_arg(name: &str, value: Option<&String>) -> Result<PathBuf, String> {
    value
        .map(PathBuf::from)
        .ok_or_else(|| format!("missing {name}\n{}", usage()))
}
