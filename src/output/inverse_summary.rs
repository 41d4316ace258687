//! `summary.json` of an inverse-dynamics run: what was prescribed, the peak driving forces,
//! how the run ended and the files it wrote (the forward run's is [`super::Summary`]).

use std::path::Path;

use serde::Serialize;

use super::OutputError;
use super::excursions::LimitExcursion;
use super::outcome::Outcome;
use super::summary::{NamedValues, write_json};
use super::table::InverseTable;
use crate::linalg::max_nan;

/// The contents of an inverse run's `summary.json` (keys in this order).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct InverseSummary {
    /// `inverse`, which tells this summary from a forward run's.
    pub command: String,
    /// Mechanism name.
    pub mechanism: String,
    /// Parameter values by name, in declaration order.
    pub parameters: NamedValues,
    /// The prescribed motions as given (`phi = 2*pi*t`).
    pub drives: Vec<String>,
    /// Samples computed.
    pub samples: usize,
    /// max_t |tau| of each driven coordinate, by column name `tau_<coordinate>` (N m for
    /// an angle, N for a length); NaN (`null`) when a sample's force is.
    pub max_abs_driving_force: NamedValues,
    /// The declared joint limits the motion or the driving forces passed (nothing
    /// enforces them); set by the caller, which knows the limits
    /// (`output::inverse_excursions`), empty from [`InverseSummary::new`].
    pub joint_limit_excursions: Vec<LimitExcursion>,
    /// How the run ended and the files it wrote: `status`, `t_last`, `error`, `stage`
    /// (`setup`, `inverse dynamics` or `output` for a failure), `files` (see [`Outcome`]).
    #[serde(flatten)]
    pub outcome: Outcome,
}

impl InverseSummary {
    /// A completed run of `mechanism` with `parameters` and `drives` whose results are
    /// `table`.
    pub fn new(
        mechanism: &str,
        parameters: NamedValues,
        drives: &[String],
        table: &InverseTable,
    ) -> Self {
        let peaks = (0..table.driven.len())
            .map(|k| {
                let peak = table.torque(k).iter().fold(0.0, |a, v| max_nan(a, v.abs()));
                (format!("tau_{}", table.driven[k]), peak)
            })
            .collect();
        Self {
            command: "inverse".into(),
            mechanism: mechanism.to_string(),
            parameters,
            drives: drives.to_vec(),
            samples: table.rows.len(),
            max_abs_driving_force: NamedValues(peaks),
            joint_limit_excursions: Vec::new(),
            outcome: Outcome::completed(table.times().last().copied().unwrap_or(f64::NAN)),
        }
    }

    /// A run of `mechanism` that failed in `stage` with `error` before any result: no
    /// samples, `t_last` NaN (`null`).
    pub fn not_started(
        mechanism: &str,
        parameters: NamedValues,
        drives: &[String],
        stage: &str,
        error: &dyn std::fmt::Display,
    ) -> Self {
        let mut summary = Self::new(mechanism, parameters, drives, &InverseTable::default());
        summary.outcome.failed_in(stage, error);
        summary
    }
}

/// Writes `summary` as pretty-printed JSON to `path` (whole or not at all), creating its
/// directory. Non-finite numbers are written as `null`.
pub fn write_inverse_summary(path: &Path, summary: &InverseSummary) -> Result<(), OutputError> {
    write_json(path, summary)
}
