//! Writing to standard output and standard error without a panic: `print!` and `eprintln!`
//! panic when the stream is closed (`mechanism list | true`) or full (`>/dev/full`).
//!
//! A reader that stops early (a broken pipe) is not an error of the command: the rest of
//! the text is dropped and the exit status is the command's own. Any other failure to write
//! standard output (a full disk) is [`CliError::Stdout`], one line on stderr and exit
//! status 1. A failure to write standard error is ignored: there is nowhere left to say it.

use std::io::{ErrorKind, Write as _};

use super::CliError;

/// Writes `text` to standard output and flushes it (see the module docs).
pub fn print(text: &str) -> Result<(), CliError> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() != ErrorKind::BrokenPipe => Err(CliError::Stdout(e)),
        _ => Ok(()),
    }
}

/// Writes `line` and a newline to standard error; a failure is ignored.
pub fn eprint_line(line: &str) {
    let mut err = std::io::stderr().lock();
    let _ = writeln!(err, "{line}").and_then(|()| err.flush());
}
