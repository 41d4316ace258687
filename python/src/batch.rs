//! One state or a batch: every per-state function of a model (mass matrix, bias, inverse and
//! forward dynamics, frames) takes 1-D arrays for one state or 2-D arrays with one state a
//! row, and answers in kind. A batch runs in one call, without the GIL, its rows in parallel
//! (rayon) when there are enough of them to pay for the threads.
//!
//! A new per-state function is one call of [`batched`]: the arguments with their lengths,
//! the shape of one answer, and a closure that fills one answer from one state's slices.

use numpy::{IntoPyArray, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use rayon::prelude::*;

use crate::errors::input;

/// Rows below which a batch runs on the calling thread: rayon's hand-off costs a few
/// microseconds, about a dozen states' work.
const PARALLEL_FROM: usize = 64;

/// One argument of a per-state function: its name (for messages), its array and the
/// number of values of one state.
pub struct Arg<'py> {
    pub name: &'static str,
    pub array: PyArrayLikeDyn<'py, f64, numpy::AllowTypeChange>,
    pub len: usize,
}

/// The arguments' values as contiguous row-major buffers, and the batch size (`None` for
/// one state given as 1-D arrays).
fn gather(args: &[Arg<'_>]) -> PyResult<(Vec<Vec<f64>>, Option<usize>)> {
    let mut rows: Option<Option<usize>> = None;
    let mut buffers = Vec::with_capacity(args.len());
    for a in args {
        let shape = a.array.shape().to_vec();
        let this = match shape.as_slice() {
            [k] if *k == a.len => None,
            [r, k] if *k == a.len => Some(*r),
            _ => {
                return Err(input(format!(
                    "{}: expected {} values (one state) or an array of shape (rows, {}), got \
                     shape {:?}",
                    a.name, a.len, a.len, shape
                )));
            }
        };
        match rows {
            None => rows = Some(this),
            Some(r) if r == this => {}
            Some(r) => {
                return Err(input(format!(
                    "{}: {} while {} has {}: give every argument as one state or all with the \
                     same number of rows",
                    a.name,
                    describe(this),
                    args[0].name,
                    describe(r)
                )));
            }
        }
        let values: Vec<f64> = a.array.as_array().iter().copied().collect();
        if let Some(bad) = values.iter().position(|v| !v.is_finite()) {
            let place = match this {
                None => format!("entry {bad}"),
                Some(_) => format!("row {}, entry {}", bad / a.len, bad % a.len),
            };
            return Err(input(format!(
                "{}: {place} is {}; states must be finite",
                a.name, values[bad]
            )));
        }
        buffers.push(values);
    }
    Ok((buffers, rows.flatten()))
}

fn describe(rows: Option<usize>) -> String {
    match rows {
        None => "one state".into(),
        Some(r) => format!("{r} rows"),
    }
}

/// Evaluates `f` at every state of `args` (see the module docs): `f(state, out)` receives
/// one slice per argument and fills `out`, `shape.iter().product()` values in row-major
/// order. Returns an array of `shape` for one state, of `(rows, *shape)` for a batch.
///
/// # Errors
/// [`crate::errors::InputError`] for a wrong shape or a non-finite entry; the first error
/// `f` returns (by row).
pub fn batched<F>(py: Python<'_>, args: &[Arg<'_>], shape: &[usize], f: F) -> PyResult<Py<PyAny>>
where
    F: Fn(&[&[f64]], &mut [f64]) -> Result<(), PyErrLater> + Sync,
{
    let (buffers, rows) = gather(args)?;
    let size: usize = shape.iter().product();
    let count = rows.unwrap_or(1);
    let lens: Vec<usize> = args.iter().map(|a| a.len).collect();
    let result = py.detach(|| {
        let mut out = vec![0.0; count * size];
        let row = |(i, chunk): (usize, &mut [f64])| {
            let state: Vec<&[f64]> = buffers
                .iter()
                .zip(&lens)
                .map(|(b, &k)| &b[i * k..(i + 1) * k])
                .collect();
            f(&state, chunk).map_err(|e| (i, e))
        };
        let done = if count >= PARALLEL_FROM && size > 0 {
            out.par_chunks_mut(size).enumerate().try_for_each(row)
        } else if size > 0 {
            out.chunks_mut(size).enumerate().try_for_each(row)
        } else {
            Ok(())
        };
        done.map(|()| out)
    });
    let out = match result {
        Ok(out) => out,
        Err((i, e)) => return Err(e.at_row(rows.map(|_| i))),
    };
    let mut full = Vec::with_capacity(shape.len() + 1);
    if let Some(r) = rows {
        full.push(r);
    }
    full.extend_from_slice(shape);
    let array = out.into_pyarray(py).reshape(full)?;
    Ok(array.into_any().unbind())
}

/// An error found without the GIL, made into a Python exception once it is held again.
pub struct PyErrLater {
    kind: fn(String) -> PyErr,
    message: String,
}

impl PyErrLater {
    /// An error of the exception `kind` with `message`.
    pub fn new(kind: fn(String) -> PyErr, message: impl Into<String>) -> Self {
        Self {
            kind,
            message: message.into(),
        }
    }

    /// The exception, naming the batch row where one failed.
    fn at_row(self, row: Option<usize>) -> PyErr {
        match row {
            Some(i) => (self.kind)(format!("row {i}: {}", self.message)),
            None => (self.kind)(self.message),
        }
    }
}

/// The library's error `e` as a [`PyErrLater`] of its exception class.
pub fn later(e: mechanism::Error) -> PyErrLater {
    PyErrLater::new(crate::errors::kind(&e), e.to_string())
}

/// A 2-D numpy array from a row-major buffer.
pub fn matrix(py: Python<'_>, rows: usize, cols: usize, values: Vec<f64>) -> PyResult<Py<PyAny>> {
    let array: Bound<'_, PyArrayDyn<f64>> = values.into_pyarray(py).reshape(vec![rows, cols])?;
    Ok(array.into_any().unbind())
}
