//! `trajectory.csv` and `inverse.csv`.
//!
//! Numbers are written with Rust's shortest round-trip formatting (the fewest digits that
//! parse back to the same `f64`), in plain decimal for 1e-5 <= |x| < 1e16 and in exponent
//! form (`1.5e-13`) otherwise, so a reader gets every bit back and small residuals stay short.
//! Non-finite values are written as `NaN`, `inf` and `-inf`.

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
    let a = x.abs();
    if x == 0.0 || !x.is_finite() || (1e-5..1e16).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
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
    let mut w = ::csv::Writer::from_path(partial).map_err(csv_err)?;
    w.write_record(header).map_err(csv_err)?;
    let mut fields = Vec::with_capacity(header.len());
    for (i, row) in rows.into_iter().enumerate() {
        if row.len() != header.len() {
            let msg = format!(
                "row {i} has {} values, the header has {}",
                row.len(),
                header.len()
            );
            return Err(OutputError::invalid(path.display().to_string(), msg));
        }
        fields.clear();
        fields.extend(row.iter().map(|&x| format_f64(x)));
        w.write_record(&fields).map_err(csv_err)?;
    }
    w.flush().map_err(|e| OutputError::io(path, e))
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
