//! The `mechanism` command-line tool (see `mechanism --help`): argument parsing, loading a
//! mechanism by name or file, and the `list`, `equations`, `simulate`, `inverse` and
//! `import` commands, on top of the library's public API.
mod cli;

#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> std::process::ExitCode {
    cli::main_with_args(std::env::args_os())
}
