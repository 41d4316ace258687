//! A derived declaration's generated forward dynamics, interpreted: the routine of
//! [`mechanism_codegen::Role::ForwardDynamics`] (with tau, [`mechanism_codegen::Role::Forces`])
//! and its own parameter cache ([`mechanism_codegen::compile_forward_dynamics`]), which
//! [`crate::Interpreted`] compiles for a mechanism without constraint rows, as the macro
//! emits `forward_dynamics`.
//!
//! The routine solves M(q) q'' = u - b(t, q, q') straight-line, by whichever of two routes
//! the compilation found to count fewer operations: the factorisation M = L^T D L over M's
//! pattern, or for a tree of links the articulated-body recursion (O(n) on a chain, where
//! evaluating the dense M and factoring it costs O(n^2) and n^3 / 3).

use mechanism_codegen::{Equations, Error, Model, Role, compile_forward_dynamics};

use crate::ParameterError;
use crate::system::parameters::Parameters;
use crate::system::routine::{Routine, Values};

/// The forward-dynamics routine of one declaration without constraint rows, tau's, and the
/// parameter values they read.
#[derive(Clone, Debug)]
pub(crate) struct ForwardRoutine {
    /// The parameters and the cache of these routines' parameter-only values.
    parameters: Parameters,
    /// q'', the pivots and the references they must exceed 1e-14 of (3 n outputs).
    accelerations: Routine,
    /// tau (n outputs).
    forces: Routine,
    /// n.
    n: usize,
}

impl ForwardRoutine {
    /// Compiles the forward dynamics of the derived equations `eqs` of `model`; `None` for a
    /// mechanism with constraint rows, or one whose forward dynamics is past the derivation
    /// budget (the dense route then serves it).
    ///
    /// # Errors
    /// A compilation error from codegen other than a budget's (as
    /// [`crate::Interpreted::from_equations`]).
    pub(crate) fn new(model: &mut Model, eqs: &Equations) -> Result<Option<Self>, Error> {
        let routines = match compile_forward_dynamics(model, eqs) {
            Ok(Some(routines)) => routines,
            Ok(None) | Err(Error::Budget(_)) => return Ok(None),
            Err(e) => return Err(e),
        };
        let n = model.coordinates.len();
        let routine = |role: Role, outputs: usize| {
            Routine::new(routines.program(role)?, routines.sources(), outputs)
        };
        Ok(Some(Self {
            accelerations: routine(Role::ForwardDynamics, 3 * n)?,
            forces: routine(Role::Forces, n)?,
            parameters: Parameters::new(model, &routines)?,
            n,
        }))
    }

    /// Sets parameter `index` and recomputes the cache.
    ///
    /// # Errors
    /// As [`Parameters::set`]: an index out of range or a value outside its declared range.
    pub(crate) fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError> {
        self.parameters.set(index, value)
    }

    /// q'' = M^-1 (u - b) at (t, q, q') for the effort `effort` into `qdd`, and tau into
    /// `forces`; false (the outputs then hold no meaning) when a pivot is not finite or not
    /// above 1e-14 of its reference (M not positive definite beyond round-off), or q'' or
    /// tau is not finite: the test the emitted `forward_dynamics` makes.
    pub(crate) fn solve(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        effort: &[f64],
        qdd: &mut [f64],
        forces: &mut [f64],
    ) -> bool {
        let n = self.n;
        let values = Values {
            qd,
            effort,
            ..self.parameters.at(t, q)
        };
        let definite = self.accelerations.run(&values, |v| {
            let (acc, rest) = v.split_at(n);
            let (pivots, references) = rest.split_at(n);
            qdd.iter_mut().zip(acc).for_each(|(o, v)| *o = *v);
            let definite = pivots
                .iter()
                .zip(references)
                .fold(true, |ok, (d, m)| ok & (d.is_finite() && *d > 1e-14 * *m));
            definite & acc.iter().fold(true, |ok, x| ok & x.is_finite())
        });
        let finite = self.forces.run(&values, |v| {
            forces.iter_mut().zip(v).for_each(|(o, v)| *o = *v);
            v.iter().fold(true, |ok, x| ok & x.is_finite())
        });
        definite && finite
    }
}
