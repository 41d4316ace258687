//! Event functions g(t, q, q') whose sign changes end or mark a simulation, and the
//! crossings found, located by the Illinois variant of regula falsi ([`illinois`]).

use std::fmt;
use std::sync::Arc;

use crate::error::Error;

/// What to do when an event function changes sign.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EventAction {
    /// Record the crossing and end the simulation there (last sample at the crossing).
    Stop,
    /// Record the crossing and continue.
    Record,
}

/// An event function g(t, q, q').
pub type EventFn = Arc<dyn Fn(f64, &[f64], &[f64]) -> f64 + Send + Sync>;

/// A user function g(t, q, q') whose sign changes are located to round-off on the dense
/// output of the step in which they occur.
#[derive(Clone)]
pub struct Event {
    /// Name for reports.
    pub name: String,
    /// g(t, q, q'); should not allocate.
    pub g: EventFn,
    /// Stop or record.
    pub action: EventAction,
}

impl Event {
    /// An event called `name` with function `g` and `action`.
    pub fn new(
        name: &str,
        action: EventAction,
        g: impl Fn(f64, &[f64], &[f64]) -> f64 + Send + Sync + 'static,
    ) -> Self {
        Self {
            name: name.to_string(),
            g: Arc::new(g),
            action,
        }
    }
}

impl fmt::Debug for Event {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("Event")
            .field("name", &self.name)
            .field("action", &self.action)
            .finish_non_exhaustive()
    }
}

/// One located sign change of an event function.
#[derive(Clone, Debug, PartialEq)]
pub struct EventHit {
    /// Index of the event in [`crate::SimulationOptions::events`].
    pub event: usize,
    /// Time of the crossing (s).
    pub t: f64,
    /// q at the crossing.
    pub q: Vec<f64>,
    /// q' at the crossing.
    pub qd: Vec<f64>,
}

/// The event functions' state during a run: g at the start of the current step, the roots
/// located inside it, the crossings recorded and the event that stopped the run.
pub(crate) struct EventLog {
    /// g_i(t, q, q') at the start of the step.
    pub(crate) g_old: Vec<f64>,
    /// Located root of each event inside the step (NaN: none).
    pub(crate) roots: Vec<f64>,
    /// Crossings recorded so far, in time order.
    pub(crate) hits: Vec<EventHit>,
    /// Index of the event that stopped the run.
    pub(crate) stopped_by: Option<usize>,
}

impl EventLog {
    /// State for `count` event functions.
    pub(crate) fn new(count: usize) -> Self {
        Self {
            g_old: vec![0.0; count],
            roots: vec![f64::NAN; count],
            hits: Vec::with_capacity(16),
            stopped_by: None,
        }
    }

    /// Evaluates every g at (t, q, q') as the start values of the next step.
    pub(crate) fn restart(&mut self, events: &[Event], t: f64, q: &[f64], qd: &[f64]) {
        for (g, ev) in self.g_old.iter_mut().zip(events) {
            *g = (ev.g)(t, q, qd);
        }
    }
}

/// The root of g on the step, as a fraction of it, by the Illinois variant of regula falsi
/// (Dowell & Jarratt 1971) from g(0) = g0 and g(1) = g1 of opposite signs, to 4 eps of t;
/// `g(c)` evaluates g at t0 + c h on the dense output.
pub(crate) fn illinois(
    g0: f64,
    g1: f64,
    h: f64,
    t0: f64,
    mut g: impl FnMut(f64) -> Result<f64, Error>,
) -> Result<f64, Error> {
    let (mut a, mut fa, mut b, mut fb) = (0.0f64, g0, 1.0f64, g1);
    let mut side = 0i8;
    for _ in 0..200 {
        if fb == 0.0 || (b - a) * h <= 4.0 * f64::EPSILON * (t0.abs() + h) {
            break;
        }
        let mut c = (a * fb - b * fa) / (fb - fa);
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
        }
        let fc = g(c)?;
        if fc == 0.0 {
            return Ok(c);
        }
        // Keep the bracket; halve the retained end's value when it is kept twice.
        if (fc > 0.0) == (fb > 0.0) {
            (b, fb) = (c, fc);
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            (a, fa) = (c, fc);
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
    }
    Ok(b)
}
