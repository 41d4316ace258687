//! The checks run before any work: every numeric option within its stated range, and the
//! output a run asks for within its limits (samples, CSV size). Each failure is one line
//! naming the option, the allowed range and the value given.

use super::CliError;
use super::args::{CommonArgs, SimulateArgs};
use mechanism::output::csv::{MAX_CSV_BYTES, estimated_csv_bytes, format_f64};

/// Longest run (s), 1e9 s or 32 years: no mechanism run needs more, and at t = 1e9 s the
/// spacing of f64 times (1.2e-7 s) approaches the steps of a fast mechanism.
pub const MAX_T_END: f64 = 1e9;

/// Smallest relative tolerance, about 5 machine epsilons: below it the local error estimate
/// is round-off and the step size cannot satisfy it.
pub const MIN_RTOL: f64 = 1e-15;

/// `Ok` when `ok`, else "`option` must be `allowed`, got `value`".
fn check(option: &str, value: f64, allowed: &str, ok: bool) -> Result<(), CliError> {
    if ok {
        return Ok(());
    }
    Err(CliError::Argument(format!(
        "{option} must be {allowed}, got {}",
        format_f64(value)
    )))
}

/// Output samples of a run of `c`: t = 0, 1/K, ..., t_end (the end time always included).
pub fn sample_count(c: &CommonArgs) -> usize {
    // Checked against MAX_OUTPUT_SAMPLES by `check_span`, so this fits a usize.
    ((c.t_end * c.samples_per_second - 1e-9).ceil().max(1.0)) as usize + 1
}

/// Checks the time span and sampling arguments shared by simulate and inverse:
/// `--t-end` in (0, 1e9] s, `--samples-per-second` > 0 and finite, and at most
/// [`mechanism::MAX_OUTPUT_SAMPLES`] samples.
pub fn check_span(c: &CommonArgs) -> Result<(), CliError> {
    let (t_end, rate) = (c.t_end, c.samples_per_second);
    let ranges = [
        (
            "--t-end",
            t_end,
            "> 0 s and at most 1e9 s",
            t_end > 0.0 && t_end <= MAX_T_END,
        ),
        (
            "--samples-per-second",
            rate,
            "> 0 and finite",
            rate > 0.0 && rate.is_finite(),
        ),
    ];
    for (option, value, allowed, ok) in ranges {
        check(option, value, allowed, ok)?;
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

/// Checks the integrator options of `simulate`: `--rtol` finite in [1e-15, 1) (a relative
/// error of 100 % accepts any step), `--atol` finite and > 0, `--step` in (0, --t-end] s.
pub fn check_integrator(a: &SimulateArgs) -> Result<(), CliError> {
    let (rtol, atol) = (a.rtol, a.atol);
    let ranges = [
        (
            "--rtol",
            rtol,
            "finite, at least 1e-15 and below 1",
            (MIN_RTOL..1.0).contains(&rtol),
        ),
        (
            "--atol",
            atol,
            "> 0 and finite",
            atol > 0.0 && atol.is_finite(),
        ),
    ];
    for (option, value, allowed, ok) in ranges {
        check(option, value, allowed, ok)?;
    }
    if let Some(h) = a.step {
        let allowed = format!(
            "> 0 s and at most --t-end ({} s)",
            format_f64(a.common.t_end)
        );
        check("--step", h, &allowed, h > 0.0 && h <= a.common.t_end)?;
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
