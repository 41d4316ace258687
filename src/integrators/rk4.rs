//! Classical fixed-step Runge–Kutta of order 4 (Kutta 1901), with cubic Hermite dense output
//! from y and f at both ends of the step (order 3 in between, exact at the ends).

use super::{Dense, OdeRhs, RungeKutta, Tolerance};
use crate::error::Error;

/// Classical RK4: k1 = f(t, y), k2 = f(t + h/2, y + h/2 k1), k3 = f(t + h/2, y + h/2 k2),
/// k4 = f(t + h, y + h k3), y1 = y + h/6 (k1 + 2 k2 + 2 k3 + k4).
#[derive(Clone, Debug)]
pub struct Rk4 {
    k: [Vec<f64>; 4],
    f_new: Vec<f64>,
    tmp: Vec<f64>,
    dense: Dense,
}

impl Rk4 {
    /// Stages for a state of dimension `dim`.
    pub fn new(dim: usize) -> Self {
        let v = || vec![0.0; dim];
        Self {
            k: [v(), v(), v(), v()],
            f_new: v(),
            tmp: v(),
            dense: Dense::new(dim, 4),
        }
    }
}

impl RungeKutta for Rk4 {
    fn adaptive(&self) -> bool {
        false
    }
    fn exponent(&self) -> f64 {
        0.2
    }
    fn pi_beta(&self) -> f64 {
        0.0
    }
    fn max_growth(&self) -> f64 {
        1.0
    }
    fn nodes(&self) -> &'static [f64] {
        &[0.0, 0.5, 0.5, 1.0]
    }
    fn k1_mut(&mut self) -> &mut [f64] {
        &mut self.k[0]
    }
    fn attempt(
        &mut self,
        rhs: &mut dyn OdeRhs,
        t: f64,
        y: &[f64],
        h: f64,
        y_new: &mut [f64],
        _tol: Tolerance,
    ) -> Result<f64, Error> {
        let [k1, k2, k3, k4] = &mut self.k;
        let tmp = &mut self.tmp;
        for i in 0..y.len() {
            tmp[i] = y[i] + 0.5 * h * k1[i];
        }
        rhs.rhs(t + 0.5 * h, tmp, k2)?;
        for i in 0..y.len() {
            tmp[i] = y[i] + 0.5 * h * k2[i];
        }
        rhs.rhs(t + 0.5 * h, tmp, k3)?;
        for i in 0..y.len() {
            tmp[i] = y[i] + h * k3[i];
        }
        rhs.rhs(t + h, tmp, k4)?;
        for i in 0..y.len() {
            y_new[i] = y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        Ok(0.0)
    }
    fn finish(&mut self, rhs: &mut dyn OdeRhs, t: f64, y_new: &[f64], h: f64) -> Result<(), Error> {
        rhs.rhs(t + h, y_new, &mut self.f_new)
    }
    fn f_new(&self) -> &[f64] {
        &self.f_new
    }
    fn reuse_f_new(&mut self) {
        self.k[0].copy_from_slice(&self.f_new);
    }
    fn prepare_dense(
        &mut self,
        _rhs: &mut dyn OdeRhs,
        _t: f64,
        y: &[f64],
        y_new: &[f64],
        h: f64,
    ) -> Result<(), Error> {
        self.dense.set_hermite(y, y_new, &self.k[0], &self.f_new, h);
        Ok(())
    }
    fn dense(&self, theta: f64, out: &mut [f64]) {
        self.dense.eval(theta, out)
    }
}
