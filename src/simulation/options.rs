//! What a forward simulation is asked to do: time span, output rate, integrator,
//! stabilisation, initial state, events and limits.

use crate::algorithms::dynamics::DEFAULT_CONDITION_LIMIT;
use crate::algorithms::kinematics::AssemblyOptions;
use crate::algorithms::stabilization::Stabilization;
use crate::integrators::IntegratorOptions;
use crate::simulation::events::Event;
use crate::system::Independent;

/// Output samples whose storage is reserved before the first step.
pub(crate) const RESERVED_SAMPLES: usize = 1_000_000;

/// Where the simulation starts.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum InitialState {
    /// Assemble from the declared independent coordinates and guesses.
    #[default]
    Declared,
    /// Assemble from these independent coordinates (declared guesses for the rest).
    Independent(Vec<Independent>),
    /// A state the user asserts is consistent (checked: |Phi| and |Phi_q q' + Phi_t| below
    /// 1e-8, then projected when the stabilisation is projection).
    Consistent {
        /// Positions q(t0).
        q: Vec<f64>,
        /// Rates q'(t0).
        qd: Vec<f64>,
    },
}

/// Everything a forward simulation needs besides the system.
#[derive(Clone, Debug)]
pub struct SimulationOptions {
    /// Start time (s).
    pub t_start: f64,
    /// End time (s).
    pub t_end: f64,
    /// Output samples per second (default 100); the end time is always a sample.
    pub output_rate: f64,
    /// Method and step-size control.
    pub integrator: IntegratorOptions,
    /// Constraint stabilisation (default projection).
    pub stabilization: Stabilization,
    /// Initial state.
    pub initial: InitialState,
    /// Newton options for the assembly.
    pub assembly: AssemblyOptions,
    /// Event functions.
    pub events: Vec<Event>,
    /// Condition-estimate limit of the LU route of the augmented solve, beyond which it
    /// hands over to the augmented Lagrangian route ([`crate::Dynamics`]).
    pub condition_limit: f64,
}

impl Default for SimulationOptions {
    fn default() -> Self {
        Self {
            t_start: 0.0,
            t_end: 10.0,
            output_rate: 100.0,
            integrator: IntegratorOptions::default(),
            stabilization: Stabilization::default(),
            initial: InitialState::default(),
            assembly: AssemblyOptions::default(),
            events: Vec::new(),
            condition_limit: DEFAULT_CONDITION_LIMIT,
        }
    }
}
