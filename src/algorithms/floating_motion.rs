//! The motion of a floating-base robot ([`FloatingBase`]) from an initial configuration
//! and velocity under given joint efforts: fixed-step fourth-order Runge-Kutta in one of
//! two forms, both four forward dynamics per step.
//!
//! - [`FloatingStep::Projection`]: RK4 on the embedded ODE in R^(NQ + NV), p' = R v,
//!   quaternion' = 1/2 quaternion (w, 0) (Hamilton product), joints' = rates,
//!   v' = a(q, v), then the quaternion projected back onto |quaternion| = 1 (the
//!   orthogonal projection onto the norm's constraint surface: a division by the norm).
//!   The exact flow keeps the norm (d|quaternion|^2/dt = 0), so RK4 moves it by O(h^5) per
//!   step and the projection removes that.
//! - [`FloatingStep::LieGroup`]: Munthe-Kaas' RK4 (RKMK4) on SE(3) x R^joints: each stage
//!   configuration is q0 moved by exp(Theta_i) ([`crate::integrate_floating`]), the body
//!   twists corrected by dexp^-1_{-Theta}(xi) = xi + 1/2 [Theta, xi] + 1/12 [Theta,
//!   [Theta, xi]] (enough for order 4), so the quaternion stays unit by construction.
//!
//! The test `floating_free_body` measures both on a tumbling body; `Projection` is the
//! default (docs/src/floating.md says why).

use nalgebra::SVector;

use crate::error::Error;
use crate::system::FloatingBase;
use crate::system::free_flyer::integrate;

/// How [`simulate_floating`] steps (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FloatingStep {
    /// RK4 on the embedded ODE, the quaternion normalised after each step.
    #[default]
    Projection,
    /// RKMK4 on SE(3) x R^joints.
    LieGroup,
}

/// A floating-base motion sampled at the step ends: t, q and v.
#[derive(Clone, Debug, PartialEq)]
pub struct FloatingTrajectory<const NQ: usize, const NV: usize> {
    /// Times (s), from 0.
    pub t: Vec<f64>,
    /// Configurations q (NQ: position, quaternion x y z w, joints).
    pub q: Vec<SVector<f64, NQ>>,
    /// Velocities v (NV: velocity and angular velocity in the root's axes, joint rates).
    pub v: Vec<SVector<f64, NV>>,
}

/// The largest |norm - 1| of a starting quaternion that is accepted (and normalised):
/// nine digits, what a quaternion typed by hand or printed with %.9g keeps.
pub const QUATERNION_NORM_TOLERANCE: f64 = 1e-9;

/// Simulates `robot` from (q0, v0) for `t_end` s with the fixed step `h`, the joint efforts
/// `effort(t, q, v)` (NV entries: the root's six are a wrench on the root, in its axes),
/// storing every `every`-th step (and the last).
///
/// # Errors
/// [`Error::QuaternionNotUnit`] for a starting quaternion whose norm differs from 1 by more
/// than [`QUATERNION_NORM_TOLERANCE`]; [`Error::InvalidOption`] for `h` or `t_end` not
/// positive and finite or `every` = 0; [`Error::NonFinite`] where the forward dynamics
/// fails (M not positive definite beyond round-off) or the state leaves the finite numbers.
#[allow(clippy::too_many_arguments)]
pub fn simulate_floating<R, const NQ: usize, const NV: usize>(
    robot: &R,
    q0: &SVector<f64, NQ>,
    v0: &SVector<f64, NV>,
    t_end: f64,
    h: f64,
    every: usize,
    method: FloatingStep,
    effort: impl Fn(f64, &SVector<f64, NQ>, &SVector<f64, NV>) -> SVector<f64, NV>,
) -> Result<FloatingTrajectory<NQ, NV>, Error>
where
    R: FloatingBase<NQ, NV>,
{
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(h) || !positive(t_end) {
        let (option, value) = if positive(h) {
            ("t_end", t_end)
        } else {
            ("h", h)
        };
        let allowed = "a positive finite number";
        return Err(Error::InvalidOption {
            option,
            value,
            allowed,
        });
    }
    if every == 0 {
        let allowed = "every >= 1";
        return Err(Error::InvalidOption {
            option: "every",
            value: 0.0,
            allowed,
        });
    }
    let mut q = unit_start(q0)?;
    let mut v = *v0;
    let steps = step_count(t_end, h);
    let mut out = FloatingTrajectory {
        t: vec![0.0],
        q: vec![q],
        v: vec![v],
    };
    let accel = |t: f64, q: &SVector<f64, NQ>, v: &SVector<f64, NV>| {
        let u = effort(t, q, v);
        robot
            .forward_dynamics(t, q, v, &u)
            .ok_or_else(|| Error::NonFinite {
                what: "the forward dynamics (M not positive definite or a non-finite a)".into(),
                t,
            })
    };
    for k in 0..steps {
        let t = k as f64 * h;
        (q, v) = match method {
            FloatingStep::Projection => projection_step(&accel, t, &q, &v, h)?,
            FloatingStep::LieGroup => lie_step(&accel, t, &q, &v, h)?,
        };
        if q.iter().chain(v.iter()).any(|x| !x.is_finite()) {
            let what = "the state".to_string();
            return Err(Error::NonFinite { what, t: t + h });
        }
        if (k + 1) % every == 0 || k + 1 == steps {
            out.t.push((k + 1) as f64 * h);
            out.q.push(q);
            out.v.push(v);
        }
    }
    Ok(out)
}

