//! A system with an effort added to its declared forces: what `forward_dynamics` hands the
//! library's augmented solve ([`mechanism::Dynamics`]), so that the accelerations under an
//! applied effort come from the same solver as every simulation's. For a batch's row the
//! evaluation is one already made side by side with the other rows ([`WithEffort::evaluated`]).

use mechanism::{Evaluation, Kinematic, ParameterError, Sparsity, System, SystemInfo};
use nalgebra::DMatrix;

/// `inner` with the generalised force `effort` (n values) added to tau, evaluated by
/// `inner` or, for a batch's row, as the given evaluation.
pub struct WithEffort<'a, S: System> {
    inner: &'a S,
    effort: &'a [f64],
    /// The evaluation at the row's (t, q, q'): the solve, which asks only there, then
    /// evaluates nothing itself.
    evaluation: Option<&'a Evaluation>,
}

impl<'a, S: System> WithEffort<'a, S> {
    /// `inner` with `effort` added to its forces.
    pub fn new(inner: &'a S, effort: &'a [f64]) -> Self {
        Self {
            inner,
            effort,
            evaluation: None,
        }
    }

    /// `inner` evaluated as `evaluation` (made at the state the solve will ask for), with
    /// `effort` added to its forces.
    pub fn evaluated(inner: &'a S, evaluation: &'a Evaluation, effort: &'a [f64]) -> Self {
        Self {
            inner,
            effort,
            evaluation: Some(evaluation),
        }
    }
}

impl<S: System> Kinematic for WithEffort<'_, S> {
    fn info(&self) -> &SystemInfo {
        self.inner.info()
    }
    fn constraints(&self, t: f64, q: &[f64], phi: &mut [f64]) {
        self.inner.constraints(t, q, phi);
    }
    fn constraint_jacobian(&self, t: f64, q: &[f64], phi_q: &mut DMatrix<f64>, phi_t: &mut [f64]) {
        self.inner.constraint_jacobian(t, q, phi_q, phi_t);
    }
}

impl<S: System> System for WithEffort<'_, S> {
    fn parameter_values(&self, out: &mut [f64]) {
        self.inner.parameter_values(out);
    }
    fn set_parameter(&mut self, index: usize, _value: f64) -> Result<(), ParameterError> {
        // Borrowed: the parameters belong to the model, and this view changes none.
        Err(ParameterError::NoSuchParameter { index, count: 0 })
    }
    fn evaluate(&self, t: f64, q: &[f64], qd: &[f64], out: &mut Evaluation) {
        match self.evaluation {
            None => self.inner.evaluate(t, q, qd, out),
            Some(e) => copy_evaluation(e, out),
        }
        for (f, u) in out.forces.iter_mut().zip(self.effort) {
            *f += u;
        }
    }
    fn sparsity(&self) -> Option<&Sparsity> {
        self.inner.sparsity()
    }
}

/// `out` = `e`, entry by entry into `out`'s own storage (no allocation).
fn copy_evaluation(e: &Evaluation, out: &mut Evaluation) {
    out.mass.copy_from(&e.mass);
    out.phi_q.copy_from(&e.phi_q);
    for (o, x) in [
        (&mut out.coriolis, &e.coriolis),
        (&mut out.gravity, &e.gravity),
        (&mut out.forces, &e.forces),
        (&mut out.phi, &e.phi),
        (&mut out.phi_t, &e.phi_t),
        (&mut out.gamma, &e.gamma),
    ] {
        o.copy_from(x);
    }
    out.kinetic = e.kinetic;
    out.potential = e.potential;
}
