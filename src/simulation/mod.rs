//! Forward simulation: the index-3 DAE integrated as an ODE in y = [q, q', W] with the
//! accelerations from [`crate::Dynamics`], a constraint stabilisation after each step, output
//! samples from the dense output, located events and recorded singular passages.
//!
//! What enters: a [`crate::System`] and [`SimulationOptions`]. What leaves: a
//! [`Trajectory`] (one row per output sample: t, q, q', q'', lambda, |Phi|,
//! |Phi_q q' + Phi_t|, T, Pi, W) with its run counters, mobility and singular passages, and
//! the events. A run that cannot succeed stops early ([`fail_fast`]: a fixed step too small, a
//! collapsed step size, a diverging state). Invariant: the step loop ([`Simulator::step`])
//! allocates nothing; every buffer is made in [`Simulator::new`].
//!
//! The parts: [`simulator`] orchestrates; [`start`] checks what a run starts from; [`rhs`]
//! is y' = f(t, y), built once per run; [`stepper`] holds the method with its step control
//! and dense output; [`events`], [`singular`] and [`fail_fast`] watch the steps;
//! [`apex`] tells the singular positions a nearby motion passes through from those it can miss.

pub(crate) mod apex;
pub(crate) mod events;
pub(crate) mod fail_fast;
pub(crate) mod options;
pub(crate) mod rhs;
pub(crate) mod simulator;
pub(crate) mod singular;
pub(crate) mod start;
pub(crate) mod stepper;
pub(crate) mod sweep;
pub(crate) mod trajectory;