/// The steps of h that reach t_end: t_end / h rounded up, a quotient within 1e-9 of a
/// whole number taken as that number (0.1 / 1e-3 is 100.00000000000001 in f64: 100
/// steps, not 101 ending at 0.101).
pub(crate) fn step_count(t_end: f64, h: f64) -> usize {
    (t_end / h - 1e-9).ceil().max(1.0) as usize
}

/// q0 with its quaternion normalised, or the error for one too far from unit.
fn unit_start<const NQ: usize>(q0: &SVector<f64, NQ>) -> Result<SVector<f64, NQ>, Error> {
    let mut q = *q0;
    if NQ < 7 {
        return Ok(q);
    }
    let norm = quaternion_norm(q.as_slice())?;
    for k in 3..7 {
        q[k] /= norm;
    }
    Ok(q)
}

/// The norm of q's quaternion (entries 3..7), or [`Error::QuaternionNotUnit`] when it
/// differs from 1 by more than [`QUATERNION_NORM_TOLERANCE`] (or is NaN).
pub(crate) fn quaternion_norm(q: &[f64]) -> Result<f64, Error> {
    let norm = (3..7).map(|k| q[k] * q[k]).sum::<f64>().sqrt();
    // A NaN norm is refused too.
    if (norm - 1.0).abs().is_nan() || (norm - 1.0).abs() > QUATERNION_NORM_TOLERANCE {
        return Err(Error::QuaternionNotUnit {
            quaternion: [q[3], q[4], q[5], q[6]],
            norm,
        });
    }
    Ok(norm)
}

/// q' of the embedded ODE: p' = R v, quaternion' = 1/2 quaternion (w, 0), joints' = rates.
fn rate<const NQ: usize, const NV: usize>(
    q: &SVector<f64, NQ>,
    v: &SVector<f64, NV>,
) -> SVector<f64, NQ> {
    let mut d = SVector::<f64, NQ>::zeros();
    configuration_rate(q.as_slice(), v.as_slice(), d.as_mut_slice());
    d
}

/// [`rate`] on slices (q of nq = nv + 1 entries, v of nv, the rate into `d`, nq).
pub(crate) fn configuration_rate(q: &[f64], v: &[f64], d: &mut [f64]) {
    let quat = [q[3], q[4], q[5], q[6]];
    let r = crate::system::free_flyer::rotation(&quat);
    for i in 0..3 {
        d[i] = r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2];
    }
    let [x, y, z, w] = quat;
    let [a, b, c] = [v[3], v[4], v[5]];
    // 1/2 (x, y, z, w) (a, b, c, 0).
    d[3] = 0.5 * (w * a + y * c - z * b);
    d[4] = 0.5 * (w * b + z * a - x * c);
    d[5] = 0.5 * (w * c + x * b - y * a);
    d[6] = -0.5 * (x * a + y * b + z * c);
    d[7..].copy_from_slice(&v[6..]);
}

type Step<const NQ: usize, const NV: usize> = (SVector<f64, NQ>, SVector<f64, NV>);

