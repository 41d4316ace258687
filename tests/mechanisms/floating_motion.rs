//! Floating bodies in motion (`simulate_floating`), against closed forms and the
//! conservation laws: a symmetric top's torque-free precession (Euler's equations), a
//! tumbling brick's energy and linear and angular momentum over 100 s, a falling Solo12's
//! energy and momentum under gravity, the two stepping methods' order, and the starting
//! quaternion's check.
//!
//! The momenta are read off M v: its root rows are the whole tree's momentum in the root's
//! axes, the force part p_r and the moment about the root's origin L_r (the root's motion
//! subspace is the identity), so in the world p = R p_r and, about the world's origin,
//! L = x x p + R L_r.

use mechanism::{
    Error, FloatingBase, FloatingStep, FloatingTrajectory, integrate_floating, mechanism,
    simulate_floating,
};
use nalgebra::{Matrix3, SVector, Vector3};

mechanism! {
    pub struct Top;
    parameters { a = 0.3; c = 0.5; }
    link body { joint = floating(base); mass = 2.0; inertia = diag(a, a, c); }
}

mechanism! {
    pub struct Brick;
    link body {
        joint = floating(base);
        mass = 3.0;
        com = [0.1, -0.05, 0.2];
        inertia = [[0.2, 0.01, -0.02], [0.01, 0.35, 0.03], [-0.02, 0.03, 0.5]];
    }
}

// Solo12 as floating_pinocchio.rs declares it (one expansion for the binary).
use super::floating_pinocchio::Solo;

type Q = SVector<f64, 7>;
type V = SVector<f64, 6>;

fn rotation<const NQ: usize>(q: &SVector<f64, NQ>) -> Matrix3<f64> {
    let quat = nalgebra::Quaternion::new(q[6], q[3], q[4], q[5]);
    *nalgebra::UnitQuaternion::from_quaternion(quat)
        .to_rotation_matrix()
        .matrix()
}

/// (p, L): the world's linear momentum and the angular momentum about its origin.
fn momenta<R: FloatingBase<NQ, NV>, const NQ: usize, const NV: usize>(
    robot: &R,
    q: &SVector<f64, NQ>,
    v: &SVector<f64, NV>,
) -> (Vector3<f64>, Vector3<f64>) {
    let h = robot.mass_matrix(q) * v;
    let r = rotation(q);
    let p = r * Vector3::new(h[0], h[1], h[2]);
    let l = Vector3::new(q[0], q[1], q[2]).cross(&p) + r * Vector3::new(h[3], h[4], h[5]);
    (p, l)
}

fn start() -> (Q, V) {
    let axis = Vector3::new(0.3, -0.5, 0.8).normalize();
    let quat = nalgebra::UnitQuaternion::from_scaled_axis(axis * 0.9);
    let q = Q::from([0.1, -0.2, 0.3, quat.i, quat.j, quat.k, quat.w]);
    (q, V::from([0.3, -0.2, 0.5, 1.0, 0.2, 1.5]))
}

/// Euler's equations for a symmetric body (A = B = a, C = c) without torque: w3 is
/// constant and (w1 + i w2)(t) = (w1 + i w2)(0) e^(-i lambda t), lambda = (a - c) w3 / a;
/// in the world the symmetry axis turns about the constant L at |L| / a. Both to 1e-9 over
/// 20 s at h = 1e-3 (RK4's global error, about 1e-12 here, has a thousandfold margin).
#[test]
fn a_symmetric_top_precesses_as_eulers_equations_say() {
    let top = Top::default();
    let (q0, _) = start();
    let v0 = V::from([0.0, 0.0, 0.0, 0.7, -0.4, 2.5]);
    for method in [FloatingStep::Projection, FloatingStep::LieGroup] {
        let run = simulate_floating(&top, &q0, &v0, 20.0, 1e-3, 100, method, |_, _, _| {
            V::zeros()
        })
        .unwrap();
        let (a, c) = (0.3, 0.5);
        let lambda = (a - c) * v0[5] / a;
        let (_, l) = momenta(&top, &q0, &v0);
        let axis0 = rotation(&q0).column(2).into_owned();
        for (k, t) in run.t.iter().enumerate() {
            let (cs, sn) = ((lambda * t).cos(), (lambda * t).sin());
            let w1 = v0[3] * cs + v0[4] * sn;
            let w2 = v0[4] * cs - v0[3] * sn;
            let w = run.v[k];
            let err = (w[3] - w1)
                .abs()
                .max((w[4] - w2).abs())
                .max((w[5] - v0[5]).abs());
            assert!(err < 1e-9, "{method:?}: w at t = {t}: {err:e}");
            let turned = nalgebra::Rotation3::from_axis_angle(
                &nalgebra::Unit::new_normalize(l),
                l.norm() / a * t,
            );
            let axis = rotation(&run.q[k]).column(2).into_owned();
            let err = (axis - turned * axis0).amax();
            assert!(
                err < 1e-9,
                "{method:?}: the symmetry axis at t = {t}: {err:e}"
            );
        }
    }
}

