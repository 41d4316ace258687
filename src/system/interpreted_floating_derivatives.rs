//! The derivatives of the forward dynamics of a floating-base robot read at run time
//! ([`InterpretedFloating`] built by [`InterpretedFloating::for_derivatives`]): with the
//! storage allocated once by [`FloatingDerivatives::new`],
//! [`FloatingDerivatives::compute`] allocates nothing. As the macro's type
//! ([`crate::FloatingBase::forward_dynamics_derivatives`]):
//!
//! ```text
//! a = M^-1 (effort - b),   da/dq = -M^-1 dtau/dq,   da/dv = -M^-1 dtau/dv,   da/d(effort) = M^-1
//! ```
//!
//! with q's direction the tangent of the configuration manifold, M = L L^T by Cholesky.

use crate::Error;
use crate::system::InterpretedFloating;

/// A pivot below 1e-14 of M's largest diagonal entry: M is singular to round-off.
const SINGULAR: f64 = 1e-14;

/// a and da/dq, da/dv, M^-1 (nv x nv each, row-major) of a floating robot at one state
/// (module docs).
#[derive(Clone, Debug)]
pub struct FloatingDerivatives {
    nv: usize,
    /// M, then its Cholesky factor L (lower triangle).
    factor: Vec<f64>,
    a: Vec<f64>,
    dq: Vec<f64>,
    dv: Vec<f64>,
    inverse: Vec<f64>,
}

impl FloatingDerivatives {
    /// Storage for `robot`'s nv.
    pub fn new(robot: &InterpretedFloating) -> Self {
        let n = robot.nv();
        Self {
            nv: n,
            factor: vec![0.0; n * n],
            a: vec![0.0; n],
            dq: vec![0.0; n * n],
            dv: vec![0.0; n * n],
            inverse: vec![0.0; n * n],
        }
    }

    /// The acceleration a of the last [`FloatingDerivatives::compute`].
    pub fn a(&self) -> &[f64] {
        &self.a
    }
    /// da/dq (nv x nv, row-major), by the tangent of the configuration manifold.
    pub fn da_dq(&self) -> &[f64] {
        &self.dq
    }
    /// da/dv (nv x nv, row-major).
    pub fn da_dv(&self) -> &[f64] {
        &self.dv
    }
    /// M^-1 = da/d(effort) (nv x nv, row-major, symmetric).
    pub fn m_inverse(&self) -> &[f64] {
        &self.inverse
    }

    /// a and its derivatives at (t, q, v) under `effort` (module docs); no allocation.
    ///
    /// # Errors
    /// [`Error::NotProvided`] for a robot built without the derivatives;
    /// [`Error::WrongLength`] for q, v or `effort` of another length, or storage made for
    /// another robot; [`Error::UndeterminedMotion`] where M is not positive definite;
    /// [`Error::NonFinite`] for a NaN or infinity in the result.
    pub fn compute(
        &mut self,
        robot: &InterpretedFloating,
        t: f64,
        q: &[f64],
        v: &[f64],
        effort: &[f64],
    ) -> Result<(), Error> {
        let n = self.nv;
        for (what, got, expected) in [
            ("the storage's nv", n, robot.nv()),
            ("q", q.len(), robot.nq()),
            ("v", v.len(), robot.nv()),
            ("effort", effort.len(), robot.nv()),
        ] {
            if got != expected {
                return Err(Error::WrongLength {
                    what,
                    expected,
                    got,
                });
            }
        }
        if !robot.has_derivatives() {
            return Err(Error::NotProvided {
                what: format!(
                    "the derivatives of `{}` (InterpretedFloating::for_derivatives)",
                    robot.name()
                ),
            });
        }
        robot.mass_matrix(q, &mut self.factor);
        if !cholesky(&mut self.factor, n) {
            return Err(Error::UndeterminedMotion {
                t,
                coordinates: Vec::new(),
                q: q.to_vec(),
            });
        }
        // a = M^-1 (effort - b), b = C v + g - tau.
        robot.bias(t, q, v, &mut self.a);
        for (a, e) in self.a.iter_mut().zip(effort) {
            *a = e - *a;
        }
        solve(&self.factor, n, &mut self.a, 1);
        robot.inverse_dynamics_derivatives(t, q, v, &self.a, (&mut self.dq, &mut self.dv));
        for m in [&mut self.dq, &mut self.dv] {
            solve(&self.factor, n, m, n);
            m.iter_mut().for_each(|x| *x = -*x);
        }
        self.inverse.iter_mut().for_each(|x| *x = 0.0);
        for i in 0..n {
            self.inverse[i * n + i] = 1.0;
        }
        solve(&self.factor, n, &mut self.inverse, n);
        let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
        if !(finite(&self.a) && finite(&self.dq) && finite(&self.dv) && finite(&self.inverse)) {
            return Err(Error::NonFinite {
                what: "the forward dynamics' derivatives".into(),
                t,
            });
        }
        Ok(())
    }
}

/// M = L L^T in place (L in the lower triangle of the row-major n x n `m`); false when a
/// pivot is not above [`SINGULAR`] times M's largest diagonal entry.
fn cholesky(m: &mut [f64], n: usize) -> bool {
    let largest = (0..n).map(|i| m[i * n + i]).fold(0.0_f64, f64::max);
    for j in 0..n {
        let mut d = m[j * n + j];
        for k in 0..j {
            d -= m[j * n + k] * m[j * n + k];
        }
        // Also false for a NaN pivot.
        if d.is_nan() || d <= SINGULAR * largest {
            return false;
        }
        let d = d.sqrt();
        m[j * n + j] = d;
        for i in j + 1..n {
            let mut s = m[i * n + j];
            for k in 0..j {
                s -= m[i * n + k] * m[j * n + k];
            }
            m[i * n + j] = s / d;
        }
    }
    true
}

/// X = M^-1 X in place for the row-major n x `cols` `x`, M = L L^T from [`cholesky`].
fn solve(l: &[f64], n: usize, x: &mut [f64], cols: usize) {
    for c in 0..cols {
        // L y = x, then L^T z = y, column c (stride `cols`).
        for i in 0..n {
            let mut s = x[i * cols + c];
            for k in 0..i {
                s -= l[i * n + k] * x[k * cols + c];
            }
            x[i * cols + c] = s / l[i * n + i];
        }
        for i in (0..n).rev() {
            let mut s = x[i * cols + c];
            for k in i + 1..n {
                s -= l[k * n + i] * x[k * cols + c];
            }
            x[i * cols + c] = s / l[i * n + i];
        }
    }
}
