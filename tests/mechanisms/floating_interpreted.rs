//! The run-time route of a floating base (`InterpretedFloating`, codegen's tapes of
//! `compile_floating`'s routines, and `simulate_interpreted_floating`) against the
//! macro's `FloatingBase` type of the same declaration: two routes that run the same
//! routines and the same step.

use mechanism::{
    Error, FloatingBase, FloatingStep, InterpretedFloating, ParameterError, ParameterRange,
    mechanism, simulate_floating, simulate_interpreted_floating,
};
use nalgebra::{SVector, Vector3};

use super::floating_pinocchio::Solo;

/// The brick of floating_motion.rs with its weight and a parameter of declared range.
const BRICK: &str = "
    pub struct Falling;
    parameters { g = 9.81; m = 3.0 positive; }
    gravity = [0, 0, -g];
    link body {
        joint = floating(base);
        mass = m;
        com = [0.1, -0.05, 0.2];
        inertia = [[0.2, 0.01, -0.02], [0.01, 0.35, 0.03], [-0.02, 0.03, 0.5]];
    }
";

mechanism! {
    pub struct Falling;
    parameters { g = 9.81; m = 3.0 positive; }
    gravity = [0, 0, -g];
    link body {
        joint = floating(base);
        mass = m;
        com = [0.1, -0.05, 0.2];
        inertia = [[0.2, 0.01, -0.02], [0.01, 0.35, 0.03], [-0.02, 0.03, 0.5]];
    }
}

fn start() -> (SVector<f64, 7>, SVector<f64, 6>) {
    let axis = Vector3::new(0.3, -0.5, 0.8).normalize();
    let quat = nalgebra::UnitQuaternion::from_scaled_axis(axis * 0.9);
    let q = SVector::from([0.1, -0.2, 0.3, quat.i, quat.j, quat.k, quat.w]);
    (q, SVector::from([0.3, -0.2, 0.5, 1.0, 0.2, 1.5]))
}

/// The falling, tumbling brick over 2 s at h = 1e-3 by both routes: every sample's q and
/// v agree to 1e-12 of their largest entry (the step's operations are the same in the same
/// order; the tape and the emitted code may differ in the last bit where one fuses a
/// multiply-add, which 2000 steps can grow by a few orders, not to 1e-12).
#[test]
fn the_interpreted_brick_moves_as_the_macros() {
    let robot = InterpretedFloating::from_text(BRICK).unwrap();
    assert_eq!(robot.configuration(), Falling::CONFIGURATION);
    assert_eq!(robot.velocities(), Falling::VELOCITIES);
    let (q0, v0) = start();
    let zero = |_: f64, _: &SVector<f64, 7>, _: &SVector<f64, 6>| SVector::<f64, 6>::zeros();
    let brick = Falling::default();
    let macro_run = simulate_floating(
        &brick,
        &q0,
        &v0,
        2.0,
        1e-3,
        10,
        FloatingStep::Projection,
        zero,
    )
    .unwrap();
    let mut samples = Vec::new();
    simulate_interpreted_floating(
        &robot,
        (q0.as_slice(), v0.as_slice()),
        (2.0, 1e-3, 10),
        |t, q, v| samples.push((t, q.to_vec(), v.to_vec())),
    )
    .unwrap();
    assert_eq!(samples.len(), macro_run.t.len());
    for (k, (t, q, v)) in samples.iter().enumerate() {
        assert_eq!(*t, macro_run.t[k]);
        let dq = (0..7)
            .map(|i| (q[i] - macro_run.q[k][i]).abs())
            .fold(0.0, f64::max);
        let dv = (0..6)
            .map(|i| (v[i] - macro_run.v[k][i]).abs())
            .fold(0.0, f64::max);
        let scale = macro_run.q[k].amax().max(macro_run.v[k].amax());
        assert!(dq.max(dv) <= 1e-12 * scale, "t = {t}: {dq:e} {dv:e}");
    }
}

/// The `.mech` text of Solo12 imported from mechanisms/urdf/solo12.urdf on a floating base
/// (`UrdfOptions::floating`).
pub(crate) fn solo12_floating_text() -> String {
    let options = mechanism_codegen::UrdfOptions {
        file_name: "solo12.urdf".into(),
        floating: true,
        ..Default::default()
    };
    let urdf = include_str!("../../mechanisms/urdf/solo12.urdf");
    mechanism_codegen::urdf_to_mech(urdf, &options).unwrap()
}

