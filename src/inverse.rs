//! Inverse dynamics: the generalised forces that make chosen coordinates follow a prescribed
//! motion, and the constraint multipliers (joint reactions) along it.
//!
//! Each driven coordinate q_k gets the driver constraint q_k - f(t) = 0 (Haug 1989,
//! sec. 6.3), whose Jacobian row is the unit row e_k and whose acceleration right-hand side
//! is f''(t). The driving force replaces whatever force the declaration puts on q_k (tau_k
//! is zeroed); forces on the other coordinates stay. At each time:
//!
//! ```text
//! kinematics   Phi(q, t) = 0, q_k = f(t)     (Newton, continued from the previous sample)
//!              Phi_q q' = -Phi_t, q_k' = f'(t)
//! dynamics     [ M      Phi_q^T  E^T ] [ q''      ]   [ tau* - C q' - g ]
//!              [ Phi_q  0        0   ] [ lambda   ] = [ gamma           ]
//!              [ E      0        0   ] [ lambda_d ]   [ f''(t)          ]
//! ```
//!
//! with E the unit rows of the driven coordinates and tau* the declared forces with the
//! driven entries set to zero. Row k of the first block reads
//! (M q'' + C q' + g + Phi_q^T lambda)_k + lambda_d = 0, so the actuator must supply
//! **tau_k = -lambda_d**: the total generalised force on q_k (N m for an angle, N for a
//! length).
//!
//! # What lambda means
//! With the sign convention M q'' + ... + Phi_q^T lambda = tau, the constraint forces on the
//! coordinates are -Phi_q^T lambda. When a loop is closed by a vector equation
//! Phi = r_C(via chain 1) - r_C(via chain 2) = 0 (the loop cut at joint C), the virtual work of
//! a joint force F acting on chain 1 at C and -F on chain 2 is F . dPhi = (Phi_q^T F) . dq, so
//! F = -lambda: **-lambda is the force chain 2 exerts on chain 1 at the cut joint, and +lambda
//! the force chain 1 exerts on chain 2**, in the components in which Phi is written (N when
//! Phi is a length, N m when it is an angle; scaling a constraint row by c scales its lambda
//! by 1/c). For the seed crank-slider, Phi = r_C(crank and rod) - r_C(slider), so lambda is
//! the force of the connecting rod on the slider at the spherical joint C, in x, y, z.

use crate::dynamics::DEFAULT_CONDITION_LIMIT;
use crate::error::Error;
use crate::kinematics::{AssemblyOptions, Drive, check_fixed, solve_positions, solve_velocities};
use crate::linalg::Lu;
use crate::mechanism::{Evaluation, System, SystemInfo};

/// One sample of an inverse-dynamics run.
#[derive(Clone, Debug, PartialEq)]
pub struct InverseSample {
    /// Time (s).
    pub t: f64,
    /// Positions.
    pub q: Vec<f64>,
    /// Rates.
    pub qd: Vec<f64>,
    /// Accelerations.
    pub qdd: Vec<f64>,
    /// Driving generalised force on each driven coordinate (drive order): tau_k = -lambda_d.
    pub driving: Vec<f64>,
    /// Loop-constraint multipliers lambda_1..lambda_m (see the module docs for the sign).
    pub lambda: Vec<f64>,
}

/// Inverse dynamics along a prescribed motion; reuses its buffers from sample to sample and
/// continues the assembly branch from the previous configuration.
pub struct InverseDynamics {
    drives: Vec<Drive>,
    fixed: Vec<usize>,
    q: Vec<f64>,
    eval: Evaluation,
    lu: Lu,
    rhs: Vec<f64>,
    /// Newton options of the position solve.
    pub assembly: AssemblyOptions,
    /// Condition-estimate limit of the augmented matrix.
    pub condition_limit: f64,
}

impl InverseDynamics {
    /// Prepares inverse dynamics of `system` for `drives` (unknown or repeated coordinates
    /// give [`Error::UnknownDriver`]). Starts from the declared initial guesses.
    pub fn new(
        system: &dyn System,
        drives: Vec<Drive>,
        assembly: AssemblyOptions,
    ) -> Result<Self, Error> {
        let info = system.info();
        let fixed: Vec<usize> = drives.iter().map(|d| d.coordinate).collect();
        check_fixed(info, &fixed)?;
        let (n, m, k) = (info.n(), info.m(), fixed.len());
        Ok(Self {
            drives,
            fixed,
            q: info.initial_guess.clone(),
            eval: Evaluation::zeros(n, m),
            lu: Lu::new(n + m + k),
            rhs: vec![0.0; n + m + k],
            assembly,
            condition_limit: DEFAULT_CONDITION_LIMIT,
        })
    }

