//! What a run starts from, checked before any work: the options, the number of output
//! samples, and the initial state q(t0), q'(t0).

// Comparisons are written `!(x > 0.0)` on purpose: NaN must fail them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::algorithms::kinematics::{assemble, assemble_from};
use crate::error::Error;
use crate::limits::MAX_OUTPUT_SAMPLES;
use crate::simulation::options::{InitialState, SimulationOptions};
use crate::system::System;

/// Parameters finite; t_end > t_start, output_rate > 0, rtol > 0 and atol >= 0 finite.
pub(crate) fn check_options(system: &dyn System, options: &SimulationOptions) -> Result<(), Error> {
    let info = system.info();
    let mut params = vec![0.0; info.parameters.len()];
    system.parameter_values(&mut params);
    Error::check_finite(&params, "parameter", &info.parameters, options.t_start)?;
    let io = &options.integrator;
    let bad = |option, value, allowed| {
        Err(Error::InvalidOption {
            option,
            value,
            allowed,
        })
    };
    if !(options.t_end > options.t_start) {
        return bad("t_end", options.t_end, "after t_start");
    }
    if !(options.output_rate > 0.0) {
        return bad(
            "output_rate",
            options.output_rate,
            "positive, in samples per second",
        );
    }
    if !(io.rtol > 0.0 && io.rtol.is_finite()) {
        return bad("rtol", io.rtol, "positive and finite");
    }
    if !(io.atol >= 0.0 && io.atol.is_finite()) {
        return bad("atol", io.atol, "zero or positive, and finite");
    }
    Ok(())
}

/// Output samples after the first: one per 1/output_rate, the end time always included;
/// refused beyond [`MAX_OUTPUT_SAMPLES`] before any work.
pub(crate) fn output_count(options: &SimulationOptions) -> Result<usize, Error> {
    let span = options.t_end - options.t_start;
    // t_end > t_start and rate > 0 are checked, so this is not NaN.
    let samples = ((span * options.output_rate) - 1e-9).ceil().max(1.0);
    if samples > MAX_OUTPUT_SAMPLES as f64 {
        return Err(Error::TooManySamples {
            span,
            rate: options.output_rate,
            samples,
            limit: MAX_OUTPUT_SAMPLES,
        });
    }
    Ok(samples as usize)
}

/// q(t0) and q'(t0): assembled from the declared or given independent coordinates, or the
/// consistent state given (its consistency is checked after the first solve).
pub(crate) fn initial_state(
    system: &dyn System,
    options: &SimulationOptions,
) -> Result<(Vec<f64>, Vec<f64>), Error> {
    let info = system.info();
    let (n, t0) = (info.n(), options.t_start);
    let (q, qd) = match &options.initial {
        InitialState::Declared => {
            let s = assemble(system, t0, &options.assembly)?;
            (s.q, s.qd)
        }
        InitialState::Independent(ind) => {
            let s = assemble_from(system, t0, ind, &info.initial_guess, &options.assembly)?;
            (s.q, s.qd)
        }
        InitialState::Consistent { q, qd } => {
            for (what, v) in [("q", q), ("q'", qd)] {
                if v.len() != n {
                    return Err(Error::WrongLength {
                        what,
                        expected: n,
                        got: v.len(),
                    });
                }
            }
            (q.clone(), qd.clone())
        }
    };
    Error::check_finite(&q, "initial position", &info.coordinates, t0)?;
    Error::check_finite(&qd, "initial rate", &info.coordinates, t0)?;
    Ok((q, qd))
}
