//! The `noether` command-line tool (being assembled).
fn main() {
    println!("noether {}", env!("CARGO_PKG_VERSION"));
}
