//! Declared joint limits: carried the same by both routes, and reported where a run passes
//! them, checked against the run's own samples and against closed forms.
//!
//! The pendulum (`stop_pendulum.mech`): a carriage of 0.5 kg sliding along x (coordinate
//! `s`) carries an arm turning about y (`th`), its mass m = 1 kg at l = 1 m below the joint,
//! I_yy = 0.01 kg m^2 about its centre. With the carriage held, T = 1/2 (m l^2 + I_yy) th'^2
//! and Pi = -m g l cos(th), so the arm needs tau = (m l^2 + I_yy) th'' + m g l sin(th).

use mechanism::output::{InverseTable, LimitWatch, inverse_excursions};
use mechanism::{
    AssemblyOptions, Compiled, IntegratorOptions, Interpreted, JointLimits, Kinematic,
    SimulationOptions, inverse_dynamics, parse_drive, sample_times, simulate,
};

const PENDULUM: &str = include_str!("stop_pendulum.mech");

mechanism::mechanism!(file = "tests/runtime/stop_pendulum.mech");

/// The limits as declared, by coordinate (the fixed mount has none): the same from the
/// interpreter and from the code `mechanism!` emits.
#[test]
fn both_routes_carry_the_declared_limits() {
    let interpreted = Interpreted::from_source(PENDULUM).unwrap();
    let expected = vec![
        JointLimits {
            coordinate: 0,
            linear: true,
            position: Some([-0.25, 0.75]),
            velocity: None,
            effort: Some(40.0),
        },
        JointLimits {
            coordinate: 1,
            linear: false,
            position: Some([-0.3, 0.5]),
            velocity: Some(1.0),
            effort: Some(5.0),
        },
    ];
    assert_eq!(interpreted.info().coordinates, ["s", "th"]);
    assert_eq!(interpreted.info().joint_limits, expected);
    let compiled = Compiled::new(StopPendulum::default());
    assert_eq!(compiled.info().joint_limits, expected);
}

/// Released at rest from th = 0.4 rad, the carriage free along x: the arm swings to about
/// -0.4 (momentum along x and energy are conserved, so the swing is symmetric), past its
/// stop at -0.3, while the carriage recoils; the centre of mass stays put, 1.5 x_s - sin(th)
/// = -sin(0.4), so x_s reaches -2 sin(0.4) / 1.5 = -0.52 m, past its stop at -0.25. The
/// report names the first sample beyond each stop and the sample furthest out, exactly as
/// the samples give them, and the arm's fastest rate, past its 1 rad/s.
#[test]
fn a_swing_past_a_stop_is_reported_at_the_samples_that_pass_it() {
    let system = Interpreted::from_source(PENDULUM).unwrap();
    let options = SimulationOptions {
        t_end: 2.0,
        output_rate: 100.0,
        integrator: IntegratorOptions::dop853(1e-11),
        initial: mechanism::InitialState::Consistent {
            q: vec![0.0, 0.4],
            qd: vec![0.0, 0.0],
        },
        ..Default::default()
    };
    let run = simulate(&system, &options).unwrap();
    let mut watch = LimitWatch::new(system.info());
    for s in run.samples() {
        watch.sample(s.t, s.q, s.qd, None);
    }
    let passed = watch.finish(system.info());
    let arm: Vec<_> = passed.iter().filter(|e| e.coordinate == "th").collect();
    assert_eq!(arm.len(), 2, "{passed:?}");
    let (position, rate) = (arm[0], arm[1]);
    assert_eq!((position.quantity, position.unit), ("position", "rad"));
    assert_eq!((position.lower, position.upper), (-0.3, 0.5));
    // The first sample beyond -0.3 and the least th of all samples.
    let first = run.samples().find(|s| s.q[1] < -0.3 - 1e-9).unwrap();
    assert_eq!(position.first_t, first.t);
    let lowest = run
        .samples()
        .min_by(|a, b| a.q[1].total_cmp(&b.q[1]))
        .unwrap();
    assert_eq!(
        (position.extreme, position.extreme_t),
        (lowest.q[1], lowest.t)
    );
    assert!(
        position.extreme < -0.35,
        "the swing reached {}",
        position.extreme
    );
    assert_eq!((rate.quantity, rate.unit), ("rate", "rad/s"));
    let fastest = run
        .samples()
        .max_by(|a, b| a.qd[1].abs().total_cmp(&b.qd[1].abs()))
        .unwrap();
    assert_eq!(rate.extreme, fastest.qd[1]);
    assert!(rate.extreme.abs() > 1.0);
    // The carriage, in metres.
    let carriage: Vec<_> = passed.iter().filter(|e| e.coordinate == "s").collect();
    assert_eq!(carriage.len(), 1, "{passed:?}");
    assert_eq!((carriage[0].quantity, carriage[0].unit), ("position", "m"));
    let leftmost = run
        .samples()
        .min_by(|a, b| a.q[0].total_cmp(&b.q[0]))
        .unwrap();
    assert_eq!(carriage[0].extreme, leftmost.q[0]);
    // At the turning point x_s' = 0, so the nearest sample (within 5 ms) misses it by
    // x_s'' dt^2 / 2 < 5.5 m/s^2 (the run's largest) x (5 ms)^2 / 2 = 6.9e-5 m.
    let recoil = -2.0 * 0.4_f64.sin() / 1.5;
    assert!(
        (carriage[0].extreme - recoil).abs() < 1e-4,
        "{}",
        carriage[0].extreme
    );
    // No effort: a forward run computes no driving force.
    assert!(passed.iter().all(|e| e.quantity != "effort"));
}

