//! How a run ended and what it left in its folder: the last keys of both summaries
//! (`summary.json` of a forward run, [`super::Summary`], and of an inverse run,
//! [`super::InverseSummary`]).

use serde::Serialize;

/// `status`, `t_last`, `error`, `stage` and `files`, flattened into a summary's keys.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Outcome {
    /// `completed`, or `failed` when the run stopped before its end.
    pub status: String,
    /// Time of the last sample written (s); NaN (`null` in JSON) when no sample was.
    pub t_last: f64,
    /// Why the run stopped early (`null` when completed).
    pub error: Option<String>,
    /// Where a failed run stopped: `assembly`, `integration`, `inverse dynamics` or
    /// `output` (`null` when completed or not said). The command-line tool records only
    /// runs that started: one refused before (loading the mechanism, its parameters and
    /// initial values, the output checks) leaves the folder as it was.
    pub stage: Option<String>,
    /// The files the run wrote into its output folder, by name, the summary included: the
    /// next run there removes them first ([`super::remove_previous_results`]).
    pub files: Vec<String>,
}

impl Outcome {
    /// A completed run whose last sample is at `t_last`.
    pub fn completed(t_last: f64) -> Self {
        Self {
            status: "completed".into(),
            t_last,
            ..Self::default()
        }
    }

    /// Marks the run as stopped early by `error` (status `failed`).
    pub fn failed(&mut self, error: &dyn std::fmt::Display) {
        self.status = "failed".into();
        self.error = Some(error.to_string());
    }

    /// Marks the run as stopped early in `stage` by `error`.
    pub fn failed_in(&mut self, stage: &str, error: &dyn std::fmt::Display) {
        self.failed(error);
        self.stage = Some(stage.to_string());
    }
}
