//! The inverse-dynamics table that `inverse.csv` and the driving-torque figure share.

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

    /// Column `j` of the rows ([`InverseTable::headers`] order; NaN where a row is short).
    pub fn column(&self, j: usize) -> Vec<f64> {
        self.rows
            .iter()
            .map(|r| r.get(j).copied().unwrap_or(f64::NAN))
            .collect()
    }

    /// Column of time values.
    pub fn times(&self) -> Vec<f64> {
        self.column(0)
    }

    /// Column of q for coordinate number `i`.
    pub fn positions(&self, i: usize) -> Vec<f64> {
        self.column(1 + i)
    }

    /// Column of q' for coordinate number `i`.
    pub fn rates(&self, i: usize) -> Vec<f64> {
        self.column(1 + self.coordinates.len() + i)
    }

    /// Column of tau for driven coordinate number `k` (index into [`InverseTable::driven`]).
    pub fn torque(&self, k: usize) -> Vec<f64> {
        self.column(1 + 3 * self.coordinates.len() + k)
    }
}
