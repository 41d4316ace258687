//! Inverse dynamics with a velocity row: the Chaplygin sleigh held sideways by a spring
//! (potential k y^2 / 2), driven in heading and forward position. The knife edge fixes y'
//! but not y: y is carried along the motion between samples, and the forces that depend on
//! it (the spring's, hence the knife edge's reaction and both driving forces) follow it.
//!
//! Closed forms with theta = 0.5 sin t, x = 0.3 t (x'' = 0): the row
//! -sin(th) x' + cos(th) y' - a th' = 0 gives y' = (x' sin th + a th') / cos th, and the
//! equations M q'' + g + A^T lambda = tau (A = [-sin th, cos th, -a], M = diag(m, m, I),
//! g = (0, k y, 0), no force on y) give
//! lambda = -(m y'' + k y) / cos th, tau_x = m x'' - sin(th) lambda, tau_th = I th'' - a lambda.

use mechanism::{AssemblyOptions, Drive, Interpreted, inverse_dynamics, sample_times};

const M: f64 = 1.0;
const I: f64 = 0.1;
const A: f64 = 0.2;
const K: f64 = 10.0;

fn sleigh_on_a_spring() -> Interpreted {
    Interpreted::from_source(
        "pub struct SleighOnASpring;
         parameters { m = 1.0; I = 0.1; a = 0.2; k = 10.0; }
         coordinates { x = 0.0; y = 0.0; theta = 0.0; }
         independent { x = 0.0; theta = 0.0; der(x) = 0.3; der(theta) = 0.5; }
         kinetic = m/2*(der(x)^2 + der(y)^2) + I/2*der(theta)^2;
         potential = 1/2*k*y^2;
         velocity_constraints { -sin(theta)*der(x) + cos(theta)*der(y) - a*der(theta); }",
    )
    .expect("builds")
}

/// theta, theta', theta'' at t.
fn heading(t: f64) -> [f64; 3] {
    [0.5 * t.sin(), 0.5 * t.cos(), -0.5 * t.sin()]
}

/// y' and y'' at t from the row (x' = 0.3, x'' = 0).
fn lateral_rates(t: f64) -> (f64, f64) {
    let [th, thd, thdd] = heading(t);
    let (n, d) = (0.3 * th.sin() + A * thd, th.cos());
    let (nd, dd) = (0.3 * th.cos() * thd + A * thdd, -th.sin() * thd);
    (n / d, (nd * d - n * dd) / (d * d))
}

/// y(t) = integral of y' from 0 (y(0) = 0), by composite Simpson on 2,000 panels: error
/// below 1e-14 m for this smooth integrand over 2 s.
fn lateral_position(t: f64) -> f64 {
    let panels = 2000;
    let h = t / panels as f64;
    let f = |s: f64| lateral_rates(s).0;
    let inner: f64 = (1..panels)
        .map(|i| f(i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
        .sum();
    h / 3.0 * (f(0.0) + inner + f(t))
}

#[test]
fn sleigh_on_a_spring_is_carried_sideways_and_its_forces_follow() {
    let system = sleigh_on_a_spring();
    let info = mechanism::Kinematic::info(&system).clone();
    let (x, y, th) = (0, 1, 2);
    assert_eq!(info.coordinates, ["x", "y", "theta"]);
    for rate in [10.0, 1000.0] {
        let drives = vec![
            Drive::new(th, heading),
            Drive::new(x, |t| [0.3 * t, 0.3, 0.0]),
        ];
        let times = sample_times(0.0, 2.0, rate);
        let r = inverse_dynamics(&system, drives, &times, &AssemblyOptions::default())
            .unwrap_or_else(|e| panic!("{e}"));
        let (mut dy, mut dforce) = (0.0_f64, 0.0_f64);
        for s in &r.samples {
            let [angle, _, thdd] = heading(s.t);
            let (_, ydd) = lateral_rates(s.t);
            let yy = lateral_position(s.t);
            let lambda = -(M * ydd + K * yy) / angle.cos();
            let tau_th = I * thdd - A * lambda;
            let tau_x = -angle.sin() * lambda;
            dy = dy.max((s.q[y] - yy).abs());
            // Drive order: theta, then x.
            for (got, want) in [
                (s.driving[0], tau_th),
                (s.driving[1], tau_x),
                (s.lambda[0], lambda),
            ] {
                dforce = dforce.max((got - want).abs());
            }
        }
        let last = r.samples.last().unwrap();
        println!(
            "{rate} samples/s: y(2) = {:.12} m (closed form {:.12}), max |dy| = {dy:e} m, \
             max force error = {dforce:e}",
            last.q[y],
            lateral_position(2.0)
        );
        // y(2) = 0.321 m: carried, not left at its start.
        assert!(last.q[y] > 0.3, "{}", last.q[y]);
        // DOP853 at a local error of 1e-12 (the position solve's tolerance): 3e-15 m
        // measured, held to that tolerance. The forces (up to 3.4 N)
        // then within k dy / cos(th) plus round-off.
        assert!(dy < 1e-12, "{dy}");
        assert!(dforce < 1e-10, "{dforce}");
    }
}
