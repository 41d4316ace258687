//! The `mechanism` command-line tool (see `mechanism --help`): argument parsing, loading a
//! mechanism by name or file, and the `list`, `equations`, `simulate`, `inverse` and
//! `import` commands, on top of the library's public API.
mod cli;

/// The derivation of a large mechanism is millions of small allocations (arena nodes, their
/// children, hash tables); mimalloc serves them faster than the system allocator. The step
/// loops allocate nothing, so a simulation's speed does not depend on it.
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;

fn main() -> std::process::ExitCode {
    cli::main_with_args(std::env::args_os())
}
