//! `Model`'s derivatives of the dynamics as numpy arrays (the book's "Derivatives of the
//! dynamics"): the inverse dynamics' by q and v (Pinocchio's `computeRNEADerivatives`),
//! by the declared parameters, and the forward dynamics' by q, v and tau with the
//! constraint rows acting (Pinocchio's `computeABADerivatives` for a robot), with the
//! multipliers' for a mechanism with rows. They run on the model's system built with every
//! derivative (`Interpreted::for_derivatives`'s routines), derived on first use. One state
//! (1-D arrays) or a batch (one state a row): each output gains a leading axis of rows.

use mechanism::{DynamicsDerivatives, Kinematic, System, Tangent};
use nalgebra::DMatrix;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PySlice, PyTuple};

use crate::batch::{Arg, PyErrLater, batched_rows, later};
use crate::errors::SolverError;
use crate::model::Model;

type Array<'py> = numpy::PyArrayLikeDyn<'py, f64, numpy::AllowTypeChange>;

/// `matrix` (rows x cols) written row-major into `out`.
fn write(matrix: &DMatrix<f64>, out: &mut [f64]) {
    let cols = matrix.ncols();
    for i in 0..matrix.nrows() {
        for j in 0..cols {
            out[i * cols + j] = matrix[(i, j)];
        }
    }
}

fn not_provided(what: &str) -> PyErrLater {
    PyErrLater::new(
        SolverError::new_err,
        format!("{what}: not finite at this state"),
    )
}

/// The parts of `flat` (shape `(size,)` or `(rows, size)`), each the next `shape`'s
/// product of values reshaped to `shape` (after the rows).
fn split<'py>(
    py: Python<'py>,
    flat: Py<PyAny>,
    shapes: &[Vec<usize>],
) -> PyResult<Vec<Bound<'py, PyAny>>> {
    let flat = flat.into_bound(py);
    let dims: Vec<usize> = flat.getattr("shape")?.extract()?;
    let rows = (dims.len() == 2).then(|| dims[0]);
    // Always (rows, size) here: one state is one row.
    let table = flat.call_method1("reshape", ((rows.unwrap_or(1), dims[dims.len() - 1]),))?;
    let mut start = 0;
    let mut parts = Vec::with_capacity(shapes.len());
    for shape in shapes {
        let size: usize = shape.iter().product();
        let columns = PySlice::new(py, start as isize, (start + size) as isize, 1);
        let index = PyTuple::new(py, [PySlice::full(py), columns])?;
        let mut full: Vec<usize> = rows.into_iter().collect();
        full.extend_from_slice(shape);
        parts.push(table.get_item(index)?.call_method1("reshape", (full,))?);
        start += size;
    }
    Ok(parts)
}

/// What a batch's rows function returns: the first failing row of its piece.
type RowsResult = Result<(), (usize, PyErrLater)>;

/// The per-row loop of a batch: `one` on each state of the piece.
fn each_row<F>(
    lens: &[usize],
    size: usize,
    one: F,
) -> impl Fn(&[&[f64]], &mut [f64]) -> RowsResult + Sync
where
    F: Fn(&[&[f64]], &mut [f64]) -> Result<(), PyErrLater> + Sync,
{
    let lens = lens.to_vec();
    move |s: &[&[f64]], out: &mut [f64]| {
        for (i, o) in out.chunks_mut(size).enumerate() {
            let state: Vec<&[f64]> = (s.iter().zip(&lens))
                .map(|(a, &k)| &a[i * k..(i + 1) * k])
                .collect();
            one(&state, o).map_err(|e| (i, e))?;
        }
        Ok(())
    }
}

