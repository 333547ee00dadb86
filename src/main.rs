//! The `noether` command-line tool: `noether --help` lists the commands.

mod cli;

fn main() -> std::process::ExitCode {
    cli::main()
}
