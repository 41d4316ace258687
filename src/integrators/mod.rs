//! Time integrators for the equations of motion.
//!
//! The explicit methods integrate the first-order ODE in y = [q, q', W] (W the work of tau)
//!
//! ```text
//! q' = q',   (q'', lambda) from the augmented system,   W' = tau . q'
//! ```
//!
//! with a constraint stabilisation applied by the driver ([`crate::simulate()`]):
//! - [`Rk4`]: classical fixed-step Runge–Kutta of order 4 (Hermite cubic dense output);
//! - [`Dopri5`]: Dormand–Prince 5(4) with Shampine's dense output of order 4
//!   (Hairer, Nørsett & Wanner, Solving ODEs I, sec. II.5 and II.6);
//! - [`Dop853`]: Dormand–Prince 8(5,3) with its dense output of order 7 (ibid., sec. II.10).
//!
//! [`Hht`] is implicit: HHT-alpha (Hilber, Hughes & Taylor 1977) on the index-3 DAE with the
//! scaling of Negrut et al. (J. Comput. Nonlinear Dyn. 2, 2007), solving for (q'', lambda)
//! by Newton.

mod dop853;
mod dopri5;
mod hht;
mod rk4;

pub use dop853::Dop853;
pub use dopri5::Dopri5;
pub use hht::Hht;
pub use rk4::Rk4;

use crate::error::Error;

/// The integration method.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Method {
    /// Classical Runge–Kutta 4, fixed step `h` (s).
    Rk4 {
        /// Step size (s).
        h: f64,
    },
    /// Dormand–Prince 5(4), adaptive (rtol, atol from [`IntegratorOptions`]).
    #[default]
    Dopri5,
    /// Dormand–Prince 8(5,3), adaptive.
    Dop853,
    /// HHT-alpha on the index-3 DAE, fixed step `h`, alpha in [-1/3, 0]
    /// (gamma = 1/2 - alpha, beta = (1 - alpha)^2 / 4).
    Hht {
        /// Step size (s).
        h: f64,
        /// Numerical damping alpha in [-1/3, 0] (0: trapezoidal Newmark, no damping).
        alpha: f64,
    },
}

impl Method {
    /// The method's name as the command line spells it: `rk4`, `dopri5`, `dop853`, `hht`.
    pub fn name(self) -> &'static str {
        match self {
            Method::Rk4 { .. } => "rk4",
            Method::Dopri5 => "dopri5",
            Method::Dop853 => "dop853",
            Method::Hht { .. } => "hht",
        }
    }
}

/// How the adaptive methods choose the next step after an accepted one.
///
/// With err_n the scaled error norm of step n (accepted when <= 1), h_n its size and k = 1/8
/// for DOP853, 1/5 for DOPRI5:
///
/// ```text
/// Pi:          h_new = 0.9 h_n err_n^-(k - 0.2 beta) err_(n-1)^beta      (beta = 0.04)
/// Predictive:  the smaller of that and 0.9 h_n (h_n / h_(n-1)) (err_(n-1) / err_n^2)^k
/// ```
///
/// The predictive term (Gustafsson, BIT 34, 1994; Hairer & Wanner, Solving ODEs II,
/// sec. IV.8) extrapolates the growth of the error constant err / h^(1/k) from the last two
/// steps. Where the solution's high derivatives rise steeply (the mechanisms' dead centres,
/// where err / h^8 grows 3-10x from one step to the next) it cuts most rejected steps; the
/// accepted steps then carry errors closer to the tolerance, so at one tolerance the global
/// error is somewhat larger (BENCHMARKS.md measures both).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StepController {
    /// Hairer's PI controller (the default).
    #[default]
    Pi,
    /// The PI step, capped by Gustafsson's predictive step.
    Predictive,
}

/// Step-size and tolerance options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegratorOptions {
    /// The method.
    pub method: Method,
    /// Relative tolerance of the local error (adaptive methods).
    pub rtol: f64,
    /// Absolute tolerance of the local error (adaptive methods).
    pub atol: f64,
    /// First step size; `None` for Hairer's automatic choice.
    pub h_initial: Option<f64>,
    /// Smallest step allowed before [`Error::StepSizeUnderflow`] (s).
    pub h_min: f64,
    /// Largest step allowed (s); `None` for no limit.
    pub h_max: Option<f64>,
    /// Accepted-step limit before [`Error::TooManySteps`].
    pub max_steps: usize,
    /// The step-size controller of the adaptive methods.
    pub controller: StepController,
}

