//! # mechanism
//!
//! Closed-loop mechanism dynamics: declare a mechanism once with [`mechanism!`], get its
//! Lagrange equations with multipliers derived at build time as specialised, allocation-free
//! Rust, then assemble, simulate and plot it.
//!
//! ```text
//! M(q) q'' + C(q, q') q' + g(q) + Phi_q(q, t)^T lambda = tau(t, q, q'),      Phi(q, t) = 0
//! ```
//!
//! The package is `mechanism-dynamics` (the name `mechanism` on crates.io belongs to an
//! unrelated crate); the library keeps the import name `mechanism`, the one the generated
//! code and every example use.
//!
//! ## Declare, simulate, embed
//!
//! A pendulum of length l in Cartesian coordinates, the rod a constraint; simulated with
//! the run-time solvers, then stepped in a loop of your own with the `no_std` fixed-size
//! solvers, as a controller would:
//!
//! ```
//! use mechanism::prelude::*;
//!
//! // 1. Declare. The equations are derived when this compiles; see `language` for the
//! //    whole declaration language.
//! mechanism! {
//!     /// A point mass on a rod of length l, x right and y up.
//!     pub struct Pendulum;
//!     parameters { m = 1.0; l = 1.0; g = 9.81; }   // kg, m, m/s^2
//!     coordinates { x = 0.6; y = -0.8; }          // initial guesses: the lower branch
//!     independent { x = 0.6; }                     // released from rest at x = 0.6 m
//!     kinetic = 1/2*m*(der(x)^2 + der(y)^2);
//!     potential = m*g*y;
//!     constraints { x^2 + y^2 - l^2; }
//! }
//!
//! fn main() -> Result<(), Box<dyn std::error::Error>> {
//!     // 2. Simulate: assembled from `independent`, DOP853, the loop closed by projection.
//!     let system = Compiled::new(Pendulum::default());
//!     let options = SimulationOptions { t_end: 2.0, ..SimulationOptions::default() };
//!     let trajectory = simulate(&system, &options)?;
//!     let end = trajectory.last().expect("samples");
//!     let (x, y) = (end.q[0], end.q[1]);
//!     assert!((x * x + y * y - 1.0).abs() < 1e-12); // the rod keeps its length
//!
//!     // 3. Embed: the generated code in your own loop (no allocation; works without std):
//!     //    RK4 steps of 1 ms, each projected back onto the constraints.
//!     let model = Pendulum::default();
//!     let q = Coordinates::from([0.6, -0.8]);
//!     let mut state = State { t: 0.0, q, qd: Velocities::zeros() };
//!     let stepper = FixedStep::new(1e-3);
//!     for _ in 0..2000 {
//!         stepper.step(&model, &mut state)?;
//!     }
//!     // Energy is conserved (T + Pi = m g y(0)), and both routes reach the same place.
//!     let energy = model.kinetic_energy(&state.q, &state.qd) + model.potential_energy(&state.q);
//!     assert!((energy - 9.81 * -0.8).abs() < 1e-8);
//!     assert!((state.q[0] - x).abs() < 1e-6 && (state.q[1] - y).abs() < 1e-6);
//!     Ok(())
//! }
//! ```
//!
//! The same declaration in a file is `mechanism!(file = "pendulum.mech");`, and
//! [`Interpreted`](crate#features) derives a `.mech` at run time. The command-line tool
//! (`cargo run --release -- simulate FILE.mech`) writes the trajectory, a summary, the
//! figures and an animation page.
//!
//! ## Where things are
//!
//! - [`language`]: the declaration language, its grammar, sections and functions.
//! - [`Mechanism`]: what `mechanism!` emits (static sizes, one method per derived
//!   quantity); [`System`] is the run-time face the solvers read (its supertrait
//!   [`Kinematic`], the constraint rows, is all that assembly and the mobility read),
//!   [`Compiled`] adapts one to the other.
//! - [`simulate`], [`inverse_dynamics`], [`linearize`], [`mobility`], [`assemble`]: the
//!   algorithms; [`integrators`] underneath; [`Trajectory`] the result.
//! - [`fixed`]: the `no_std` KKT solve and fixed step; [`math`]: the real functions the
//!   generated code calls.
//! - [`output`]: CSV, `summary.json`, figures and the animation page.
//!
//! The command-line tool is a separate binary on top of this API. `ARCHITECTURE.md` draws
//! the whole path.
//!
//! ## Features
//!
//! Without default features the crate is `#![no_std]` and allocation-free: the generated
//! code ([`mechanism!`], [`Mechanism`]), the real functions it calls (`math`), and the
//! fixed-size solvers in [`fixed`] (the KKT solve for q'' and lambda, one fixed step with
//! projection). `std` adds the run-time library (the `System` face, the adaptive
//! integrators, simulation, inverse dynamics, linearisation); `interpreter` derives
//! mechanisms from text at run time (`Interpreted`); `builtin` compiles the mechanisms of
//! `mechanisms/`; `files`, `plots`, `parallel`, `progress` and `cli` serve the command-line
//! tool.
#![cfg_attr(not(feature = "std"), no_std)]
#![warn(missing_docs)]

