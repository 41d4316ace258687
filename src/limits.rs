//! The limits every run is held to, checked before any work: how many output samples it
//! may record and how much memory they may take. A run beyond them is refused with the
//! figures ([`Error::TooManySamples`], [`Error::TooMuchOutput`]) instead of filling the
//! memory or the disk for minutes first.

use crate::error::Error;

/// Most output samples one run records.
pub const MAX_OUTPUT_SAMPLES: usize = 10_000_000;

/// Most bytes the recorded samples of one run may take in memory (1 GB). The command-line
/// tool holds a second copy while it writes (the figures' series) and the CSV takes about
/// three times as much on disk (up to 24 characters per value), so this keeps a run within
/// a few GB of memory and disk on any machine it is likely to meet.
pub const MAX_OUTPUT_BYTES: usize = 1_000_000_000;

/// Checks that `samples` output samples of `columns` values each, plus `overhead` bytes of
/// bookkeeping per sample, fit in [`MAX_OUTPUT_BYTES`] (8 bytes per value).
pub(crate) fn check_output_memory(
    samples: usize,
    columns: usize,
    overhead: usize,
) -> Result<(), Error> {
    let bytes = samples as f64 * (columns * 8 + overhead) as f64;
    if bytes > MAX_OUTPUT_BYTES as f64 {
        return Err(Error::TooMuchOutput {
            samples,
            columns,
            bytes,
            limit: MAX_OUTPUT_BYTES,
        });
    }
    Ok(())
}