/// The largest relative drift of T, p and L over a run of the free `robot`.
fn drifts<R: FloatingBase<NQ, NV>, const NQ: usize, const NV: usize>(
    robot: &R,
    run: &FloatingTrajectory<NQ, NV>,
) -> [f64; 4] {
    let (p0, l0) = momenta(robot, &run.q[0], &run.v[0]);
    let e0 = robot.kinetic_energy(&run.q[0], &run.v[0]);
    let mut worst = [0.0_f64; 4];
    for (q, v) in run.q.iter().zip(&run.v) {
        let (p, l) = momenta(robot, q, v);
        let unit = (q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6]).sqrt();
        let now = [
            (robot.kinetic_energy(q, v) - e0).abs() / e0,
            (p - p0).amax() / p0.amax(),
            (l - l0).amax() / l0.amax(),
            (unit - 1.0).abs(),
        ];
        for (w, n) in worst.iter_mut().zip(now) {
            *w = w.max(n);
        }
    }
    worst
}

/// A brick tumbling about all three axes with its centre off the root's origin: T, p and
/// L (about the world's origin: the brick also translates) kept to 1e-9 of their size over
/// 100 s (2e5 steps of 5e-4: RK4's error per step, about (|w| h)^5 = 4e-16, summed; measured
/// at most 4e-11), and the quaternion unit to 1e-14 by either method.
#[test]
fn a_free_brick_keeps_its_energy_and_momenta_for_100_s() {
    let brick = Brick::default();
    let (q0, v0) = start();
    for method in [FloatingStep::Projection, FloatingStep::LieGroup] {
        let run = simulate_floating(&brick, &q0, &v0, 100.0, 5e-4, 2000, method, |_, _, _| {
            V::zeros()
        })
        .unwrap();
        let [e, p, l, unit] = drifts(&brick, &run);
        eprintln!(
            "brick, {method:?}: drift T {e:.1e}, p {p:.1e}, L {l:.1e}, |quaternion| - 1 {unit:.1e}"
        );
        assert!(
            e < 1e-9 && p < 1e-9 && l < 1e-9,
            "{method:?}: {e:e} {p:e} {l:e}"
        );
        assert!(unit < 1e-14, "{method:?}: |quaternion| - 1 = {unit:e}");
    }
}

/// Both methods are of order 4: halving h from 1e-2 divides the error at t = 2 s (against
/// a run at h = 1.25e-3) by more than 12 (16 in the limit).
#[test]
fn both_steps_are_of_fourth_order() {
    let brick = Brick::default();
    let (q0, v0) = start();
    let zero = |_: f64, _: &Q, _: &V| V::zeros();
    for method in [FloatingStep::Projection, FloatingStep::LieGroup] {
        let run = |h: f64| simulate_floating(&brick, &q0, &v0, 2.0, h, 1 << 20, method, zero);
        let reference = run(1.25e-3).unwrap();
        let (qr, vr) = (reference.q.last().unwrap(), reference.v.last().unwrap());
        let error = |h: f64| {
            let r = run(h).unwrap();
            let (q, v) = (r.q.last().unwrap(), r.v.last().unwrap());
            (q - qr).amax().max((v - vr).amax())
        };
        let (coarse, fine) = (error(1e-2), error(5e-3));
        eprintln!("{method:?}: error at h = 1e-2 {coarse:.2e}, 5e-3 {fine:.2e}");
        assert!(coarse / fine > 12.0, "{method:?}: ratio {}", coarse / fine);
    }
}