#[cfg(feature = "std")]
mod algorithms;
#[cfg(feature = "builtin")]
pub mod builtin;
#[cfg(feature = "std")]
mod error;
pub mod fixed;
#[cfg(feature = "std")]
pub mod integrators;
pub mod language;
#[cfg(feature = "std")]
mod limits;
#[cfg(feature = "std")]
mod linalg;
#[cfg(feature = "std")]
pub mod output;
#[cfg(feature = "std")]
mod simulation;
mod system;

#[cfg(feature = "interpreter")]
pub use crate::algorithms::drive::{DriveError, parse_drive};
#[cfg(feature = "std")]
pub use crate::algorithms::dynamics::{DEFAULT_CONDITION_LIMIT, Dynamics};
#[cfg(feature = "std")]
pub use crate::algorithms::dynamics_derivatives::DynamicsDerivatives;
#[cfg(feature = "std")]
pub use crate::algorithms::floating_motion::{
    FloatingStep, FloatingTrajectory, QUATERNION_NORM_TOLERANCE, simulate_floating,
};
#[cfg(feature = "interpreter")]
pub use crate::algorithms::interpreted_floating_motion::simulate_interpreted_floating;
#[cfg(feature = "std")]
pub use crate::algorithms::inverse::{
    InverseDynamics, InverseResult, InverseSample, check_inverse_dynamics, inverse_dynamics,
    inverse_dynamics_from, sample_times,
};
#[cfg(feature = "std")]
pub use crate::algorithms::kinematics::{
    AssemblyOptions, Drive, KinematicState, assemble, assemble_from, kinematic_analysis,
    solve_accelerations, solve_positions, solve_velocities,
};
#[cfg(feature = "std")]
pub use crate::algorithms::linearize::{Linearization, linearize};
#[cfg(feature = "std")]
pub use crate::algorithms::mobility::{Mobility, mobility};
#[cfg(feature = "std")]
pub use crate::algorithms::stabilization::Stabilization;
#[cfg(feature = "std")]
pub use crate::algorithms::steady::{SteadyLinearization, SteadyOptions, linearize_steady};
#[cfg(feature = "std")]
pub use crate::error::{Error, OrientationSingularity};
#[cfg(feature = "std")]
pub use crate::integrators::{IntegratorOptions, Method, StepController};
#[cfg(feature = "std")]
pub use crate::limits::{MAX_OUTPUT_BYTES, MAX_OUTPUT_SAMPLES};
#[cfg(feature = "std")]
pub use crate::simulation::apex::PassageGeometry;
#[cfg(feature = "std")]
pub use crate::simulation::events::{Event, EventAction, EventFn, EventHit};
#[cfg(feature = "std")]
pub use crate::simulation::options::{InitialState, SimulationOptions};
#[cfg(feature = "std")]
pub use crate::simulation::simulator::{
    Simulation, Simulator, simulate, simulate_recording, simulate_with_events,
};
#[cfg(feature = "std")]
pub use crate::simulation::singular::SingularPassage;
#[cfg(feature = "std")]
pub use crate::simulation::sweep::{ParameterSet, sweep};
#[cfg(feature = "std")]
pub use crate::simulation::trajectory::{Sample, SolverStats, Trajectory};
pub use crate::system::free_flyer::integrate as integrate_floating;
pub use crate::system::{
    Accelerations, Coordinates, EvaluationSlices, FloatingBase, Independent, JointLimits,
    Mechanism, Multipliers, ParameterError, ParameterRange, RotationFactor, StaticEvaluation,
    StaticSparsity, Velocities,
};
#[cfg(feature = "std")]
pub use crate::system::{
    BodyOrientation, Compiled, ConstraintRow, ConstraintTangent, Drawing, DrawnPoint, Evaluation,
    Kinematic, Sparsity, System, SystemInfo, Tangent,
};
#[cfg(feature = "interpreter")]
pub use crate::system::{
    FloatingDerivatives, Interpreted, InterpretedConstraints, InterpretedFloating, Momentum,
};
/// The declaration language is documented in [`language`]; what the expansion implements
/// is [`Mechanism`].
pub use mechanism_macros::mechanism;
/// The real functions the code generated by [`mechanism!`] calls (`sin_cos`, `sqrt`, `powi`,
/// ...): std's with the `std` feature, libm's without.
pub use mechanism_math as math;
pub use nalgebra;

