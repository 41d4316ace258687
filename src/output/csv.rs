//! `trajectory.csv` and `inverse.csv`.
//!
//! Numbers are written with Rust's shortest round-trip formatting (the fewest digits that
//! parse back to the same `f64`), in plain decimal for 1e-5 <= |x| < 1e16 and in exponent
//! form (`1.5e-13`) otherwise, so a reader gets every bit back and small residuals stay short.
//! Non-finite values are written as `NaN`, `inf` and `-inf`. The digits come from `zmij`
//! (the shortest correctly rounded decimal, as Rust's own `Display`), written into one
//! reused line buffer per row: no allocation per value.

use std::io::{BufWriter, Write};
use std::path::Path;

use super::table::InverseTable;
use super::{OutputError, ensure_dir, write_atomically};
use crate::simulation::trajectory::Trajectory;

/// Bytes one value takes in a CSV file, comma included, for the size estimate checked before
/// a run: at most 25 (`-1.2345678901234567e-100,`), 18.8 on average in the seed's
/// trajectory.csv and 19.2 in n_four_bar's, so 20.
pub const CSV_BYTES_PER_VALUE: usize = 20;

/// Largest CSV file a run is allowed to write (1 GB): beyond it a spreadsheet or a plotting
/// script will not open it either, and the run is refused before any work.
pub const MAX_CSV_BYTES: usize = 1_000_000_000;

/// The estimated size in bytes of a CSV of `rows` rows of `columns` values:
/// rows x columns x [`CSV_BYTES_PER_VALUE`] (the header is negligible).
pub fn estimated_csv_bytes(rows: usize, columns: usize) -> f64 {
    rows as f64 * columns as f64 * CSV_BYTES_PER_VALUE as f64
}

/// Formats `x` with the fewest digits that parse back to exactly `x`.
///
/// ```
/// # use mechanism::output::csv::format_f64;
/// assert_eq!(format_f64(0.1), "0.1");
/// assert_eq!(format_f64(-2.5e-15), "-2.5e-15");
/// assert_eq!(format_f64(0.1 + 0.2).parse::<f64>().unwrap(), 0.1 + 0.2);
/// ```
pub fn format_f64(x: f64) -> String {
    let mut out = Vec::with_capacity(24);
    push_f64(&mut out, x);
    // Only ASCII digits, signs, '.', 'e', "NaN" and "inf" are written.
    String::from_utf8(out).unwrap_or_default()
}

/// Appends [`format_f64`]'s text of `x` to `out` without allocating (beyond `out`'s
/// growth): `zmij`'s shortest digits, in its plain decimal form (`12.5`; the `.0` of a whole
/// number left out, as `Display` does) for 1e-5 <= |x| < 1e16, the range where `zmij`
/// writes decimals too, and in its exponent form without a `+` (`1.5e-13`, `1e16`, as
/// `{:e}`) otherwise; `0`, `-0`, `NaN`, `inf` and `-inf` as `Display` writes them. Where two
/// shortest decimals are equally close to x (`may_tie`), `zmij` takes the even last digit
/// and `Display` the one above: those values go through `Display` itself, so the text is
/// `Display`'s for every double.
pub fn push_f64(out: &mut Vec<u8>, x: f64) {
    if x == 0.0 || !x.is_finite() {
        let text = if x.is_nan() {
            "NaN"
        } else if x.is_infinite() {
            if x > 0.0 { "inf" } else { "-inf" }
        } else if x.is_sign_negative() {
            "-0"
        } else {
            "0"
        };
        out.extend_from_slice(text.as_bytes());
        return;
    }
    if may_tie(x) {
        let _ = if (1e-5..1e16).contains(&x.abs()) {
            write!(out, "{x}")
        } else {
            write!(out, "{x:e}")
        };
        return;
    }
    let mut buffer = zmij::Buffer::new();
    let text = buffer.format_finite(x).as_bytes();
    match text.iter().position(|&b| b == b'e') {
        Some(e) => {
            out.extend_from_slice(&text[..=e]);
            let exponent = &text[e + 1..];
            out.extend_from_slice(exponent.strip_prefix(b"+").unwrap_or(exponent));
        }
        None => out.extend_from_slice(text.strip_suffix(b".0").unwrap_or(text)),
    }
}

