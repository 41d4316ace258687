//! # mechanism
//!
//! Closed-loop mechanism dynamics: declare a mechanism once with [`mechanism!`], get its
//! Lagrange equations with multipliers derived at build time as specialised, allocation-free
//! Rust, then assemble, simulate and plot it.
#![warn(missing_docs)]

pub mod builtin;
pub mod cli;
mod drive;
mod interpreted;
mod mechanism;
pub mod output;
mod progress;
mod trajectory;

// Runtime solvers (issue 4).
mod dynamics;
mod error;
pub mod integrators;
mod inverse;
mod kinematics;
pub mod linalg;
mod linearize;
mod simulate;
mod stabilization;
mod sweep;

pub use crate::drive::{DriveError, parse_drive};
pub use crate::interpreted::Interpreted;
pub use crate::mechanism::{
    Compiled, Evaluation, Independent, Mechanism, StaticEvaluation, System, SystemInfo,
};
pub use crate::trajectory::{Sample, SolverStats, Trajectory};

pub use crate::dynamics::{DEFAULT_CONDITION_LIMIT, Dynamics};
pub use crate::error::Error;
pub use crate::integrators::{IntegratorOptions, Method};
pub use crate::inverse::{
    InverseDynamics, InverseResult, InverseSample, inverse_dynamics, sample_times,
};
pub use crate::kinematics::{
    AssemblyOptions, Drive, KinematicState, assemble, assemble_from, check_constraint_rank,
    kinematic_analysis, solve_accelerations, solve_positions, solve_velocities,
};
pub use crate::linearize::{Linearization, linearize};
pub use crate::mechanism::Tangent;
pub use crate::progress::Progress;
pub use crate::simulate::{
    Event, EventAction, EventFn, EventHit, InitialState, MAX_OUTPUT_SAMPLES, Simulation,
    SimulationOptions, Simulator, simulate, simulate_with_events,
};
pub use crate::stabilization::{Projector, Stabilization};
pub use crate::sweep::{ParameterSet, sweep, sweep_simulate, with_parameters};
pub use mechanism_macros::mechanism;
pub use nalgebra;

/// Everything a declaration needs: the macro, the traits and the nalgebra types.
pub mod prelude {
    pub use crate::{Compiled, Independent, Mechanism, StaticEvaluation, System, mechanism};
    pub use nalgebra::{SMatrix, SVector};
}

#[doc(hidden)]
pub mod __private {
    pub use nalgebra::ArrayStorage;
    pub use nalgebra::{SMatrix, SVector};
}