impl Default for IntegratorOptions {
    fn default() -> Self {
        Self {
            method: Method::Dopri5,
            rtol: 1e-8,
            atol: 1e-10,
            h_initial: None,
            h_min: 1e-14,
            h_max: None,
            max_steps: 10_000_000,
            controller: StepController::Pi,
        }
    }
}

impl IntegratorOptions {
    /// DOP853 with rtol = atol = `tolerance` and the other options at their defaults: the
    /// method of reference runs (an 8th-order error per step makes a tight tolerance cheap).
    ///
    /// ```
    /// use mechanism::{IntegratorOptions, Method};
    /// let o = IntegratorOptions::dop853(1e-12);
    /// assert_eq!((o.method, o.rtol, o.atol), (Method::Dop853, 1e-12, 1e-12));
    /// ```
    pub fn dop853(tolerance: f64) -> Self {
        Self {
            method: Method::Dop853,
            rtol: tolerance,
            atol: tolerance,
            ..Self::default()
        }
    }

    /// The local error tolerance of these options.
    pub(crate) fn tolerance(&self) -> Tolerance {
        Tolerance {
            rtol: self.rtol,
            atol: self.atol,
        }
    }
}

/// A first-order system y' = f(t, y) evaluated into a caller buffer.
pub trait OdeRhs {
    /// Writes f(t, y) into `dy`.
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error>;
}

/// An explicit Runge–Kutta stepper with an error estimate and dense output.
///
/// Protocol: put f(t, y) into [`RungeKutta::k1_mut`], call [`RungeKutta::attempt`] until a
/// step is accepted, then [`RungeKutta::finish`] (f at the new point) and, when output falls
/// inside the step, [`RungeKutta::prepare_dense`] and [`RungeKutta::dense`].
pub trait RungeKutta: Send {
    /// True for methods with an error estimate.
    fn adaptive(&self) -> bool;
    /// Exponent of the step-size controller, 1/(order of the error estimate + 1).
    fn exponent(&self) -> f64;
    /// PI-controller beta (Gustafsson; Hairer's DOPRI5 uses 0.04, DOP853 0).
    fn pi_beta(&self) -> f64;
    /// Largest step growth factor.
    fn max_growth(&self) -> f64;
    /// The nodes c_i in [0, 1] of every stage the method evaluates in a step and in its
    /// dense output: f is evaluated at t + c_i h and nowhere else inside the step. The
    /// driver places a predicted singular position between two of them
    /// ([`crate::SingularPassage`]).
    fn nodes(&self) -> &'static [f64];
    /// f(t, y) at the start of the step.
    fn k1_mut(&mut self) -> &mut [f64];
    /// One step of size h from (t, y): writes y(t + h) into `y_new` and returns the scaled
    /// error norm (accept when <= 1; 0 for fixed-step methods).
    fn attempt(
        &mut self,
        rhs: &mut dyn OdeRhs,
        t: f64,
        y: &[f64],
        h: f64,
        y_new: &mut [f64],
        tol: Tolerance,
    ) -> Result<f64, Error>;
    /// After acceptance: ensures f(t + h, y_new) is known (see [`RungeKutta::f_new`]).
    fn finish(&mut self, rhs: &mut dyn OdeRhs, t: f64, y_new: &[f64], h: f64) -> Result<(), Error>;
    /// f(t + h, y_new) after [`RungeKutta::finish`].
    fn f_new(&self) -> &[f64];
    /// Starts the next step from f_new: k1 = f_new (FSAL), exact for an unmodified y_new
    /// (after a small projection the simulation keeps it and corrects the position rows
    /// through [`RungeKutta::k1_mut`]).
    fn reuse_f_new(&mut self);
    /// Builds the continuous extension of the last accepted step.
    fn prepare_dense(
        &mut self,
        rhs: &mut dyn OdeRhs,
        t: f64,
        y: &[f64],
        y_new: &[f64],
        h: f64,
    ) -> Result<(), Error>;
    /// y(t + theta h), 0 <= theta <= 1, from the continuous extension.
    fn dense(&self, theta: f64, out: &mut [f64]);
}