/// (dtau/dq, dtau/dv) of the inverse dynamics u = M a + C v + g - tau, n x n each.
pub(crate) fn inverse_dynamics<'py>(
    model: &Model,
    py: Python<'py>,
    (q, v, a): (Array<'py>, Array<'py>, Array<'py>),
    t: f64,
) -> PyResult<Bound<'py, PyTuple>> {
    let system = model.system_with_derivatives()?;
    let n = system.info().n();
    let args = [arg("q", q, n), arg("v", v, n), arg("a", a, n)];
    let one = |s: &[&[f64]], out: &mut [f64]| {
        let mut d = Tangent::zeros(n);
        system
            .inverse_dynamics_derivatives(t, s[0], s[1], s[2], &mut d)
            .ok_or_else(|| not_provided("inverse_dynamics_derivatives"))?;
        write(&d.stiffness, &mut out[..n * n]);
        write(&d.damping, &mut out[n * n..]);
        Ok(())
    };
    let one = &one;
    let flat = batched_rows(
        py,
        &args,
        &[2 * n * n],
        one,
        each_row(&[n; 3], 2 * n * n, one),
    )?;
    PyTuple::new(py, split(py, flat, &[vec![n, n], vec![n, n]])?)
}

/// dtau/dp of the inverse dynamics by the declared parameters, n x p.
pub(crate) fn parameters(
    model: &Model,
    py: Python<'_>,
    (q, v, a): (Array<'_>, Array<'_>, Array<'_>),
    t: f64,
) -> PyResult<Py<PyAny>> {
    let system = model.system_with_derivatives()?;
    let (n, p) = (system.info().n(), system.info().parameters.len());
    let args = [arg("q", q, n), arg("v", v, n), arg("a", a, n)];
    let one = |s: &[&[f64]], out: &mut [f64]| {
        let mut d = DMatrix::zeros(n, p);
        system
            .parameter_derivatives(t, s[0], s[1], s[2], &mut d)
            .ok_or_else(|| not_provided("parameter_derivatives"))?;
        write(&d, out);
        Ok(())
    };
    let one = &one;
    batched_rows(py, &args, &[n, p], one, each_row(&[n; 3], n * p, one))
}

/// The forward dynamics' derivatives: with `multipliers`, a dict with q'', lambda and
/// their derivatives by q, v and tau; else (dq''/dq, dq''/dv, dq''/dtau).
pub(crate) fn forward_dynamics<'py>(
    model: &Model,
    py: Python<'py>,
    (q, v, tau): (Array<'py>, Array<'py>, Array<'py>),
    t: f64,
    multipliers: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let system = model.system_with_derivatives()?;
    let (n, m) = (system.info().n(), system.info().m());
    let args = [arg("q", q, n), arg("v", v, n), arg("tau", tau, n)];
    let shapes = [
        vec![n],
        vec![m],
        vec![n, n],
        vec![n, n],
        vec![n, n],
        vec![m, n],
        vec![m, n],
        vec![m, n],
    ];
    let size: usize = shapes.iter().map(|s| s.iter().product::<usize>()).sum();
    let one = |s: &[&[f64]], out: &mut [f64]| {
        let mut d = DynamicsDerivatives::new(system.info());
        d.compute(system.as_ref(), t, s[0], s[1], s[2])
            .map_err(later)?;
        out[..n].copy_from_slice(d.accelerations());
        out[n..n + m].copy_from_slice(d.multipliers());
        let mut at = n + m;
        for matrix in [
            d.dqdd_dq(),
            d.dqdd_dqd(),
            d.dqdd_du(),
            d.dlambda_dq(),
            d.dlambda_dqd(),
            d.dlambda_du(),
        ] {
            let len = matrix.len();
            write(matrix, &mut out[at..at + len]);
            at += len;
        }
        Ok(())
    };
    let one = &one;
    let flat = batched_rows(py, &args, &[size], one, each_row(&[n; 3], size, one))?;
    let parts = split(py, flat, &shapes)?;
    if !multipliers {
        return Ok(PyTuple::new(py, &parts[2..5])?.into_any());
    }
    let dict = PyDict::new(py);
    let names = [
        "qdd",
        "lambda",
        "dqdd_dq",
        "dqdd_dv",
        "dqdd_dtau",
        "dlambda_dq",
        "dlambda_dv",
        "dlambda_dtau",
    ];
    for (name, part) in names.iter().zip(parts) {
        dict.set_item(name, part)?;
    }
    Ok(dict.into_any())
}

fn arg<'py>(name: &'static str, array: Array<'py>, len: usize) -> Arg<'py> {
    Arg { name, array, len }
}
