//! The checks run before any work: every numeric option within its stated range, and the
//! output a run asks for within its limits (samples, CSV size). Each failure is one line
//! naming the option, the allowed range and the value given.

use super::CliError;
use super::args::CommonArgs;
use mechanism::output::csv::{MAX_CSV_BYTES, estimated_csv_bytes, format_f64};

/// Output samples of a run of `c`: t = 0, 1/K, ..., t_end (the end time always included).
pub fn sample_count(c: &CommonArgs) -> usize {
    // Checked against MAX_OUTPUT_SAMPLES by `check_span`, so this fits a usize.
    ((c.t_end * c.samples_per_second - 1e-9).ceil().max(1.0)) as usize + 1
}

/// Checks the time span and sampling arguments shared by simulate and inverse.
pub fn check_span(c: &CommonArgs) -> Result<(), CliError> {
    if !(c.t_end.is_finite() && c.t_end > 0.0) {
        return Err(CliError::Argument(format!(
            "--t-end must be a positive number of seconds, got {}",
            c.t_end
        )));
    }
    if !(c.samples_per_second.is_finite() && c.samples_per_second > 0.0) {
        return Err(CliError::Argument(format!(
            "--samples-per-second must be positive, got {}",
            c.samples_per_second
        )));
    }
    let samples = c.t_end * c.samples_per_second;
    if samples > mechanism::MAX_OUTPUT_SAMPLES as f64 {
        return Err(CliError::Argument(format!(
            "--t-end {} at --samples-per-second {} asks for {samples:e} samples; at most {} are recorded",
            format_f64(c.t_end),
            format_f64(c.samples_per_second),
            mechanism::MAX_OUTPUT_SAMPLES
        )));
    }
    Ok(())
}

/// Refuses a run whose CSV `file` of `columns` values per sample would exceed
/// [`MAX_CSV_BYTES`] (estimated by [`estimated_csv_bytes`]).
pub fn check_csv_size(c: &CommonArgs, file: &str, columns: usize) -> Result<(), CliError> {
    let rows = sample_count(c);
    let bytes = estimated_csv_bytes(rows, columns);
    if bytes > MAX_CSV_BYTES as f64 {
        return Err(CliError::Argument(format!(
            "{file} would hold {rows} samples of {columns} values, about {:.2} GB, more than \
             the {:.0} GB allowed: lower --samples-per-second or shorten --t-end",
            bytes / 1e9,
            MAX_CSV_BYTES as f64 / 1e9
        )));
    }
    Ok(())
}
