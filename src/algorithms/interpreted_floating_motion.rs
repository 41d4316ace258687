//! The motion of a floating-base robot read at run time ([`InterpretedFloating`]): the
//! step [`crate::simulate_floating`] takes by default ([`crate::FloatingStep::Projection`]:
//! RK4 on the embedded ODE p' = R v, quaternion' = 1/2 quaternion (w, 0), joints' = rates,
//! v' = a(q, v), then the quaternion divided by its norm), on vectors sized at run time,
//! with the same operations in the same order. What `mechanism simulate robot.mech` runs
//! for a floating declaration. The step loop allocates nothing: its stages live in one
//! scratch buffer made before the first step.

use crate::algorithms::floating_motion::{configuration_rate, quaternion_norm, step_count};
use crate::error::Error;
use crate::system::InterpretedFloating;

/// The stages of one step: rates of q (nq) and of v (nv) at the four stages, the stage
/// state, and the efforts (zero: the declared ones are in the bias).
struct Stages {
    kq: [Vec<f64>; 4],
    kv: [Vec<f64>; 4],
    q: Vec<f64>,
    v: Vec<f64>,
    effort: Vec<f64>,
}

/// Simulates `robot` from (q0, v0) for `t_end` s with fixed steps of `h` under the declared
/// efforts alone, and hands `sample(t, q, v)` the start and every `every`-th step (and the
/// last). A starting quaternion within [`crate::QUATERNION_NORM_TOLERANCE`] of unit is
/// normalised first.
///
/// # Errors
/// [`Error::QuaternionNotUnit`] for a starting quaternion farther from unit;
/// [`Error::InvalidOption`] for `h` or `t_end` not positive and finite, `every` = 0, or q0
/// and v0 not of `robot.nq()` and `robot.nv()` entries; [`Error::NonFinite`] where the
/// forward dynamics fails or the state leaves the finite numbers (the samples before it
/// were handed on).
pub fn simulate_interpreted_floating(
    robot: &InterpretedFloating,
    (q0, v0): (&[f64], &[f64]),
    (t_end, h, every): (f64, f64, usize),
    mut sample: impl FnMut(f64, &[f64], &[f64]),
) -> Result<(), Error> {
    check_options(robot, (q0, v0), (t_end, h, every))?;
    let (nq, nv) = (robot.nq(), robot.nv());
    let mut q = q0.to_vec();
    let norm = quaternion_norm(&q)?;
    for x in &mut q[3..7] {
        *x /= norm;
    }
    let mut v = v0.to_vec();
    let mut s = Stages {
        kq: std::array::from_fn(|_| vec![0.0; nq]),
        kv: std::array::from_fn(|_| vec![0.0; nv]),
        q: vec![0.0; nq],
        v: vec![0.0; nv],
        effort: vec![0.0; nv],
    };
    sample(0.0, &q, &v);
    let steps = step_count(t_end, h);
    for k in 0..steps {
        let t = k as f64 * h;
        step(robot, &mut s, t, (&mut q, &mut v), h)?;
        if q.iter().chain(&v).any(|x| !x.is_finite()) {
            let what = "the state".to_string();
            return Err(Error::NonFinite { what, t: t + h });
        }
        if (k + 1) % every == 0 || k + 1 == steps {
            sample((k + 1) as f64 * h, &q, &v);
        }
    }
    Ok(())
}

/// The refusals of [`simulate_interpreted_floating`] before its first step but the
/// quaternion's.
fn check_options(
    robot: &InterpretedFloating,
    (q0, v0): (&[f64], &[f64]),
    (t_end, h, every): (f64, f64, usize),
) -> Result<(), Error> {
    let positive = |x: f64| x.is_finite() && x > 0.0;
    let refuse = |option, value, allowed| {
        Err(Error::InvalidOption {
            option,
            value,
            allowed,
        })
    };
    if !positive(h) {
        return refuse("h", h, "a positive finite number");
    }
    if !positive(t_end) {
        return refuse("t_end", t_end, "a positive finite number");
    }
    if every == 0 {
        return refuse("every", 0.0, "every >= 1");
    }
    if q0.len() != robot.nq() {
        return refuse(
            "q0 entries",
            q0.len() as f64,
            "nq, the configuration's size",
        );
    }
    if v0.len() != robot.nv() {
        return refuse("v0 entries", v0.len() as f64, "nv, the velocities' size");
    }
    Ok(())
}

/// One RK4 step of the embedded ODE from (q, v) at t, then the quaternion normalised
/// (the operations of `floating_motion::projection_step`, entry by entry).
fn step(
    robot: &InterpretedFloating,
    s: &mut Stages,
    t: f64,
    (q, v): (&mut [f64], &mut [f64]),
    h: f64,
) -> Result<(), Error> {
    let times = [t, t + h / 2.0, t + h / 2.0, t + h];
    let weights = [h / 2.0, h / 2.0, h];
    s.q.copy_from_slice(q);
    s.v.copy_from_slice(v);
    for stage in 0..4 {
        configuration_rate(&s.q, &s.v, &mut s.kq[stage]);
        let ok = robot.forward_dynamics(times[stage], &s.q, &s.v, &s.effort, &mut s.kv[stage]);
        if !ok {
            return Err(Error::NonFinite {
                what: "the forward dynamics (M not positive definite or a non-finite a)".into(),
                t: times[stage],
            });
        }
        if stage < 3 {
            let w = weights[stage];
            for (i, x) in s.q.iter_mut().enumerate() {
                *x = q[i] + s.kq[stage][i] * w;
            }
            for (i, x) in s.v.iter_mut().enumerate() {
                *x = v[i] + s.kv[stage][i] * w;
            }
        }
    }
    let combine = |k: &[Vec<f64>; 4], i: usize| k[0][i] + k[1][i] * 2.0 + k[2][i] * 2.0 + k[3][i];
    for (i, x) in q.iter_mut().enumerate() {
        *x += combine(&s.kq, i) * (h / 6.0);
    }
    for (i, x) in v.iter_mut().enumerate() {
        *x += combine(&s.kv, i) * (h / 6.0);
    }
    let norm = (3..7).map(|k| q[k] * q[k]).sum::<f64>().sqrt();
    for x in &mut q[3..7] {
        *x /= norm;
    }
    Ok(())
}
