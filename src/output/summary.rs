//! `summary.json`: what was run, the consistent initial state, and how well the run kept
//! the constraints and the energy balance.

use std::io::Write;
use std::path::Path;

use serde::Serialize;
use serde::ser::{SerializeMap, Serializer};

use super::excursions::{LimitExcursion, LimitWatch};
use super::outcome::Outcome;
use super::{OutputError, ensure_dir, write_atomically};
use crate::algorithms::mobility::Mobility;
use crate::linalg::max_nan;
use crate::simulation::apex::PassageGeometry;
use crate::simulation::singular::SingularPassage;
use crate::simulation::trajectory::Trajectory;
use crate::system::SystemInfo;

/// Name -> value pairs that serialise as a JSON object in their given order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NamedValues(pub Vec<(String, f64)>);

impl NamedValues {
    /// Pairs `names[i]` with `values[i]`; `None` when the lengths differ.
    pub fn zip(names: &[String], values: &[f64]) -> Option<Self> {
        (names.len() == values.len())
            .then(|| Self(names.iter().cloned().zip(values.iter().copied()).collect()))
    }

    /// The value called `name`.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.0.iter().find(|(n, _)| n == name).map(|&(_, v)| v)
    }
}

impl Serialize for NamedValues {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            map.serialize_entry(k, v)?;
        }
        map.end()
    }
}

/// The consistent initial state: q(0) satisfying Phi(q, 0) = 0 and q'(0) satisfying
/// Phi_q q' + Phi_t = 0 (the first sample of the trajectory).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct InitialState {
    /// q(0) by coordinate name.
    pub q: NamedValues,
    /// q'(0) by coordinate name.
    pub q_dot: NamedValues,
}

/// How the run was configured (what the CLI was given, after defaults).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct RunSettings {
    /// Integrator name (`rk4`, `dopri5`, `dop853`, `hht`).
    pub integrator: String,
    /// Relative tolerance (`None`, written as `null`, for fixed-step integrators).
    pub rtol: Option<f64>,
    /// Absolute tolerance (`None` for fixed-step integrators).
    pub atol: Option<f64>,
    /// Constraint stabilisation (`projection`, `baumgarte`, `none`).
    pub stabilization: String,
}

/// Maxima over all samples of a trajectory.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct TrajectoryMaxima {
    /// max_i |Phi(q_i, t_i)|_inf.
    pub constraint_error: f64,
    /// max_i |Phi_q q'_i + Phi_t|_inf.
    pub velocity_constraint_error: f64,
    /// Energy balance error: max_i |E_i - E_0| with E = T + Pi - W, where W is the work done
    /// by the applied forces tau and by the constraint rows that move with t (lambda .
    /// Phi_t) since t = 0. For an exact solution E is constant, so this
    /// measures the integration error of the energy (zero for an empty trajectory).
    pub energy_balance_error: f64,
}

impl TrajectoryMaxima {
    /// The maxima of `trajectory` (all zero when it is empty; NaN when any sample is NaN).
    pub fn of(trajectory: &Trajectory) -> Self {
        let Some(first) = trajectory.samples().next() else {
            return Self::default();
        };
        let e0 = first.kinetic + first.potential - first.work;
        trajectory.samples().fold(Self::default(), |acc, s| Self {
            constraint_error: max_nan(acc.constraint_error, s.constraint_error.abs()),
            velocity_constraint_error: max_nan(
                acc.velocity_constraint_error,
                s.velocity_constraint_error.abs(),
            ),
            energy_balance_error: max_nan(
                acc.energy_balance_error,
                (s.kinetic + s.potential - s.work - e0).abs(),
            ),
        })
    }
}

/// The mobility at the first sample, with rows named by their joints.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MobilityReport {
    /// Coordinates n.
    pub n: usize,
    /// Constraint rows m.
    pub m: usize,
    /// Rank of Phi_q at the assembled configuration.
    pub rank: usize,
    /// n - rank.
    pub degrees_of_freedom: usize,
    /// Grübler's count n - m (every row taken as independent).
    pub grubler: i64,
    /// The rows that repeat rows before them, by label.
    pub redundant_rows: Vec<String>,
    /// `unique` at full rank; otherwise says that lambda is the minimum-norm choice and
    /// which joints share its indeterminate part (only Phi_q^T lambda is unique).
    pub multipliers: String,
}

impl MobilityReport {
    /// Names the rows of `mobility` with the labels of `info`.
    pub fn new(mobility: &Mobility, info: &SystemInfo) -> Self {
        let multipliers = if mobility.full_rank() {
            "unique".to_string()
        } else {
            format!(
                "not unique: the CSV and plots give the minimum-norm lambda; the joints {} share \
                 the indeterminate part (their constraint forces Phi_q^T lambda are unique)",
                info.joints_of(&mobility.indeterminate_rows).join(", ")
            )
        };
        Self {
            n: mobility.n,
            m: mobility.m,
            rank: mobility.rank,
            degrees_of_freedom: mobility.degrees_of_freedom,
            grubler: mobility.grubler,
            redundant_rows: mobility
                .redundant_rows
                .iter()
                .map(|&r| info.constraint_label(r))
                .collect(),
            multipliers,
        }
    }
}

