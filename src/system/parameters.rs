//! The parameters of an interpreted mechanism and what is computed from them alone: the
//! routines' cache ([`mechanism_codegen::Role::ParameterCache`]), computed once per
//! parameter set, as the struct `mechanism!` emits caches them, and the declared initial
//! values ([`mechanism_codegen::Role::InitialValues`]), which follow every change.

use mechanism_codegen::{Error, Model, Role, Routines};

use crate::system::parameter_range::{ParameterError, ParameterRange, check_parameter};
use crate::system::routine::{Routine, Values};
use crate::system::{Independent, SystemInfo};

/// Parameter values, their declared ranges, and what is computed from them.
#[derive(Clone, Debug)]
pub(crate) struct Parameters {
    /// The values, in declaration order.
    values: Vec<f64>,
    /// The declared range of each, in declaration order.
    ranges: Vec<ParameterRange>,
    /// The parameter-only values of `values`, in cache-slot order.
    cache: Vec<f64>,
    /// Computes `cache` from `values`.
    routine: Routine,
    /// Computes the initial guesses and the independent values from `values`.
    initial: Routine,
}

/// The runtime's copy of a declared range.
pub(crate) fn declared_range(declared: mechanism_codegen::ParameterRange) -> ParameterRange {
    match declared {
        mechanism_codegen::ParameterRange::Any => ParameterRange::Any,
        mechanism_codegen::ParameterRange::Positive => ParameterRange::Positive,
        mechanism_codegen::ParameterRange::NonNegative => ParameterRange::NonNegative,
    }
}

impl Parameters {
    /// The declared defaults of `model` and their cache, computed by the parameter-cache
    /// program of `routines`.
    ///
    /// # Errors
    /// As [`Routine::new`], for the parameter-cache and initial-value programs.
    pub(crate) fn new(model: &Model, routines: &Routines) -> Result<Self, Error> {
        let routine = Routine::new(
            routines.program(Role::ParameterCache)?,
            routines.sources(),
            routines.cache_len(),
        )?;
        let initial = Routine::new(
            routines.program(Role::InitialValues)?,
            routines.sources(),
            model.coordinates.len() + 2 * model.independent.len(),
        )?;
        let mut parameters = Self {
            values: model.parameters.iter().map(|p| p.default).collect(),
            ranges: model
                .parameters
                .iter()
                .map(|p| declared_range(p.range))
                .collect(),
            cache: vec![0.0; routines.cache_len()],
            routine,
            initial,
        };
        parameters.refresh();
        Ok(parameters)
    }

    /// The values, in declaration order.
    pub(crate) fn values(&self) -> &[f64] {
        &self.values
    }

    /// Sets parameter `index` and recomputes the cache.
    ///
    /// # Errors
    /// An index out of range or a value outside the declared range ([`check_parameter`]).
    pub(crate) fn set(&mut self, index: usize, value: f64) -> Result<(), ParameterError> {
        check_parameter(index, value, self.values.len(), &self.ranges)?;
        self.values[index] = value;
        self.refresh();
        Ok(())
    }

    /// The values of an evaluation at (t, q) with these parameters.
    pub(crate) fn at<'a>(&'a self, t: f64, q: &'a [f64]) -> Values<'a> {
        Values {
            parameters: &self.values,
            cache: &self.cache,
            t,
            q,
            ..Values::default()
        }
    }

    /// Writes the initial guesses and the independent coordinates' positions and rates at
    /// the current values into `info` (whose independent entries name the coordinates).
    pub(crate) fn write_initial_values(&self, info: &mut SystemInfo) {
        let values = Values {
            parameters: &self.values,
            ..Values::default()
        };
        let n = info.initial_guess.len();
        self.initial.run(&values, |v| {
            let (guess, independent) = v.split_at(n.min(v.len()));
            info.initial_guess.copy_from_slice(guess);
            for (entry, pair) in info.independent.iter_mut().zip(independent.chunks_exact(2)) {
                *entry = Independent {
                    coordinate: entry.coordinate,
                    position: pair[0],
                    velocity: pair[1],
                };
            }
        });
    }

    /// The first `n` outputs of the initial-value program at the current values: the
    /// initial guesses of the coordinates.
    pub(crate) fn initial_guess(&self, n: usize) -> Vec<f64> {
        let values = Values {
            parameters: &self.values,
            ..Values::default()
        };
        self.initial.run(&values, |v| v[..n.min(v.len())].to_vec())
    }

    /// Computes the cache of the current values.
    fn refresh(&mut self) {
        let values = Values {
            parameters: &self.values,
            ..Values::default()
        };
        let cache = &mut self.cache;
        self.routine.run(&values, |v| cache.copy_from_slice(v));
    }
}
