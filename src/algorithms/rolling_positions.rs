//! The positions that velocity rows leave to the motion, along a prescribed motion.
//!
//! A velocity (nonholonomic) row A(q, t) q' + a(q, t) = 0 fixes rates, not positions: once
//! the drives and the position rows Phi(q, t) = 0 are met, the coordinates they leave free
//! (the sleigh's y, the rolling disc's contact point) are wherever the motion has carried
//! them, q(t) = q(t_a) + integral of q' from t_a. Inverse dynamics samples the motion at
//! given times, so between two samples this integrates q' = v(tau, q), the rates of the
//! velocity solve at (tau, q) with the drives' f(tau) and f'(tau), by the classical
//! Runge-Kutta method in steps of at most [`MAX_STEP`], each stage's positions first
//! brought back onto Phi = 0 (so that the velocity solve is consistent).

use crate::algorithms::kinematics::{AssemblyOptions, Drive, solve_positions, solve_velocities};
use crate::error::Error;
use crate::system::Kinematic;

/// The longest Runge-Kutta step (s): RK4's error per step is of order h^5 times the fifth
/// derivative of the motion, 1e-15 of it at 1 ms for motions of a few hertz.
pub const MAX_STEP: f64 = 1e-3;

/// Advances `q` from time `a` to time `b` along the drives (module docs); the driven
/// coordinates end at f(b) and the position rows are met at b.
///
/// # Errors
/// Those of the position and velocity solves at the stages.
pub(crate) fn advance(
    system: &dyn Kinematic,
    drives: &[Drive],
    q: &mut [f64],
    (a, b): (f64, f64),
    options: &AssemblyOptions,
) -> Result<(), Error> {
    let fixed: Vec<usize> = drives.iter().map(|d| d.coordinate).collect();
    let steps = ((b - a) / MAX_STEP).ceil().max(1.0) as usize;
    let h = (b - a) / steps as f64;
    let n = q.len();
    let rate = |tau: f64, at: &mut [f64]| -> Result<Vec<f64>, Error> {
        let mut qd = vec![0.0; n];
        for d in drives {
            let [f, fd, _] = (d.f)(tau);
            at[d.coordinate] = f;
            qd[d.coordinate] = fd;
        }
        solve_positions(system, tau, &fixed, at, options)?;
        solve_velocities(system, tau, at, &fixed, &mut qd, options)?;
        Ok(qd)
    };
    for step in 0..steps {
        let t = a + step as f64 * h;
        let q0 = q.to_vec();
        let stage = |k: &[f64], c: f64| -> Vec<f64> {
            q0.iter().zip(k).map(|(x, v)| x + c * h * v).collect()
        };
        let mut s = q0.clone();
        let k1 = rate(t, &mut s)?;
        let mut s = stage(&k1, 0.5);
        let k2 = rate(t + 0.5 * h, &mut s)?;
        let mut s = stage(&k2, 0.5);
        let k3 = rate(t + 0.5 * h, &mut s)?;
        let mut s = stage(&k3, 1.0);
        let k4 = rate(t + h, &mut s)?;
        for i in 0..n {
            q[i] = q0[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
    }
    for d in drives {
        q[d.coordinate] = (d.f)(b)[0];
    }
    solve_positions(system, b, &fixed, q, options)?;
    Ok(())
}
