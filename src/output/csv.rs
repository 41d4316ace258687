//! `trajectory.csv` and `inverse.csv`.
//!
//! Numbers are written with Rust's shortest round-trip formatting (the fewest digits that
//! parse back to the same `f64`), in plain decimal for 1e-5 <= |x| < 1e16 and in exponent
//! form (`1.5e-13`) otherwise, so a reader gets every bit back and small residuals stay short.
//! Non-finite values are written as `NaN`, `inf` and `-inf`.

use std::path::Path;

use super::{OutputError, ensure_dir};
use crate::simulation::trajectory::Trajectory;

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

/// Writes `header` and then each row of `rows` to the CSV file `path`, creating its directory.
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
    let csv_err = |source| OutputError::Csv {
        path: path.to_path_buf(),
        source,
    };
    let mut w = ::csv::Writer::from_path(path).map_err(csv_err)?;
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

/// The result of an inverse-dynamics run, as written to `inverse.csv`.
///
/// Each row holds, in order: t; q (one value per coordinate); q'; q''; tau for each driven
/// coordinate (the total generalised force needed on it, N m for an angle, N for a length);
/// lambda_1..lambda_m. See [`InverseTable::headers`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct InverseTable {
    /// Coordinate names, in the order of q.
    pub coordinates: Vec<String>,
    /// Names of the driven coordinates, in the order of the tau columns.
    pub driven: Vec<String>,
    /// Number of constraint rows m (number of lambda columns).
    pub constraints: usize,
    /// The rows: 1 + 3 n + driven.len() + m values each.
    pub rows: Vec<Vec<f64>>,
}

impl InverseTable {
    /// The `inverse.csv` header: `t`, each coordinate, `<name>_dot`, `<name>_ddot`,
    /// `tau_<driven>` for each driven coordinate, `lambda_1..lambda_m`.
    pub fn headers(&self) -> Vec<String> {
        let c = &self.coordinates;
        let mut h = vec!["t".to_string()];
        h.extend(c.iter().cloned());
        h.extend(c.iter().map(|x| format!("{x}_dot")));
        h.extend(c.iter().map(|x| format!("{x}_ddot")));
        h.extend(self.driven.iter().map(|x| format!("tau_{x}")));
        h.extend((1..=self.constraints).map(|i| format!("lambda_{i}")));
        h
    }

    /// Column of time values.
    pub fn times(&self) -> Vec<f64> {
        self.rows
            .iter()
            .map(|r| r.first().copied().unwrap_or(f64::NAN))
            .collect()
    }

    /// Column of tau for driven coordinate number `k` (index into [`InverseTable::driven`]).
    pub fn torque(&self, k: usize) -> Vec<f64> {
        let col = 1 + 3 * self.coordinates.len() + k;
        self.rows
            .iter()
            .map(|r| r.get(col).copied().unwrap_or(f64::NAN))
            .collect()
    }
}

/// Writes `inverse.csv` with the header [`InverseTable::headers`].
pub fn write_inverse_csv(path: &Path, table: &InverseTable) -> Result<(), OutputError> {
    write_table(path, &table.headers(), table.rows.iter().map(Vec::as_slice))
}
