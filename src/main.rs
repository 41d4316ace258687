//! The `mechanism` command-line tool (see `mechanism --help`).
fn main() -> std::process::ExitCode {
    mechanism::cli::main_with_args(std::env::args_os())
}