/// Solo12 falling with its legs free from a spinning start: T + Pi kept to 1e-9 of T over
/// 2 s, the momentum's change p(t) - p(0) = m g t to 1e-9 of |m g t| and the vertical
/// angular momentum about the world's origin (gravity has no moment about the vertical)
/// to 1e-9 of |L|; the quaternion unit to 1e-14.
#[test]
fn a_falling_solo12_keeps_energy_and_momentum() {
    let solo = Solo::default();
    let mut q0 = Solo::neutral();
    let (qb, vb) = start();
    for k in 0..7 {
        q0[k] = qb[k];
    }
    let mut v0 = SVector::<f64, 18>::zeros();
    for k in 0..6 {
        v0[k] = vb[k];
    }
    for j in 0..12 {
        q0[7 + j] = 0.4 * ((j as f64) * 1.3).sin();
        v0[6 + j] = 1.5 * ((j as f64) * 0.7).cos();
    }
    let run = simulate_floating(
        &solo,
        &q0,
        &v0,
        2.0,
        5e-4,
        40,
        FloatingStep::Projection,
        |_, _, _| SVector::<f64, 18>::zeros(),
    )
    .unwrap();
    let energy = |q: &SVector<f64, 19>, v: &SVector<f64, 18>| {
        solo.kinetic_energy(q, v) + solo.potential_energy(q)
    };
    let mass = solo.mass_matrix(&q0)[(0, 0)];
    let (t0, e0) = (solo.kinetic_energy(&q0, &v0), energy(&q0, &v0));
    let (p0, l0) = momenta(&solo, &q0, &v0);
    for (k, t) in run.t.iter().enumerate() {
        let (q, v) = (&run.q[k], &run.v[k]);
        let e = (energy(q, v) - e0).abs() / t0;
        assert!(e < 1e-9, "energy at t = {t}: {e:e}");
        let (p, l) = momenta(&solo, q, v);
        let fall = Vector3::new(0.0, 0.0, -9.81 * mass * t);
        let dp = (p - p0 - fall).amax() / (9.81 * mass * 2.0);
        assert!(dp < 1e-9, "momentum at t = {t}: {dp:e}");
        let dl = (l[2] - l0[2]).abs() / l0.norm();
        assert!(dl < 1e-9, "vertical angular momentum at t = {t}: {dl:e}");
        let unit = (3..7).map(|i| q[i] * q[i]).sum::<f64>().sqrt();
        assert!((unit - 1.0).abs() < 1e-14);
    }
}

/// A starting quaternion that is not unit is refused with the quaternion and its norm; one
/// within 1e-9 is normalised.
#[test]
fn a_non_unit_starting_quaternion_is_refused() {
    let brick = Brick::default();
    let q0 = Q::from([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.5]);
    let zero = |_: f64, _: &Q, _: &V| V::zeros();
    let step = FloatingStep::Projection;
    let e = simulate_floating(&brick, &q0, &V::zeros(), 1.0, 1e-2, 1, step, zero).unwrap_err();
    assert!(matches!(e, Error::QuaternionNotUnit { norm, .. } if norm == 1.5));
    assert!(e.to_string().contains("has norm 1.5, not 1"), "{e}");
    let q0 = Q::from([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0 + 5e-10]);
    let run = simulate_floating(&brick, &q0, &V::zeros(), 0.1, 1e-2, 1, step, zero).unwrap();
    assert_eq!(run.q[0][6], 1.0);
}

/// integrate is exact for a constant twist: one step of dt equals ten of dt / 10, and a
/// rotation about the root's z by w dt turns the quaternion by half that angle.
#[test]
fn integrate_composes_along_a_constant_twist() {
    let (q0, v) = start();
    let once = integrate_floating(&q0, &v, 0.5);
    let mut q = q0;
    for _ in 0..10 {
        q = integrate_floating(&q, &v, 0.05);
    }
    assert!((once - q).amax() < 1e-14, "{:e}", (once - q).amax());
    let spin = V::from([0.0, 0.0, 0.0, 0.0, 0.0, 2.0]);
    let turned = integrate_floating(&Q::from([0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]), &spin, 0.3);
    assert!((turned[5] - 0.3_f64.sin()).abs() < 1e-15 && (turned[6] - 0.3_f64.cos()).abs() < 1e-15);
}