    /// Kinematics and the driven augmented system at time t (see the module equations).
    pub fn solve_at(&mut self, system: &dyn System, t: f64) -> Result<InverseSample, Error> {
        let info = system.info();
        let (n, m, k) = (info.n(), info.m(), self.fixed.len());
        let mut qd = vec![0.0; n];
        let mut fdd = vec![0.0; k];
        for (j, d) in self.drives.iter().enumerate() {
            let [f, fd, f2] = (d.f)(t);
            if !(f.is_finite() && fd.is_finite() && f2.is_finite()) {
                return Err(Error::NonFinite {
                    what: format!("drive of {}", info.coordinates[d.coordinate]),
                    t,
                });
            }
            self.q[d.coordinate] = f;
            qd[d.coordinate] = fd;
            fdd[j] = f2;
        }
        solve_positions(system, t, &self.fixed, &mut self.q, &self.assembly)?;
        solve_velocities(system, t, &self.q, &self.fixed, &mut qd, &self.assembly)?;
        system.evaluate(t, &self.q, &qd, &mut self.eval);
        let e = &self.eval;
        let a = self.lu.matrix_mut();
        a.fill(0.0);
        for i in 0..n {
            for j in 0..n {
                a[(i, j)] = e.mass[(i, j)];
            }
            for r in 0..m {
                a[(n + r, i)] = e.phi_q[(r, i)];
                a[(i, n + r)] = e.phi_q[(r, i)];
            }
        }
        for (j, &c) in self.fixed.iter().enumerate() {
            a[(n + m + j, c)] = 1.0;
            a[(c, n + m + j)] = 1.0;
        }
        for i in 0..n {
            let tau = if self.fixed.contains(&i) {
                0.0
            } else {
                e.forces[i]
            };
            self.rhs[i] = tau - e.coriolis[i] - e.gravity[i];
        }
        self.rhs[n..n + m].copy_from_slice(e.gamma.as_slice());
        self.rhs[n + m..].copy_from_slice(&fdd);
        if self.rhs.iter().any(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                what: "the equations of motion along the prescribed motion".into(),
                t,
            });
        }
        let singular = |c| Error::SingularConfiguration {
            t,
            q: self.q.clone(),
            condition: c,
        };
        if !self.lu.factor() {
            return Err(singular(f64::INFINITY));
        }
        let c = self.lu.condition_estimate();
        if c > self.condition_limit {
            return Err(singular(c));
        }
        self.lu.solve(&mut self.rhs);
        Error::check_finite(&self.rhs[..n], "q''", &info.coordinates, t)?;
        Ok(InverseSample {
            t,
            q: self.q.clone(),
            qd,
            qdd: self.rhs[..n].to_vec(),
            driving: self.rhs[n + m..].iter().map(|l| -l).collect(),
            lambda: self.rhs[n..n + m].to_vec(),
        })
    }
}

/// Inverse dynamics at each of `times` (in order). The error of the first failing sample is
/// returned, e.g. [`Error::SingularConfiguration`] where the prescribed motion drives the
/// mechanism through a dead point it cannot pass.
pub fn inverse_dynamics(
    system: &dyn System,
    drives: Vec<Drive>,
    times: &[f64],
    assembly: &AssemblyOptions,
) -> Result<InverseResult, Error> {
    let coordinates = drives.iter().map(|d| d.coordinate).collect();
    let mut inv = InverseDynamics::new(system, drives, *assembly)?;
    let samples = times
        .iter()
        .map(|&t| inv.solve_at(system, t))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(InverseResult {
        info: system.info().clone(),
        driven: coordinates,
        samples,
    })
}

/// Sample times t_start, t_start + 1/rate, ..., ending exactly at t_end.
pub fn sample_times(t_start: f64, t_end: f64, rate: f64) -> Vec<f64> {
    let k = (((t_end - t_start) * rate) - 1e-9).ceil().max(0.0) as usize;
    (0..=k)
        .map(|i| {
            if i == k {
                t_end
            } else {
                t_start + i as f64 / rate
            }
        })
        .collect()
}

/// The result of [`inverse_dynamics`].
#[derive(Clone, Debug, PartialEq)]
pub struct InverseResult {
    /// The system's names and sizes.
    pub info: SystemInfo,
    /// Driven coordinate indices, in drive order.
    pub driven: Vec<usize>,
    /// One entry per time.
    pub samples: Vec<InverseSample>,
}

impl InverseResult {
    /// Column headers: t, q, `<q>_dot`, `<q>_ddot`, `tau_<driven>`, lambda_1..lambda_m.
    pub fn headers(&self) -> Vec<String> {
        let c = &self.info.coordinates;
        let mut h = vec!["t".to_string()];
        h.extend(c.iter().cloned());
        h.extend(c.iter().map(|x| format!("{x}_dot")));
        h.extend(c.iter().map(|x| format!("{x}_ddot")));
        h.extend(self.driven.iter().map(|&k| format!("tau_{}", c[k])));
        h.extend((1..=self.info.m()).map(|i| format!("lambda_{i}")));
        h
    }

    /// The samples as rows in [`InverseResult::headers`] order.
    pub fn rows(&self) -> Vec<Vec<f64>> {
        self.samples
            .iter()
            .map(|s| {
                let mut r = vec![s.t];
                for part in [&s.q, &s.qd, &s.qdd, &s.driving, &s.lambda] {
                    r.extend_from_slice(part);
                }
                r
            })
            .collect()
    }
}
