//! Dormand–Prince 5(4) (Dormand & Prince, J. Comput. Appl. Math. 6, 1980) with the
//! order-4 dense output of Shampine (Math. Comp. 46, 1986), as in Hairer's DOPRI5
//! (Hairer, Nørsett & Wanner, Solving ODEs I, 2nd ed., Table II.5.2 and eq. II.6.12).
//! Seven stages, the last evaluated at the new point (first same as last).

use super::{Dense, OdeRhs, RungeKutta, Tolerance};
use crate::error::Error;

const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// Difference of the 5th- and 4th-order weights.
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];
/// Shampine's dense-output weights.
const D: [f64; 7] = [
    -12715105075.0 / 11282082432.0,
    0.0,
    87487479700.0 / 32700410799.0,
    -10690763975.0 / 1880347072.0,
    701980252875.0 / 199316789632.0,
    -1453857185.0 / 822651844.0,
    69997945.0 / 29380423.0,
];

/// Dormand–Prince 5(4) stepper with preallocated stages.
#[derive(Clone, Debug)]
pub struct Dopri5 {
    k: Vec<Vec<f64>>,
    tmp: Vec<f64>,
    dense: Dense,
}

impl Dopri5 {
    /// Stages for a state of dimension `dim`.
    pub fn new(dim: usize) -> Self {
        Self {
            k: vec![vec![0.0; dim]; 7],
            tmp: vec![0.0; dim],
            dense: Dense::new(dim, 5),
        }
    }
}

impl RungeKutta for Dopri5 {
    fn adaptive(&self) -> bool {
        true
    }
    fn exponent(&self) -> f64 {
        0.2 - 0.04 * 0.75
    }
    fn pi_beta(&self) -> f64 {
        0.04
    }
    fn max_growth(&self) -> f64 {
        10.0
    }
    fn nodes(&self) -> &'static [f64] {
        &C
    }
    fn k1_mut(&mut self) -> &mut [f64] {
        &mut self.k[0]
    }
    #[allow(clippy::needless_range_loop)] // stages are indexed like the Butcher tableau
    fn attempt(
        &mut self,
        rhs: &mut dyn OdeRhs,
        t: f64,
        y: &[f64],
        h: f64,
        y_new: &mut [f64],
        tol: Tolerance,
    ) -> Result<f64, Error> {
        let n = y.len();
        for s in 1..7 {
            for i in 0..n {
                let mut acc = 0.0;
                for (j, a) in A[s].iter().enumerate().take(s) {
                    acc += a * self.k[j][i];
                }
                self.tmp[i] = y[i] + h * acc;
            }
            if s == 6 {
                y_new.copy_from_slice(&self.tmp);
            }
            let (_, rest) = self.k.split_at_mut(s);
            rhs.rhs(t + C[s] * h, &self.tmp, &mut rest[0])?;
        }
        let mut err = 0.0;
        for i in 0..n {
            let e: f64 = (0..7).map(|j| E[j] * self.k[j][i]).sum::<f64>() * h;
            err += (e / tol.scale(y[i], y_new[i])).powi(2);
        }
        Ok((err / n.max(1) as f64).sqrt())
    }
    fn finish(
        &mut self,
        _rhs: &mut dyn OdeRhs,
        _t: f64,
        _y_new: &[f64],
        _h: f64,
    ) -> Result<(), Error> {
        Ok(()) // stage 7 is f(t + h, y_new)
    }
    fn f_new(&self) -> &[f64] {
        &self.k[6]
    }
    fn reuse_f_new(&mut self) {
        let (first, rest) = self.k.split_at_mut(6);
        first[0].copy_from_slice(&rest[0]);
    }
    fn prepare_dense(
        &mut self,
        _rhs: &mut dyn OdeRhs,
        _t: f64,
        y: &[f64],
        y_new: &[f64],
        h: f64,
    ) -> Result<(), Error> {
        self.dense.set_hermite(y, y_new, &self.k[0], &self.k[6], h);
        let r5 = self.dense.term_mut(4);
        for (i, r) in r5.iter_mut().enumerate() {
            *r = h * (0..7).map(|j| D[j] * self.k[j][i]).sum::<f64>();
        }
        Ok(())
    }
    fn dense(&self, theta: f64, out: &mut [f64]) {
        self.dense.eval(theta, out)
    }
}
