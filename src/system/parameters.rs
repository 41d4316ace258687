//! The parameters of an interpreted mechanism and their parameter-only values: the
//! routines' cache ([`mechanism_codegen::Role::ParameterCache`]), computed once per
//! parameter set, as the struct `mechanism!` emits caches them.

use mechanism_codegen::{Error, Model, Role, Routines};

use crate::system::routine::{Routine, Values};

/// Parameter values and the cache computed from them.
#[derive(Clone, Debug)]
pub(crate) struct Parameters {
    /// The values, in declaration order.
    values: Vec<f64>,
    /// The parameter-only values of `values`, in cache-slot order.
    cache: Vec<f64>,
    /// Computes `cache` from `values`.
    routine: Routine,
}

impl Parameters {
    /// The declared defaults of `model` and their cache, computed by the parameter-cache
    /// program of `routines`.
    ///
    /// # Errors
    /// As [`Routine::new`], for the parameter-cache program.
    pub(crate) fn new(model: &Model, routines: &Routines) -> Result<Self, Error> {
        let routine = Routine::new(
            routines.program(Role::ParameterCache)?,
            routines.sources(),
            routines.cache_len(),
        )?;
        let mut parameters = Self {
            values: model.parameters.iter().map(|p| p.default).collect(),
            cache: vec![0.0; routines.cache_len()],
            routine,
        };
        parameters.refresh();
        Ok(parameters)
    }

    /// The values, in declaration order.
    pub(crate) fn values(&self) -> &[f64] {
        &self.values
    }

    /// Sets parameter `index` and recomputes the cache; false when out of range.
    pub(crate) fn set(&mut self, index: usize, value: f64) -> bool {
        match self.values.get_mut(index) {
            Some(p) => {
                *p = value;
                self.refresh();
                true
            }
            None => false,
        }
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