/// Whether two shortest decimals can be equally close to the finite, nonzero `x`. With x =
/// M 2^E, M odd, E < 0, its exact decimal is M 5^-E / 10^-E, whose last significant digit
/// is a 5: a tie between the two decimals one digit shorter. Every shortest decimal of a
/// double has at most 17 digits, so a tie needs M 5^-E < 10^18; an integer x (E >= 0) has
/// none (below 2^53 the decimal is exact within half a unit; above, the midpoints of the
/// shorter decimals are odd multiples of 5 10^(p-1), never a multiple of the spacing).
/// True only for values with few significant bits: about 1e13 <= |x| < 2^52 with a short
/// fraction, or dyadic fractions such as 0.5 + 2^-17.
fn may_tie(x: f64) -> bool {
    let bits = x.to_bits() & !(1u64 << 63);
    let biased = (bits >> 52) as i32;
    if biased == 0 {
        // Subnormal: a multiple of 2^-1074 with at most 16 significant bits above it.
        return false;
    }
    let mantissa = (bits & ((1u64 << 52) - 1)) | (1u64 << 52);
    let zeros = mantissa.trailing_zeros();
    let exponent = biased - 1075 + zeros as i32;
    if exponent >= 0 {
        return false;
    }
    let k = exponent.unsigned_abs();
    k <= 26 && u128::from(mantissa >> zeros) * 5u128.pow(k) < 1_000_000_000_000_000_000
}

/// Writes `header` and then each row of `rows` to the CSV file `path`, creating its
/// directory; written under a temporary name and renamed when complete
/// ([`super::write_atomically`]), so `path` is never left half-written.
///
/// Fails with [`OutputError::InvalidData`] when a row's length differs from the header's.
pub fn write_table<'a>(
    path: &Path,
    header: &[String],
    rows: impl IntoIterator<Item = &'a [f64]>,
) -> Result<(), OutputError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        ensure_dir(dir)?;
    }
    write_atomically(path, |partial| write_rows(partial, path, header, rows))
}

/// [`write_table`]'s work on the file `partial`; errors name `path`.
fn write_rows<'a>(
    partial: &Path,
    path: &Path,
    header: &[String],
    rows: impl IntoIterator<Item = &'a [f64]>,
) -> Result<(), OutputError> {
    let csv_err = |source| OutputError::Csv {
        path: path.to_path_buf(),
        source,
    };
    let file = std::fs::File::create(partial).map_err(|e| OutputError::io(path, e))?;
    // The header through the csv crate (a name may need quoting); the numbers never do
    // (digits, '-', '.', 'e', "NaN", "inf"), so each row is formatted into one line buffer
    // and written as it is.
    let mut w = ::csv::Writer::from_writer(BufWriter::with_capacity(1 << 16, file));
    w.write_record(header).map_err(csv_err)?;
    let mut file = w
        .into_inner()
        .map_err(|e| OutputError::io(path, e.into_error()))?;
    let mut line = Vec::with_capacity(24 * header.len() + 1);
    for (i, row) in rows.into_iter().enumerate() {
        if row.len() != header.len() {
            let msg = format!(
                "row {i} has {} values, the header has {}",
                row.len(),
                header.len()
            );
            return Err(OutputError::invalid(path.display().to_string(), msg));
        }
        line.clear();
        for (k, &x) in row.iter().enumerate() {
            if k > 0 {
                line.push(b',');
            }
            push_f64(&mut line, x);
        }
        line.push(b'\n');
        file.write_all(&line)
            .map_err(|e| OutputError::io(path, e))?;
    }
    file.flush().map_err(|e| OutputError::io(path, e))
}

/// Writes `trajectory.csv`: header exactly [`Trajectory::headers`], one row per sample.
pub fn write_trajectory_csv(path: &Path, trajectory: &Trajectory) -> Result<(), OutputError> {
    write_table(
        path,
        &trajectory.headers(),
        (0..trajectory.len()).map(|i| trajectory.row(i)),
    )
}

/// Writes `inverse.csv` with the header [`InverseTable::headers`].
pub fn write_inverse_csv(path: &Path, table: &InverseTable) -> Result<(), OutputError> {
    write_table(path, &table.headers(), table.rows.iter().map(Vec::as_slice))
}
