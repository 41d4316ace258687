//! The `mechanism` command-line tool: argument parsing, loading a mechanism by name or
//! file, and the `list`, `equations`, `simulate`, `inverse`, `linearize` and `import`
//! commands.
//!
//! Exit status ([`args::EXIT_CODES`], printed by `--help`): 0 success; 1 a failed run or
//! invalid input; 2 a usage error (an unknown option, a missing argument, a value that is
//! not a number). Every error is one line on stderr: clap's usage errors are cut to their
//! message and a pointer to `--help` ([`usage_error`]).

pub mod args;
mod budget;
mod drawing;
mod equations;
mod floating;
mod import;
mod input;
mod inverse;
mod linearize;
mod load;
mod physical;
#[cfg(feature = "progress")]
mod progress;
#[cfg(not(feature = "progress"))]
#[path = "progress_off.rs"]
mod progress;
mod report;
mod run_dir;
mod seed;
mod signals;
mod simulate;
mod stdio;
mod validate;

use std::process::ExitCode;

use clap::{CommandFactory, Parser};

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
    /// A URDF that cannot be read or imported (`FILE:LINE:COL: <element>: message`).
    #[error("{0}")]
    Import(String),
    /// Writing a result file failed.
    #[error("{0}")]
    Output(#[from] mechanism::output::OutputError),
    /// A run whose results could not be put in its output folder (`why`, when that is not
    /// `error` itself: a failed summary or swap), which is left as it was.
    #[error(
        "{error}; {dir} is left as it was{}{}",
        why.as_ref().map_or(String::new(), |w| format!(" ({w})")),
        full_disk_hint(why.as_deref().unwrap_or(&error.to_string()))
    )]
    NotReplaced {
        /// Why the run failed.
        error: Box<CliError>,
        /// Why its results could not be put in, if not `error`.
        why: Option<String>,
        /// The output folder.
        dir: String,
    },
    /// Writing to standard output failed (a full disk; a closed pipe is not an error:
    /// [`stdio::print`]).
    #[error("cannot write to standard output: {0}")]
    Stdout(std::io::Error),
}

/// What to do when `message` says that a disk is full or a file beyond the size allowed
/// (the operating system's words for ENOSPC, EDQUOT and EFBIG), else nothing.
fn full_disk_hint(message: &str) -> &'static str {
    if message.contains("No space left on device") || message.contains("Disk quota exceeded") {
        ": free space on its disk, or write elsewhere with --out"
    } else if message.contains("File too large") {
        ": a file of the run is larger than its file system or the process's limit \
         (ulimit -f) allows; lower --samples-per-second, shorten --t-end or write elsewhere \
         with --out"
    } else {
        ""
    }
}

/// Runs the command line in `args` (the program name first) and returns the exit status.
pub fn main_with_args(args: impl IntoIterator<Item = std::ffi::OsString>) -> ExitCode {
    signals::install();
    let args: Vec<std::ffi::OsString> = args.into_iter().collect();
    let cli = match Cli::try_parse_from(&args) {
        Ok(cli) => cli,
        // --help and --version print and succeed.
        Err(e) if !e.use_stderr() => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
        Err(e) => {
            stdio::eprint_line(&usage_error(&e, &args));
            return ExitCode::from(2);
        }
    };
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            stdio::eprint_line(&format!("error: {e}"));
            ExitCode::from(1)
        }
    }
}

/// A clap usage error for the command line `args` as one line:
/// `error: <message> (see <command> --help)`. The message is clap's first paragraph (a
/// list such as the missing arguments or the possible values joined onto it); its tip,
/// usage and "for more information" paragraphs are dropped. The command is `mechanism`
/// and the subcommand given, if any (`mechanism simulate`).
pub fn usage_error(e: &clap::Error, args: &[std::ffi::OsString]) -> String {
    let text = e.render().to_string();
    let first = text.split("\n\n").next().unwrap_or_default();
    let message: Vec<&str> = first
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    let message = message.join(" ");
    let message = message.strip_prefix("error: ").unwrap_or(&message);
    let subcommand = args
        .get(1)
        .and_then(|a| a.to_str())
        .filter(|a| Cli::command().get_subcommands().any(|c| c.get_name() == *a));
    let command = match subcommand {
        Some(sub) => format!("mechanism {sub}"),
        None => "mechanism".to_string(),
    };
    format!("error: {message} (see {command} --help)")
}

/// Runs a parsed command line.
pub fn run(cli: Cli) -> Result<(), CliError> {
    match cli.command {
        None => simulate::run(&simulate::default_args()),
        Some(Command::List) => stdio::print(&equations::list()?),
        Some(Command::Equations { mechanism, latex }) => {
            stdio::print(&equations::equations(&mechanism, latex)?)
        }
        Some(Command::Simulate(a)) => simulate::run(&a),
        Some(Command::Inverse(a)) => inverse::run(&a),
        Some(Command::Import(a)) => import::run(&a),
        Some(Command::Linearize(a)) => linearize::run(&a),
    }
}
