//! The `mechanism` command-line tool.
fn main() {
    println!("mechanism: CLI under construction");
}
