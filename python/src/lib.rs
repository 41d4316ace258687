//! The native module `mechanism._native` of the Python package `mechanism`: a thin layer
//! over the `mechanism` crate's interpreter route (`Interpreted`, with the robotics
//! routines) and its algorithms (`simulate`, `inverse_dynamics`, `linearize_steady`, the
//! augmented solve). Every computation runs without the GIL; a batch of states runs on all
//! cores.
//!
//! - `model.rs`: `load` (a built-in name, a `.mech` file, a URDF), the `Model` and its
//!   pickling;
//! - `methods.rs`: `Model`'s methods and `sweep`; `derivatives.rs`: the derivatives of the
//!   dynamics;
//! - `floating.rs`: `FloatingModel`, a robot whose root link floats;
//! - `batch.rs`: one state or a batch for every per-state function;
//! - `runs.rs`: simulate, inverse, linearize, sweep as the command-line tool runs them;
//! - `errors.rs`: the exception classes; `effort.rs`, `sources.rs`: helpers.

mod batch;
mod derivatives;
mod effort;
mod errors;
mod floating;
mod methods;
mod model;
mod rows;
mod runs;
mod scratch;
mod sources;

use pyo3::prelude::*;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<model::Model>()?;
    m.add_class::<floating::FloatingModel>()?;
    m.add_function(wrap_pyfunction!(model::load, m)?)?;
    m.add_function(wrap_pyfunction!(model::from_source, m)?)?;
    m.add_function(wrap_pyfunction!(model::builtin_names, m)?)?;
    m.add_function(wrap_pyfunction!(model::_restore, m)?)?;
    m.add_function(wrap_pyfunction!(methods::sweep, m)?)?;
    errors::register(m)?;
    Ok(())
}
