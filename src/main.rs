//! The `noether` command-line tool: `noether --help` lists the commands.

mod cli;

fn main() -> std::process::ExitCode {
    // Like every Unix filter, end quietly when the reader of our output goes away
    // (`noether render ... --report /dev/stdout | head`): Rust ignores SIGPIPE by default, which
    // turns the next write into an error or a panic in `println!`.
    #[cfg(unix)]
    // SAFETY: called first thing, before any thread exists; only restores the default action.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    cli::main()
}
