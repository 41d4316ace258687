//! Inverse dynamics: the seed's driving torque for phi = 2 pi t against the hand-reduced
//! closed form, the round trip through forward dynamics, and a four-bar driven into a dead
//! point.

use std::f64::consts::PI;
use std::sync::{Arc, Mutex};

use crate::common::{CrankSlider, FourBar};
use mechanism::{
    AssemblyOptions, Drive, Error, IntegratorOptions, InverseDynamics, Method, SimulationOptions,
    inverse_dynamics, sample_times, simulate,
};

fn spin() -> Drive {
    Drive::new(0, |t| [2.0 * PI * t, 2.0 * PI, 0.0])
}

/// With phi'' = 0 the reduced equation (see runtime_integrators.rs) gives the torque
/// tau = mx X'(phi) X''(phi) phi'^2 - (m1 a1 + m2/2 l1) g sin(phi).
#[test]
fn seed_driving_torque_matches_the_reduced_model() {
    let s = CrankSlider::seed(); // its declared torque on phi must be replaced, not added
    let res = inverse_dynamics(
        &s,
        vec![spin()],
        &sample_times(0.0, 1.0, 100.0),
        &AssemblyOptions::default(),
    )
    .unwrap();
    assert_eq!(res.samples.len(), 101);
    assert_eq!(res.headers()[13], "tau_phi");
    let (h, l1, l2, d, m1, m2, m3, a1, g) = (0.12f64, 0.08, 0.3, 0.1, 0.12, 0.5, 2.0, 0.04, 9.81);
    let mut worst = 0.0f64;
    for smp in &res.samples {
        let (sp, cp) = smp.q[0].sin_cos();
        let x = (l2 * l2 - (h + l1 * cp).powi(2) - (d + l1 * sp).powi(2)).sqrt();
        let x1 = l1 * (h * sp - d * cp) / x;
        let x2 = (l1 * (h * cp + d * sp) - x1 * x1) / x;
        let tau =
            (m2 / 2.0 + m3) * x1 * x2 * (2.0 * PI).powi(2) - (m1 * a1 + m2 / 2.0 * l1) * g * sp;
        worst = worst.max((smp.driving[0] - tau).abs());
        assert!(smp.qdd[0].abs() < 1e-9);
    }
    let peak = res
        .samples
        .iter()
        .map(|s| s.driving[0].abs())
        .fold(0.0, f64::max);
    println!(
        "seed phi = 2 pi t: peak driving torque {peak:.6} N m, max deviation from the reduced closed form {worst:e} N m"
    );
    assert!(worst < 1e-11 * peak.max(1.0));
}

/// The seed's multipliers are the rod's force on the slider at C (module docs of inverse):
/// the slider's own equation, (m2/2 + m3) x_c'' = -(Phi_q^T lambda)_x_c = lambda_1 (Phi_q[0][3] = -1),
/// is the x-balance of the slider.
#[test]
fn seed_multiplier_is_the_force_on_the_slider() {
    let s = CrankSlider::seed();
    let res = inverse_dynamics(
        &s,
        vec![spin()],
        &sample_times(0.0, 1.0, 50.0),
        &AssemblyOptions::default(),
    )
    .unwrap();
    for smp in &res.samples {
        let lhs = (0.5 / 2.0 + 2.0) * smp.qdd[3];
        assert!((lhs - smp.lambda[0]).abs() < 1e-10 * (1.0 + lhs.abs()));
    }
}

/// Round trip: the inverse-dynamics torque for phi = 2 pi t, evaluated inside the force
/// closure of a forward simulation from the same initial state, reproduces phi = 2 pi t.
#[test]
fn round_trip_reproduces_the_prescribed_motion() {
    let plain = CrankSlider::seed();
    let inv = Arc::new(Mutex::new(
        InverseDynamics::new(&plain, vec![spin()], AssemblyOptions::default()).unwrap(),
    ));
    let mut forward = CrankSlider::seed();
    let (inv2, plain2) = (inv.clone(), plain.clone());
    forward.torque = Some(Arc::new(move |t, _, _| {
        inv2.lock()
            .unwrap()
            .solve_at(&plain2, t)
            .map(|s| s.driving[0])
            .unwrap_or(f64::NAN)
    }));
    let o = SimulationOptions {
        t_end: 2.0,
        integrator: IntegratorOptions {
            method: Method::Dop853,
            rtol: 1e-12,
            atol: 1e-13,
            ..Default::default()
        },
        ..Default::default()
    };
    let tr = simulate(&forward, &o).unwrap();
    let worst = tr
        .samples()
        .map(|s| (s.q[0] - 2.0 * PI * s.t).abs())
        .fold(0.0, f64::max);
    println!(
        "round trip over 2 s: max |phi - 2 pi t| = {worst:e} rad ({} steps)",
        tr.stats.steps
    );
    assert!(worst < 1e-6, "{worst:e}");
}

/// The locking four-bar (l2 + l3 < l1 + d) driven at 1 rad/s from th1 = pi/2 reaches its
/// dead point cos th1* = -0.625 (t* = 0.675 s), the edge of the crank's reach, and cannot
/// go on: the first sample past t* is out of reach, a typed error naming it (not NaN, and
/// not a singular configuration: no configuration exists there at all).
#[test]
fn four_bar_driven_past_its_dead_point_reports_the_drive_out_of_reach() {
    let s = FourBar::locking();
    let drive = Drive::new(0, |t| [PI / 2.0 + t, 1.0, 0.0]);
    let err = inverse_dynamics(
        &s,
        vec![drive],
        &sample_times(0.0, 1.0, 100.0),
        &AssemblyOptions::default(),
    )
    .unwrap_err();
    println!("{err}");
    match err {
        Error::DriveOutOfReach {
            t,
            t_last: Some(t_last),
            residual,
            ..
        } => {
            // The samples are 0.01 s apart: the last one solved before t*, the failing one
            // after it.
            let t_star = (-0.625f64).acos() - PI / 2.0;
            assert!(t_last < t_star && t_star < t, "{t_last} < {t_star} < {t}");
            assert!((t - t_last - 0.01).abs() < 1e-12, "{t_last}, {t}");
            assert!(residual.is_finite() && residual > 1e-7, "{residual:e}");
        }
        other => panic!("expected DriveOutOfReach, got {other:?}"),
    }
    // A drive on a coordinate that does not exist is a typed error too.
    assert!(matches!(
        inverse_dynamics(
            &s,
            vec![Drive::new(5, |_| [0.0; 3])],
            &[0.0],
            &AssemblyOptions::default()
        ),
        Err(Error::UnknownDriver {
            coordinate: 5,
            n: 3
        })
    ));
}
