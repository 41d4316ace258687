//! One state or a batch: every per-state function of a model (mass matrix, bias, inverse and
//! forward dynamics, frames) takes 1-D arrays for one state or 2-D arrays with one state a
//! row, and answers in kind. A batch runs in one call, without the GIL, its rows in parallel
//! (rayon) when there are enough of them to pay for the threads.
//!
//! A new per-state function is one call of [`batched_rows`]: the arguments with their
//! lengths, the shape of one answer, a closure that fills one answer from one state's
//! slices, and one that fills the answers of a piece of rows at once through the library's
//! rows methods ([`mechanism::Interpreted::evaluate_rows`]: the interpreter's tape on many
//! states side by side).

use numpy::{IntoPyArray, PyArrayDyn, PyArrayLikeDyn, PyArrayMethods, PyUntypedArrayMethods};
use pyo3::prelude::*;
use rayon::prelude::*;

use crate::errors::input;

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

/// Rows of a batch handed to one call of a rows function: eight blocks of the lane tape
/// (16 states each), whose work (tens of microseconds) dwarfs rayon's hand-off (a few); a
/// batch of more rows than this runs its pieces in parallel.
const PIECE: usize = 128;

/// Evaluates a per-state function at every state of `args` (see the module docs) and
/// returns an array of `shape` for one state, of `(rows, *shape)` for a batch. One state
/// (1-D arrays) goes to `one(state, out)`, which receives one slice per argument and fills
/// `out`, `shape.iter().product()` values in row-major order; a batch to `rows(states, out)` in pieces of at most
/// [`PIECE`] rows, where `states` holds each argument's rows of the piece (row-major) and
/// `out` the piece's answers; the pieces run in parallel (rayon) when there are enough
/// rows (more than one piece). `rows` returns the first failing row of its piece with its error.
///
/// # Errors
/// [`crate::errors::InputError`] for a wrong shape or a non-finite entry; the first error
/// the functions return (by row).
pub fn batched_rows<F, G>(
    py: Python<'_>,
    args: &[Arg<'_>],
    shape: &[usize],
    one: F,
    rows: G,
) -> PyResult<Py<PyAny>>
where
    F: Fn(&[&[f64]], &mut [f64]) -> Result<(), PyErrLater> + Sync,
    G: Fn(&[&[f64]], &mut [f64]) -> Result<(), (usize, PyErrLater)> + Sync,
{
    let (buffers, count) = gather(args)?;
    let size: usize = shape.iter().product();
    let lens: Vec<usize> = args.iter().map(|a| a.len).collect();
    let result = py.detach(|| {
        let mut out = vec![0.0; count.unwrap_or(1) * size];
        if size == 0 {
            return Ok(out);
        }
        let Some(count) = count else {
            let state: Vec<&[f64]> = buffers.iter().map(Vec::as_slice).collect();
            return one(&state, &mut out).map(|()| out).map_err(|e| (0, e));
        };
        let piece = |(p, chunk): (usize, &mut [f64])| {
            let first = p * PIECE;
            let last = (first + PIECE).min(count);
            let states: Vec<&[f64]> = buffers
                .iter()
                .zip(&lens)
                .map(|(b, &k)| &b[first * k..last * k])
                .collect();
            rows(&states, chunk).map_err(|(i, e)| (first + i, e))
        };
        let done = if count > PIECE {
            out.par_chunks_mut(PIECE * size)
                .enumerate()
                .try_for_each(piece)
        } else {
            out.chunks_mut(PIECE * size).enumerate().try_for_each(piece)
        };
        done.map(|()| out)
    });
    let out = match result {
        Ok(out) => out,
        Err((i, e)) => return Err(e.at_row(count.map(|_| i))),
    };
    let mut full = Vec::with_capacity(shape.len() + 1);
    if let Some(r) = count {
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
