//! Rows that are redundant only on the constraint manifold: a pendulum in (th, x, y) tied
//! to th by x = L sin th and y = -L cos th, with x^2 + y^2 = L^2 written as well. Off the
//! manifold (at guesses, or where a drive has moved th and x, y not yet) the third row
//! looks independent and the mechanism seems to have no freedom; the rank that counts is
//! the one where the constraints hold. And Bricard's linkage (A04), whose redundancy is of
//! the same kind, driven through the command's inverse dynamics.

use mechanism::builtin::builtin;
use mechanism::{
    AssemblyOptions, Drive, Evaluation, Independent, Interpreted, assemble_from, inverse_dynamics,
    sample_times,
};

const M: f64 = 1.5;
const L: f64 = 0.8;
const G: f64 = 9.81;

fn pendulum() -> Interpreted {
    Interpreted::from_source(
        "pub struct RedundantPendulum;
         parameters { m = 1.5; L = 0.8; g = 9.81; }
         coordinates { th = 0.0; x = 0.0; y = -0.8; }
         independent { th = 0.0; der(th) = 0.0; }
         kinetic = 1/2*m*(der(x)^2 + der(y)^2);
         potential = m*g*y;
         constraints { x - L*sin(th); y + L*cos(th); x^2 + y^2 - L^2; }",
    )
    .expect("builds")
}

/// Assembled from th = 0.3 with the guesses at th = 0 (0.24 m off): one degree of freedom,
/// the bob at (L sin 0.3, -L cos 0.3).
#[test]
fn assembly_from_guesses_off_the_manifold_counts_the_freedom_where_it_holds() {
    let system = pendulum();
    let independent = [Independent {
        coordinate: 0,
        position: 0.3,
        velocity: 1.0,
    }];
    let s = assemble_from(
        &system,
        0.0,
        &independent,
        &[0.0, 0.0, -L],
        &AssemblyOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    // Newton to the default tolerance, then round-off: 1e-12 m.
    assert!((s.q[1] - L * 0.3_f64.sin()).abs() < 1e-12, "{:?}", s.q);
    assert!((s.q[2] + L * 0.3_f64.cos()).abs() < 1e-12, "{:?}", s.q);
    assert!((s.qd[1] - L * 0.3_f64.cos()).abs() < 1e-12, "{:?}", s.qd);
}

/// Driven along th = 0.7 sin(3t), at 100 and at 1,000 samples per second (each sample tests
/// the drive where th has moved and x, y not yet): the driving torque is the closed form
/// m L^2 th'' + m g L sin th of the pendulum, to round-off.
#[test]
fn driven_pendulum_torque_matches_the_closed_form() {
    let system = pendulum();
    for rate in [100.0, 1000.0] {
        let drive = Drive::new(0, |t| {
            let (s, c) = (3.0 * t).sin_cos();
            [0.7 * s, 2.1 * c, -6.3 * s]
        });
        let times = sample_times(0.0, 2.0, rate);
        let r = inverse_dynamics(&system, vec![drive], &times, &AssemblyOptions::default())
            .unwrap_or_else(|e| panic!("{rate} samples/s: {e}"));
        let mut worst = 0.0_f64;
        for s in &r.samples {
            let th = 0.7 * (3.0 * s.t).sin();
            let thdd = -6.3 * (3.0 * s.t).sin();
            let tau = M * L * L * thdd + M * G * L * th.sin();
            worst = worst.max((s.driving[0] - tau).abs());
        }
        println!(
            "{rate} samples/s: {} samples, worst |tau - closed form| = {worst:e}",
            times.len()
        );
        // |tau| <= 1.54 N m; round-off of the KKT solve: 1e-12 N m.
        assert!(worst < 1e-12, "{worst}");
    }
}

/// Bricard's linkage (30 rows of rank 29) driven at ay1 = 0.3 t for 2 s, 200 samples per
/// second: the work of the driving force, integrated by the trapezoidal rule, equals the
/// change of T + Pi (no other force does work).
#[test]
fn driven_bricard_linkage_balances_work_and_energy() {
    let system = builtin("bricard").unwrap();
    let info = system.info();
    let k = info.coordinate_index("ay1").unwrap();
    let drive = Drive::new(k, |t| [0.3 * t, 0.3, 0.0]);
    let times = sample_times(0.0, 2.0, 200.0);
    let r = inverse_dynamics(
        system.as_ref(),
        vec![drive],
        &times,
        &AssemblyOptions::default(),
    )
    .unwrap_or_else(|e| panic!("{e}"));
    let mut eval = Evaluation::zeros(info.n(), info.m());
    let mut energy = |s: &mechanism::InverseSample| {
        system.evaluate(s.t, &s.q, &s.qd, &mut eval);
        eval.kinetic + eval.potential
    };
    let e0 = energy(&r.samples[0]);
    let (mut work, mut worst, mut scale) = (0.0, 0.0_f64, 0.0_f64);
    for pair in r.samples.windows(2) {
        let dt = pair[1].t - pair[0].t;
        work += 0.5 * dt * 0.3 * (pair[0].driving[0] + pair[1].driving[0]);
        let change = energy(&pair[1]) - e0;
        worst = worst.max((work - change).abs());
        scale = scale.max(change.abs());
    }
    println!("max |W - d(T + Pi)| = {worst:e} J of {scale:e} J");
    // The trapezoidal rule's error, t_end dt^2/12 max |d2(tau q')/dt2|, is what is left
    // (1.5e-6 of the change at dt = 5 ms): held to 1e-5.
    assert!(scale > 0.1, "the linkage moved: {scale}");
    assert!(worst < 1e-5 * scale, "{worst} of {scale}");
}
