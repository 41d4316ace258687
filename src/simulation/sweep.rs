//! Parameter sweeps: many parameter sets, each run on its own clone of the system, in
//! parallel with rayon (cargo feature `parallel`, on by default; one after the other
//! without it). Parameters are run-time values of the generated struct, so nothing is
//! rebuilt between sets.

#[cfg(feature = "parallel")]
use rayon::prelude::*;

use crate::error::Error;
use crate::system::System;

/// A parameter set: (name, value) pairs; parameters not named keep the system's values.
pub type ParameterSet = Vec<(String, f64)>;

/// A clone of `system` with the named parameters set ([`Error::UnknownParameter`] for a
/// name the system does not declare, [`Error::NonFinite`] for a NaN or infinite value,
/// [`Error::ParameterOutOfRange`] for one outside the declared range); the initial values
/// of its `info` follow them.
fn with_parameters<S: System + Clone>(system: &S, set: &[(String, f64)]) -> Result<S, Error> {
    let mut s = system.clone();
    for (name, value) in set {
        let info = s.info();
        let i = info
            .parameter_index(name)
            .ok_or_else(|| Error::UnknownParameter {
                name: name.clone(),
                known: info.parameters.clone(),
            })?;
        if !value.is_finite() {
            return Err(Error::NonFinite {
                what: format!("parameter {name}"),
                t: 0.0,
            });
        }
        s.set_parameter(i, *value)
            .map_err(|_| Error::ParameterOutOfRange {
                name: name.clone(),
                value: *value,
                range: s.info().parameter_range(i),
            })?;
    }
    Ok(s)
}

/// Applies `f` to a clone of `system` for each parameter set, in parallel (feature
/// `parallel`); results in the order of `sets`. A set that names a parameter the system
/// does not declare gives [`Error::UnknownParameter`] in its place, one with a NaN or
/// infinite value [`Error::NonFinite`], one outside a declared range
/// [`Error::ParameterOutOfRange`].
pub fn sweep<S, R, F>(system: &S, sets: &[ParameterSet], f: F) -> Vec<Result<R, Error>>
where
    S: System + Clone,
    R: Send,
    F: Fn(&S) -> Result<R, Error> + Sync,
{
    let run = |set: &ParameterSet| with_parameters(system, set).and_then(|s| f(&s));
    #[cfg(feature = "parallel")]
    return sets.par_iter().map(run).collect();
    #[cfg(not(feature = "parallel"))]
    return sets.iter().map(run).collect();
}
