//! The `mechanism` command-line tool: argument parsing, loading a mechanism by name or
//! file, and the `list`, `equations`, `simulate` and `inverse` commands.
//!
//! Every user mistake ends in a one-line message on stderr and exit status 1; clap's own
//! usage errors exit with 2.

pub mod args;
mod equations;
mod inverse;
mod load;
#[cfg(feature = "progress")]
mod progress;
#[cfg(not(feature = "progress"))]
#[path = "progress_off.rs"]
mod progress;
mod report;
mod run_dir;
mod simulate;
mod validate;

use std::process::ExitCode;

use clap::Parser;

pub use self::args::{Cli, Command};

/// A failure of one command, printed as one line.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Unknown mechanism name or unreadable file.
    #[error("{0}")]
    Mechanism(String),
    /// A bad `--set`, `--init` or `--drive`.
    #[error("{0}")]
    Argument(String),
    /// The solver failed (typed runtime error).
    #[error("{0}")]
    Solver(#[from] mechanism::Error),
    /// The simulation stopped early; the samples up to `t` were written to `dir`.
    #[error("{error} (the run stopped there; results up to t = {t} s are in {dir})")]
    Stopped {
        /// Time of the last sample written (s).
        t: f64,
        /// Output folder.
        dir: String,
        /// Why it stopped.
        error: mechanism::Error,
    },
    /// Writing a result file failed.
    #[error("{0}")]
    Output(#[from] mechanism::output::OutputError),
}

/// Runs the command line in `args` (the program name first) and returns the exit status.
pub fn main_with_args(args: impl IntoIterator<Item = std::ffi::OsString>) -> ExitCode {
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            // --help and --version print and succeed; real usage errors exit with 2.
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::from(1)
        }
    }
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        None => simulate::run(&simulate::default_args()),
        Some(Command::List) => {
            print!("{}", equations::list()?);
            Ok(())
        }
        Some(Command::Equations { mechanism, latex }) => {
            print!("{}", equations::equations(&mechanism, latex)?);
            Ok(())
        }
        Some(Command::Simulate(a)) => simulate::run(&a),
        Some(Command::Inverse(a)) => inverse::run(&a),
    }
}