/// Driven along th = 0.2 sin(2 pi t) with the carriage held at 0, the arm needs
/// tau = (m l^2 + I_yy) th'' + m g l sin(th) (the closed form in the module docs), up to
/// 6.03 N m at th = +-0.2: past its 5 N m effort limit. The report's first time and extreme
/// are those of the closed form at the same samples, to 1e-9 of the peak (the inverse
/// dynamics solves a 4 x 4 system per sample: its round-off is about 1e-15 of the peak).
#[test]
fn an_inverse_run_reports_the_effort_past_its_limit() {
    let system = Interpreted::from_source(PENDULUM).unwrap();
    let drives = vec![
        parse_drive(&system, "th = 0.2*sin(2*pi*t)").unwrap(),
        parse_drive(&system, "s = 0").unwrap(),
    ];
    let times = sample_times(0.0, 1.0, 200.0);
    let result = inverse_dynamics(&system, drives, &times, &AssemblyOptions::default()).unwrap();
    let info = system.info().clone();
    let table = InverseTable {
        coordinates: info.coordinates.clone(),
        driven: vec!["th".into(), "s".into()],
        constraints: info.m(),
        rows: result.into_rows(),
    };
    let passed = inverse_excursions(&info, &table);
    let effort: Vec<_> = passed.iter().filter(|e| e.quantity == "effort").collect();
    assert_eq!(effort.len(), 1, "{passed:?}");
    let e = effort[0];
    assert_eq!((e.coordinate.as_str(), e.unit), ("th", "N m"));
    assert_eq!((e.lower, e.upper), (-5.0, 5.0));
    let w = 2.0 * std::f64::consts::PI;
    let tau = |t: f64| {
        let (th, thdd) = (0.2 * (w * t).sin(), -0.2 * w * w * (w * t).sin());
        1.01 * thdd + 9.81 * th.sin()
    };
    let first = times.iter().copied().find(|&t| tau(t).abs() > 5.0).unwrap();
    assert_eq!(e.first_t, first);
    // The peak: the largest |tau| of the samples, reached at the time the report gives
    // (th = +-0.2 at t = 0.25 and 0.75 s need -+6.03 N m, a tie that round-off breaks).
    let peak = times.iter().fold(0.0_f64, |m, &t| m.max(tau(t).abs()));
    assert!(
        (e.extreme.abs() - peak).abs() < 1e-9 * 8.0,
        "{} against {peak}",
        e.extreme
    );
    let at = tau(e.extreme_t);
    assert!(
        (e.extreme - at).abs() < 1e-9 * 8.0,
        "{} against {at}",
        e.extreme
    );
    // The rate 0.4 pi = 1.26 rad/s passes the 1 rad/s limit too; the positions stay inside.
    assert!(
        passed
            .iter()
            .any(|e| e.quantity == "rate" && e.coordinate == "th")
    );
    assert!(passed.iter().all(|e| e.quantity != "position"));
}
