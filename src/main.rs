//! The `noether` command-line tool.
fn main() {
    println!("noether {}", env!("CARGO_PKG_VERSION"));
}