/// Local error tolerance: sk = atol + rtol max(|y0_i|, |y1_i|).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
}

impl Tolerance {
    pub(crate) fn scale(&self, y0: f64, y1: f64) -> f64 {
        self.atol + self.rtol * y0.abs().max(y1.abs())
    }
}

/// Continuous extension stored as coefficients r_1..r_K (K = 4 Hermite, 5 DOPRI5, 8 DOP853):
/// y(theta) = r1 + s (r2 + s1 (r3 + s (r4 + s1 (r5 + ...)))), s = theta, s1 = 1 - theta.
#[derive(Clone, Debug)]
pub(crate) struct Dense {
    dim: usize,
    terms: usize,
    r: Vec<f64>,
}

impl Dense {
    pub(crate) fn new(dim: usize, terms: usize) -> Self {
        Self {
            dim,
            terms,
            r: vec![0.0; dim * terms],
        }
    }

    /// Coefficient vector k (0-based).
    pub(crate) fn term_mut(&mut self, k: usize) -> &mut [f64] {
        &mut self.r[k * self.dim..(k + 1) * self.dim]
    }

    /// Fills r1..r4 from the step end points: the cubic Hermite part common to all.
    pub(crate) fn set_hermite(&mut self, y0: &[f64], y1: &[f64], f0: &[f64], f1: &[f64], h: f64) {
        let d = self.dim;
        for i in 0..d {
            let diff = y1[i] - y0[i];
            let bspl = h * f0[i] - diff;
            self.r[i] = y0[i];
            self.r[d + i] = diff;
            self.r[2 * d + i] = bspl;
            self.r[3 * d + i] = diff - h * f1[i] - bspl;
        }
    }

    pub(crate) fn eval(&self, theta: f64, out: &mut [f64]) {
        let (s, s1) = (theta, 1.0 - theta);
        let d = self.dim;
        for (i, o) in out.iter_mut().enumerate().take(d) {
            let mut acc = self.r[(self.terms - 1) * d + i];
            for k in (0..self.terms - 1).rev() {
                // after r_{k+1} (1-based) comes s when k+1 is odd, s1 when even
                let f = if k % 2 == 0 { s } else { s1 };
                acc = self.r[k * d + i] + f * acc;
            }
            *o = acc;
        }
    }
}

/// Hairer's starting step (Solving ODEs I, sec. II.4): h from |y|/|f| and a second-derivative
/// estimate, so that the first step's error is about the tolerance. `f0` is f(t, y);
/// `work` (2 dim) is scratch.
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step(
    rhs: &mut dyn OdeRhs,
    t: f64,
    y: &[f64],
    f0: &[f64],
    order: f64,
    tol: Tolerance,
    h_max: f64,
    work: &mut [f64],
) -> Result<f64, Error> {
    let n = y.len();
    let (y1, f1) = work.split_at_mut(n);
    let (mut dny, mut dnf) = (0.0, 0.0);
    for i in 0..n {
        let sk = tol.scale(y[i], y[i]);
        dny += (y[i] / sk).powi(2);
        dnf += (f0[i] / sk).powi(2);
    }
    let (dny, dnf) = (dny / n as f64, dnf / n as f64);
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
        1e-6
    } else {
        0.01 * (dny / dnf).sqrt()
    };
    h = h.min(h_max);
    for i in 0..n {
        y1[i] = y[i] + h * f0[i];
    }
    rhs.rhs(t + h, y1, f1)?;
    let mut der2 = 0.0;
    for i in 0..n {
        der2 += ((f1[i] - f0[i]) / tol.scale(y[i], y[i])).powi(2);
    }
    let der2 = (der2 / n as f64).sqrt() / h;
    let der12 = der2.max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 {
        (h * 1e-3).max(1e-6)
    } else {
        (0.01 / der12).powf(1.0 / order)
    };
    Ok((100.0 * h).min(h1).min(h_max))
}
