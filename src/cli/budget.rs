//! The derivation's budget, read from the environment (the command-line tool is the
//! boundary that reads it: `MECHANISM_MAX_SIZE`, `MECHANISM_MAX_ENTRIES`,
//! `MECHANISM_MAX_WORK`), and the progress line a long derivation prints on stderr.
//!
//! The line appears once a derivation has run for a second: on a terminal one line
//! rewritten in place, elsewhere (a log) one line every ten seconds.

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use mechanism_codegen::{Budget, Effort};

use super::CliError;

/// When the derivation started, and when a line was last printed (`None`: not yet).
static CLOCK: Mutex<Option<(Instant, Option<Instant>)>> = Mutex::new(None);

/// How long a derivation runs before it reports.
const QUIET: Duration = Duration::from_secs(1);

/// How often a line is printed when stderr is not a terminal.
const LOG_EVERY: Duration = Duration::from_secs(10);

/// The budget of a derivation starting now, with its progress line.
///
/// # Errors
/// A variable that is set but is not a positive whole number.
pub fn derivation_budget() -> Result<Budget, CliError> {
    let mut budget =
        Budget::from_lookup(|name| std::env::var(name).ok()).map_err(CliError::Argument)?;
    budget.progress = Some(report);
    if let Ok(mut clock) = CLOCK.lock() {
        *clock = Some((Instant::now(), None));
    }
    Ok(budget)
}

/// Ends the progress line of the derivation, if one was printed.
pub fn derivation_done() {
    let printed = CLOCK
        .lock()
        .ok()
        .and_then(|mut c| c.take())
        .is_some_and(|(_, last)| last.is_some());
    if printed && std::io::stderr().is_terminal() {
        let _ = writeln!(std::io::stderr());
    }
}

/// The progress hook: prints the work and size so far, once the derivation is past
/// [`QUIET`].
fn report(effort: Effort) {
    let Ok(mut clock) = CLOCK.lock() else {
        return;
    };
    let Some((start, last)) = clock.as_mut() else {
        return;
    };
    let elapsed = start.elapsed();
    if elapsed < QUIET {
        return;
    }
    let terminal = std::io::stderr().is_terminal();
    if !terminal && last.is_some_and(|l| l.elapsed() < LOG_EVERY) {
        return;
    }
    *last = Some(Instant::now());
    let line = format!(
        "deriving: {:.0} M units of work, {:.1} M nodes, {:.0} s",
        effort.work as f64 / 1e6,
        effort.size as f64 / 1e6,
        elapsed.as_secs_f64()
    );
    let mut err = std::io::stderr().lock();
    let _ = if terminal {
        write!(err, "\r{line}")
    } else {
        writeln!(err, "{line}")
    };
}
