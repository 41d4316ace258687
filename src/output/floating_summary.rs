//! `summary.json` of a floating-base run (`mechanism simulate robot.mech` of a declaration
//! whose root link floats): the state it started from, how it stepped, and the
//! conservation checks of a robot under gravity and its declared efforts alone.
//!
//! With no declared effort, the exact motion keeps E = T + Pi, the angular momentum L_c
//! about the centre of mass (gravity's moment about it is zero) and p - F t, the linear
//! momentum less the impulse of the constant weight F = m g; the run reports the largest
//! departure of each from its start, which is then the integration's error. With declared
//! efforts the same figures measure what the efforts did (`efforts_declared` says so).

use std::path::Path;

use serde::Serialize;

use super::OutputError;
use super::outcome::Outcome;
use super::summary::{NamedValues, write_json};

/// The starting state of a floating-base run: q by the configuration's names and v by the
/// velocities' (the quaternion as normalised).
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct FloatingInitialState {
    /// q(0).
    pub q: NamedValues,
    /// v(0).
    pub v: NamedValues,
}

/// The conservation checks of a floating-base run (module docs), each the largest
/// departure over the samples from its value at t = 0.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Conservation {
    /// E(0) = T + Pi at the start (J).
    pub energy_initial: f64,
    /// max |E(t) - E(0)| (J).
    pub max_energy_error: f64,
    /// max |p(t) - p(0) - F t| (kg m/s), world axes.
    pub max_linear_momentum_error: f64,
    /// max |L_c(t) - L_c(0)| (kg m^2/s), world axes.
    pub max_angular_momentum_error: f64,
    /// max ||quaternion| - 1| over the samples.
    pub max_quaternion_norm_error: f64,
    /// Whether the declaration gives efforts of its own (then the figures above measure
    /// them, not the integration's error).
    pub efforts_declared: bool,
}

/// The contents of a floating-base run's `summary.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FloatingSummary {
    /// Mechanism name.
    pub mechanism: String,
    /// Parameter values by name.
    pub parameters: NamedValues,
    /// q(0), v(0).
    pub initial_state: FloatingInitialState,
    /// `rk4` (fixed steps of `step`, the quaternion projected onto |quaternion| = 1 after
    /// each).
    pub integrator: String,
    /// The step (s).
    pub step: f64,
    /// Steps taken.
    pub steps: usize,
    /// Forward dynamics evaluated (four per step).
    pub rhs_evaluations: usize,
    /// Wall-clock time of the integration (s).
    pub wall_time_s: f64,
    /// The conservation checks.
    pub conservation: Conservation,
    /// `status`, `t_last`, `error`, `stage`, `files`.
    #[serde(flatten)]
    pub outcome: Outcome,
}

/// Writes `summary` as pretty-printed JSON to `path`, marked as ours, atomically (as
/// [`super::write_summary`]).
pub fn write_floating_summary(path: &Path, summary: &FloatingSummary) -> Result<(), OutputError> {
    write_json(path, summary)
}