/// A singular configuration passed through, with its rows named.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PassageReport {
    /// Estimated time (s), within one step.
    pub t: f64,
    /// Rows that lose their independence there.
    pub rank_drop: usize,
    /// The weakest row independence at the nearest step (0: exactly singular).
    pub independence: f64,
    /// The joints of those rows.
    pub joints: Vec<String>,
    /// `crossing`, `apex` or `unclassified` ([`crate::PassageGeometry`]).
    pub geometry: PassageGeometry,
    /// One step went over the closest approach ([`SingularPassage::stepped_over`]).
    pub stepped_over: bool,
}

impl PassageReport {
    fn new(p: &SingularPassage, info: &SystemInfo) -> Self {
        Self {
            t: p.t,
            rank_drop: p.rank_drop,
            independence: p.independence,
            joints: info.joints_of(&p.rows),
            geometry: p.geometry,
            stepped_over: p.stepped_over,
        }
    }
}

/// The declared joint limits the samples of `trajectory` pass.
fn excursions(trajectory: &Trajectory) -> Vec<LimitExcursion> {
    let mut watch = LimitWatch::new(&trajectory.info);
    for s in trajectory.samples() {
        watch.sample(s.t, s.q, s.qd, None);
    }
    watch.finish(&trajectory.info)
}

/// The contents of `summary.json` (keys in this order; tools and tests read them).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Summary {
    /// Mechanism name.
    pub mechanism: String,
    /// Parameter values by name, in declaration order.
    pub parameters: NamedValues,
    /// q(0) and q'(0) after assembly.
    pub consistent_initial_state: InitialState,
    /// See [`TrajectoryMaxima::constraint_error`].
    pub max_constraint_error: f64,
    /// See [`TrajectoryMaxima::velocity_constraint_error`].
    pub max_velocity_constraint_error: f64,
    /// See [`TrajectoryMaxima::energy_balance_error`]: max_i |(T+Pi-W)_i - (T+Pi-W)_0|.
    pub max_energy_balance_error: f64,
    /// T or Pi depends on t explicitly ([`crate::SystemInfo::energy_depends_on_time`]):
    /// then `max_energy_balance_error` is no error measure.
    pub energy_depends_on_time: bool,
    /// Accepted integration steps.
    pub steps: usize,
    /// Rejected steps.
    pub rejected_steps: usize,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: usize,
    /// Wall-clock time of the integration (s).
    pub wall_time_s: f64,
    /// Integrator name.
    pub integrator: String,
    /// Relative tolerance (`null` for fixed-step integrators).
    pub rtol: Option<f64>,
    /// Absolute tolerance (`null` for fixed-step integrators).
    pub atol: Option<f64>,
    /// Constraint stabilisation.
    pub stabilization: String,
    /// Right-hand sides solved by the augmented Lagrangian route instead of LU.
    pub augmented_solves: usize,
    /// Right-hand sides solved by the banded direct route instead of LU.
    pub banded_solves: usize,
    /// Right-hand sides solved by the mechanism's generated forward dynamics (no constraint
    /// rows: q'' without evaluating or factoring M).
    pub generated_solves: usize,
    /// Mobility at the assembled configuration.
    pub mobility: MobilityReport,
    /// Singular configurations the motion passed through, in time order.
    pub singular_passages: Vec<PassageReport>,
    /// The declared joint limits the motion passed (positions and rates; nothing enforces
    /// them), in coordinate order.
    pub joint_limit_excursions: Vec<LimitExcursion>,
    /// How the run ended and the files it wrote: `status`, `t_last`, `error`, `stage`,
    /// `files` (see [`Outcome`]).
    #[serde(flatten)]
    pub outcome: Outcome,
}