/// What a crate that declares and runs mechanisms uses: the macro, the traits, the vector
/// aliases, the fixed-size solvers, and with `std` the simulation and inverse dynamics.
pub mod prelude {
    pub use crate::fixed::{FixedError, FixedStep, KktSolution, State, kkt_solve};
    pub use crate::{
        Accelerations, Coordinates, Independent, Mechanism, Multipliers, StaticEvaluation,
        Velocities, mechanism,
    };
    #[cfg(feature = "std")]
    pub use crate::{
        AssemblyOptions, Compiled, Error, InitialState, Kinematic, SimulationOptions, System,
        Trajectory, inverse_dynamics, simulate,
    };
    #[cfg(feature = "interpreter")]
    pub use crate::{Interpreted, parse_drive};
    pub use nalgebra::{SMatrix, SVector};
}

/// The Rust examples of the README and of the book (`docs/src/`, one item per chapter),
/// compiled and run as doc-tests; `.ci/docs.py` checks that every chapter of
/// `docs/src/SUMMARY.md` is listed here.
#[cfg(doctest)]
mod book {
    #[doc = include_str!("../README.md")]
    struct Readme;
    #[doc = include_str!("../docs/src/introduction.md")]
    struct Introduction;
    #[doc = include_str!("../docs/src/building.md")]
    struct Building;
    #[doc = include_str!("../docs/src/seed.md")]
    struct Seed;
    #[doc = include_str!("../docs/src/command-line.md")]
    struct CommandLine;
    #[doc = include_str!("../docs/src/declaring.md")]
    struct Declaring;
    #[doc = include_str!("../docs/src/overconstrained.md")]
    struct Overconstrained;
    #[doc = include_str!("../docs/src/nonholonomic.md")]
    struct Nonholonomic;
    #[doc = include_str!("../docs/src/robots.md")]
    struct Robots;
    #[doc = include_str!("../docs/src/floating.md")]
    struct Floating;
    #[doc = include_str!("../docs/src/derivatives.md")]
    struct Derivatives;
    #[doc = include_str!("../docs/src/embedding.md")]
    struct Embedding;
    #[doc = include_str!("../docs/src/python.md")]
    struct Python;
    #[doc = include_str!("../docs/src/solvers.md")]
    struct Solvers;
    #[doc = include_str!("../docs/src/algebra.md")]
    struct Algebra;
    #[doc = include_str!("../docs/src/reliability.md")]
    struct Reliability;
    #[doc = include_str!("../docs/src/layout.md")]
    struct Layout;
}

/// Not API: what generated code names.
#[doc(hidden)]
pub mod __private {
    pub use crate::fixed::{FixedError, KktSolution, kkt_solve, kkt_tree_solve};
    pub use crate::system::check_parameter;
    pub use nalgebra::ArrayStorage;
    pub use nalgebra::{SMatrix, SVector};
}
