//! The positions that velocity rows leave to the motion, along a prescribed motion.
//!
//! A velocity (nonholonomic) row A(q, t) q' + a(q, t) = 0 fixes rates, not positions: once
//! the drives and the position rows Phi(q, t) = 0 are met, the coordinates they leave free
//! (the sleigh's y, the rolling disc's contact point) are wherever the motion has carried
//! them, q(t) = q(t_a) + integral of q' from t_a. Inverse dynamics samples the motion at
//! given times, so between two samples this integrates q' = v(tau, q), the rates of the
//! velocity solve at (tau, q) with the drives' f(tau) and f'(tau), each evaluation's
//! positions first brought back onto Phi = 0 (so that the velocity solve is consistent),
//! by the run-time's DOP853 with its error estimate at rtol = atol = [`TOLERANCE`].

use crate::algorithms::kinematics::{AssemblyOptions, Drive, solve_positions, solve_velocities};
use crate::error::Error;
use crate::integrators::{Dop853, OdeRhs, RungeKutta, Tolerance};
use crate::system::Kinematic;

/// The local error tolerance (relative and absolute, in the coordinates' units) of the
/// carried positions: the position solve's own tolerance.
pub const TOLERANCE: f64 = 1e-12;

/// Step attempts allowed between two samples before [`Error::TooManySteps`].
const MAX_ATTEMPTS: usize = 100_000;

/// q' = v(t, q): the rates of the velocity solve along the drives (module docs).
struct Carried<'a> {
    system: &'a dyn Kinematic,
    drives: &'a [Drive],
    fixed: Vec<usize>,
    options: &'a AssemblyOptions,
}

impl OdeRhs for Carried<'_> {
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), Error> {
        let mut at = y.to_vec();
        dy.fill(0.0);
        for d in self.drives {
            let [f, fd, _] = (d.f)(t);
            at[d.coordinate] = f;
            dy[d.coordinate] = fd;
        }
        solve_positions(self.system, t, &self.fixed, &mut at, self.options)?;
        solve_velocities(self.system, t, &at, &self.fixed, dy, self.options)
    }
}

/// Advances `q` from time `a` to time `b` along the drives (module docs); the driven
/// coordinates end at f(b) and the position rows are met at b.
///
/// # Errors
/// Those of the position and velocity solves; [`Error::TooManySteps`] when the step
/// control needs more than 100,000 attempts between the two samples.
pub(crate) fn advance(
    system: &dyn Kinematic,
    drives: &[Drive],
    q: &mut [f64],
    (a, b): (f64, f64),
    options: &AssemblyOptions,
) -> Result<(), Error> {
    let fixed: Vec<usize> = drives.iter().map(|d| d.coordinate).collect();
    let mut rhs = Carried {
        system,
        drives,
        fixed: fixed.clone(),
        options,
    };
    let mut rk = Dop853::new(q.len());
    let tol = Tolerance {
        rtol: TOLERANCE,
        atol: TOLERANCE,
    };
    let mut y_new = vec![0.0; q.len()];
    rhs.rhs(a, q, rk.k1_mut())?;
    let (mut t, mut h) = (a, b - a);
    for _ in 0..MAX_ATTEMPTS {
        if t >= b {
            break;
        }
        let last = h >= b - t;
        h = h.min(b - t);
        let err = rk.attempt(&mut rhs, t, q, h, &mut y_new, tol)?;
        if err <= 1.0 {
            rk.finish(&mut rhs, t, &y_new, h)?;
            rk.reuse_f_new();
            q.copy_from_slice(&y_new);
            t = if last { b } else { t + h };
        }
        // The elementary controller: h times 0.9 err^(-1/8), bounded to [0.2, 6].
        let factor = 0.9 * err.max(1e-10).powf(-rk.exponent());
        h *= factor.clamp(0.2, rk.max_growth());
    }
    if t < b {
        return Err(Error::TooManySteps {
            t,
            max_steps: MAX_ATTEMPTS,
        });
    }
    for d in drives {
        q[d.coordinate] = (d.f)(b)[0];
    }
    solve_positions(system, b, &fixed, q, options)?;
    Ok(())
}