/// One RK4 step of the embedded ODE, then the quaternion normalised.
fn projection_step<const NQ: usize, const NV: usize>(
    accel: &impl Fn(f64, &SVector<f64, NQ>, &SVector<f64, NV>) -> Result<SVector<f64, NV>, Error>,
    t: f64,
    q: &SVector<f64, NQ>,
    v: &SVector<f64, NV>,
    h: f64,
) -> Result<Step<NQ, NV>, Error> {
    let (kq1, kv1) = (rate(q, v), accel(t, q, v)?);
    let (q2, v2) = (q + kq1 * (h / 2.0), v + kv1 * (h / 2.0));
    let (kq2, kv2) = (rate(&q2, &v2), accel(t + h / 2.0, &q2, &v2)?);
    let (q3, v3) = (q + kq2 * (h / 2.0), v + kv2 * (h / 2.0));
    let (kq3, kv3) = (rate(&q3, &v3), accel(t + h / 2.0, &q3, &v3)?);
    let (q4, v4) = (q + kq3 * h, v + kv3 * h);
    let (kq4, kv4) = (rate(&q4, &v4), accel(t + h, &q4, &v4)?);
    let mut qn = q + (kq1 + kq2 * 2.0 + kq3 * 2.0 + kq4) * (h / 6.0);
    let vn = v + (kv1 + kv2 * 2.0 + kv3 * 2.0 + kv4) * (h / 6.0);
    let norm = (3..7).map(|k| qn[k] * qn[k]).sum::<f64>().sqrt();
    for k in 3..7 {
        qn[k] /= norm;
    }
    Ok((qn, vn))
}

/// [a, b] of se(3) twists (v, w): (w_a x v_b - w_b x v_a, w_a x w_b); joints commute.
fn bracket<const NV: usize>(a: &SVector<f64, NV>, b: &SVector<f64, NV>) -> SVector<f64, NV> {
    let cross = |u: [f64; 3], w: [f64; 3]| {
        [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ]
    };
    let (va, wa) = ([a[0], a[1], a[2]], [a[3], a[4], a[5]]);
    let (vb, wb) = ([b[0], b[1], b[2]], [b[3], b[4], b[5]]);
    let (x, y, w) = (cross(wa, vb), cross(wb, va), cross(wa, wb));
    let mut out = SVector::<f64, NV>::zeros();
    for i in 0..3 {
        out[i] = x[i] - y[i];
        out[3 + i] = w[i];
    }
    out
}

/// dexp^-1_{-theta}(xi) to the terms order 4 needs: xi + 1/2 [theta, xi] + 1/12 [theta,
/// [theta, xi]].
fn dexp_inv<const NV: usize>(theta: &SVector<f64, NV>, xi: &SVector<f64, NV>) -> SVector<f64, NV> {
    let b = bracket(theta, xi);
    xi + b * 0.5 + bracket(theta, &b) / 12.0
}

/// One RKMK4 step on SE(3) x R^joints (module docs).
fn lie_step<const NQ: usize, const NV: usize>(
    accel: &impl Fn(f64, &SVector<f64, NQ>, &SVector<f64, NV>) -> Result<SVector<f64, NV>, Error>,
    t: f64,
    q: &SVector<f64, NQ>,
    v: &SVector<f64, NV>,
    h: f64,
) -> Result<Step<NQ, NV>, Error> {
    let k1 = *v;
    let a1 = accel(t, q, v)?;
    let th2 = k1 * (h / 2.0);
    let (q2, v2) = (integrate(q, &th2, 1.0), v + a1 * (h / 2.0));
    let k2 = dexp_inv(&th2, &v2);
    let a2 = accel(t + h / 2.0, &q2, &v2)?;
    let th3 = k2 * (h / 2.0);
    let (q3, v3) = (integrate(q, &th3, 1.0), v + a2 * (h / 2.0));
    let k3 = dexp_inv(&th3, &v3);
    let a3 = accel(t + h / 2.0, &q3, &v3)?;
    let th4 = k3 * h;
    let (q4, v4) = (integrate(q, &th4, 1.0), v + a3 * h);
    let k4 = dexp_inv(&th4, &v4);
    let a4 = accel(t + h, &q4, &v4)?;
    let theta = (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
    let vn = v + (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (h / 6.0);
    Ok((integrate(q, &theta, 1.0), vn))
}