impl Summary {
    /// Builds the summary of `trajectory`, run with `parameters` (values in the order of
    /// `trajectory.info.parameters`) and `settings`. The initial state is the first sample.
    ///
    /// Fails when the trajectory is empty or `parameters` has the wrong length.
    pub fn new(
        trajectory: &Trajectory,
        parameters: &[f64],
        settings: &RunSettings,
    ) -> Result<Self, OutputError> {
        let info = &trajectory.info;
        let first = trajectory
            .samples()
            .next()
            .ok_or_else(|| OutputError::invalid("summary", "the trajectory is empty"))?;
        let parameters = NamedValues::zip(&info.parameters, parameters).ok_or_else(|| {
            let msg = format!(
                "{} parameter values for {} parameters",
                parameters.len(),
                info.parameters.len()
            );
            OutputError::invalid("summary", msg)
        })?;
        let consistent_initial_state = InitialState {
            q: NamedValues::zip(&info.coordinates, first.q).unwrap_or_default(),
            q_dot: NamedValues::zip(&info.coordinates, first.qd).unwrap_or_default(),
        };
        let max = TrajectoryMaxima::of(trajectory);
        let stats = trajectory.stats;
        Ok(Self {
            mechanism: info.name.clone(),
            parameters,
            consistent_initial_state,
            max_constraint_error: max.constraint_error,
            max_velocity_constraint_error: max.velocity_constraint_error,
            max_energy_balance_error: max.energy_balance_error,
            energy_depends_on_time: info.energy_depends_on_time,
            steps: stats.steps,
            rejected_steps: stats.rejected_steps,
            rhs_evaluations: stats.rhs_evaluations,
            wall_time_s: stats.wall_time_s,
            integrator: settings.integrator.clone(),
            rtol: settings.rtol,
            atol: settings.atol,
            stabilization: settings.stabilization.clone(),
            augmented_solves: stats.augmented_solves,
            banded_solves: stats.banded_solves,
            generated_solves: stats.generated_solves,
            mobility: trajectory
                .mobility
                .as_ref()
                .map(|m| MobilityReport::new(m, info))
                .unwrap_or_default(),
            singular_passages: trajectory
                .singular_passages
                .iter()
                .map(|p| PassageReport::new(p, info))
                .collect(),
            joint_limit_excursions: excursions(trajectory),
            outcome: Outcome::completed(trajectory.last().map_or(0.0, |s| s.t)),
        })
    }

    /// The summary of a run of `mechanism` that stopped before its first sample (status
    /// `failed`, stopped by `error` in `stage`): no state, counters 0, and the maxima and
    /// `t_last` NaN (`null` in JSON), since nothing was computed.
    pub fn not_started(
        mechanism: &str,
        parameters: NamedValues,
        settings: &RunSettings,
        stage: &str,
        error: &dyn std::fmt::Display,
    ) -> Self {
        let mut summary = Self {
            mechanism: mechanism.to_string(),
            parameters,
            consistent_initial_state: InitialState::default(),
            max_constraint_error: f64::NAN,
            max_velocity_constraint_error: f64::NAN,
            max_energy_balance_error: f64::NAN,
            energy_depends_on_time: false,
            steps: 0,
            rejected_steps: 0,
            rhs_evaluations: 0,
            wall_time_s: 0.0,
            integrator: settings.integrator.clone(),
            rtol: settings.rtol,
            atol: settings.atol,
            stabilization: settings.stabilization.clone(),
            augmented_solves: 0,
            banded_solves: 0,
            generated_solves: 0,
            mobility: MobilityReport::default(),
            singular_passages: Vec::new(),
            joint_limit_excursions: Vec::new(),
            outcome: Outcome {
                t_last: f64::NAN,
                ..Outcome::default()
            },
        };
        summary.outcome.failed_in(stage, error);
        summary
    }

    /// Marks the run as stopped early by `error` (status `failed`).
    pub fn failed(&mut self, error: &dyn std::fmt::Display) {
        self.outcome.failed(error);
    }
}

/// Writes `summary` as pretty-printed JSON to `path`, creating its directory.
/// Non-finite numbers are written as `null`.
pub fn write_summary(path: &Path, summary: &Summary) -> Result<(), OutputError> {
    write_json(path, summary)
}

/// A summary's keys after our mark: `format` and `format_version` first
/// ([`super::SUMMARY_FORMAT`]), which tell our summaries from any other `summary.json`.
#[derive(Serialize)]
struct Marked<'a, T> {
    format: &'static str,
    format_version: u64,
    #[serde(flatten)]
    summary: &'a T,
}

/// Writes the summary `value` as pretty-printed JSON to `path`, marked as ours ([`Marked`]),
/// creating its directory; under a temporary name renamed when complete
/// ([`super::write_atomically`]).
pub(crate) fn write_json(path: &Path, value: &impl Serialize) -> Result<(), OutputError> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        ensure_dir(dir)?;
    }
    let marked = Marked {
        format: super::SUMMARY_FORMAT,
        format_version: super::SUMMARY_FORMAT_VERSION,
        summary: value,
    };
    let mut text = serde_json::to_string_pretty(&marked).map_err(|source| OutputError::Json {
        path: path.to_path_buf(),
        source,
    })?;
    text.push('\n');
    write_atomically(path, |partial| {
        let mut file = std::fs::File::create(partial).map_err(|e| OutputError::io(path, e))?;
        file.write_all(text.as_bytes())
            .map_err(|e| OutputError::io(path, e))
    })
}