/// Solo12 (imported with `floating = true`) by both routes at 8 random states: M, a,
/// T, Pi, the weight and the momentum (against the macro's centroidal momentum matrix
/// times v and centre of mass) to 1e-12 of each quantity's largest entry.
#[test]
fn interpreted_solo12_agrees_with_the_macro() {
    let robot = InterpretedFloating::from_text(&solo12_floating_text()).unwrap();
    assert_eq!(robot.configuration(), Solo::CONFIGURATION);
    assert_eq!(robot.neutral(), Solo::NEUTRAL);
    let solo = Solo::default();
    let mut seed = 0x2545_f491_4f6c_dd1d_u64;
    let mut random = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let close = |what: &str, ours: &[f64], theirs: &[f64]| {
        let scale = theirs.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
        let err = (ours.iter().zip(theirs)).fold(0.0_f64, |s, (a, b)| s.max((a - b).abs()));
        assert!(
            err <= 1e-12 * scale.max(1e-300),
            "{what}: {err:e} of {scale:e}"
        );
    };
    for _ in 0..8 {
        let mut q = SVector::<f64, 19>::from_fn(|_, _| random());
        let quat = Vector3::new(random(), random(), random()) * 2.0;
        let unit = nalgebra::UnitQuaternion::from_scaled_axis(quat);
        (q[3], q[4], q[5], q[6]) = (unit.i, unit.j, unit.k, unit.w);
        let v = SVector::<f64, 18>::from_fn(|_, _| 2.0 * random());
        let tau = SVector::<f64, 18>::from_fn(|_, _| 5.0 * random());
        let mut m = vec![0.0; 18 * 18];
        robot.mass_matrix(q.as_slice(), &mut m);
        let theirs = solo.mass_matrix(&q).transpose();
        close("M", &m, theirs.as_slice());
        let mut a = vec![0.0; 18];
        assert!(robot.forward_dynamics(0.0, q.as_slice(), v.as_slice(), tau.as_slice(), &mut a));
        close(
            "a",
            &a,
            solo.forward_dynamics(0.0, &q, &v, &tau).unwrap().as_slice(),
        );
        let t = robot.kinetic_energy(q.as_slice(), v.as_slice());
        close("T", &[t], &[solo.kinetic_energy(&q, &v)]);
        close(
            "Pi",
            &[robot.potential_energy(q.as_slice())],
            &[solo.potential_energy(&q)],
        );
        let weight = robot.weight(q.as_slice());
        // The weight m g, straight down: m from M's first entry.
        close(
            "weight",
            &weight,
            &[0.0, 0.0, -9.81 * solo.mass_matrix(&q)[(0, 0)]],
        );
        let momentum = robot.momentum(q.as_slice(), v.as_slice(), &mut m);
        let h = solo.centroidal_momentum_matrix(&q) * v;
        close("p", &momentum.linear, &[h[0], h[1], h[2]]);
        close("L_c", &momentum.angular, &[h[3], h[4], h[5]]);
        close(
            "c",
            &momentum.center_of_mass,
            solo.center_of_mass(&q).as_slice(),
        );
    }
}

/// Parameters keep their declared ranges on both routes: a negative mass is refused and the
/// old value kept; a quaternion off unit is refused before the first step.
#[test]
fn interpreted_floating_bad_inputs() {
    let mut robot = InterpretedFloating::from_text(BRICK).unwrap();
    let refused = robot.set_parameter(1, -1.0);
    assert!(
        matches!(refused, Err(ParameterError::OutOfRange { index: 1, .. })),
        "{refused:?}"
    );
    assert_eq!(robot.parameter_values(), [9.81, 3.0]);
    assert!(robot.set_parameter(1, 4.0).is_ok());
    let mut m = vec![0.0; 36];
    robot.mass_matrix(&robot.neutral(), &mut m);
    assert_eq!(m[0], 4.0);
    // The macro's type keeps the same range.
    assert_eq!(
        Falling::PARAMETER_RANGES,
        [ParameterRange::Any, ParameterRange::Positive]
    );
    assert_eq!(robot.parameter_ranges(), Falling::PARAMETER_RANGES);
    let mut brick = Falling::default();
    let refused = brick.set_parameter(1, -1.0);
    assert!(
        matches!(refused, Err(ParameterError::OutOfRange { index: 1, .. })),
        "{refused:?}"
    );
    assert_eq!(brick.parameter(1), Some(3.0));
    assert!(matches!(
        brick.set_parameter(2, 1.0),
        Err(ParameterError::NoSuchParameter { index: 2, count: 2 })
    ));
    assert!(brick.set_parameter(1, 4.0).is_ok());
    assert_eq!(brick.mass_matrix(&Falling::neutral())[(0, 0)], 4.0);
    let mut q0 = robot.neutral();
    q0[6] = 1.5;
    let result =
        simulate_interpreted_floating(&robot, (&q0, &[0.0; 6]), (1.0, 1e-3, 1), |_, _, _| {});
    assert!(
        matches!(result, Err(Error::QuaternionNotUnit { .. })),
        "{result:?}"
    );
    // A declaration without a floating root is refused by this route.
    assert!(InterpretedFloating::from_text("pub struct P; link a { joint = revolute(q, [0, 0, 1]); mass = 1; inertia = diag(1, 1, 1); }").is_err());
}
