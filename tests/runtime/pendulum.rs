//! Cartesian pendulum against closed forms: periods (small amplitude and complete elliptic
//! integral) located with events, and the multiplier against the rod tension.

use std::f64::consts::PI;

use crate::common::Pendulum;
use mechanism::{
    Event, EventAction, InitialState, IntegratorOptions, Method, SimulationOptions,
    simulate_with_events,
};

const L: f64 = 1.0;
const G: f64 = 9.81;

/// K(k) = pi / (2 AGM(1, sqrt(1 - k^2))) (Abramowitz & Stegun 17.6).
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    while (a - b).abs() > 1e-16 * a {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    PI / (2.0 * a)
}

/// Period from the zero crossings of x (two per period, half a period apart by symmetry),
/// released from rest at theta0.
fn period(theta0: f64, t_end: f64) -> f64 {
    let s = Pendulum::new(theta0);
    let o = SimulationOptions {
        t_end,
        initial: InitialState::Consistent {
            q: vec![L * theta0.sin(), -L * theta0.cos()],
            qd: vec![0.0, 0.0],
        },
        integrator: IntegratorOptions {
            method: Method::Dop853,
            rtol: 1e-12,
            atol: 1e-14,
            ..Default::default()
        },
        events: vec![Event::new("x = 0", EventAction::Record, |_, q, _| q[0])],
        ..Default::default()
    };
    let sim = simulate_with_events(&s, &o).unwrap();
    let t: Vec<f64> = sim.events.iter().map(|e| e.t).collect();
    assert!(t.len() >= 2, "crossings {t:?}");
    2.0 * (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64
}

#[test]
fn small_oscillation_period() {
    let theta0: f64 = 0.01;
    let p = period(theta0, 7.0);
    let t0 = 2.0 * PI * (L / G).sqrt();
    let exact = 4.0 * (L / G).sqrt() * elliptic_k((theta0 / 2.0).sin());
    println!("small amplitude: period {p:.12} s, 2 pi sqrt(l/g) = {t0:.12}, elliptic {exact:.12}");
    // The finite amplitude lengthens the period by theta0^2/16 = 6.25e-6 relative.
    assert!((p / t0 - 1.0).abs() < 1e-5);
    assert!((p / exact - 1.0).abs() < 1e-9);
}

#[test]
fn large_amplitude_period_matches_elliptic_integral() {
    let theta0: f64 = 2.0;
    let p = period(theta0, 10.0);
    let exact = 4.0 * (L / G).sqrt() * elliptic_k((theta0 / 2.0).sin());
    println!(
        "theta0 = 2 rad: period {p:.12} s, 4 sqrt(l/g) K(sin(theta0/2)) = {exact:.12}, rel {:e}",
        p / exact - 1.0
    );
    assert!((p / exact - 1.0).abs() < 1e-9);
    // Far from the small-angle value: the test is sensitive to the amplitude.
    assert!(p / (2.0 * PI * (L / G).sqrt()) > 1.3);
}

/// Multiplier vs tension. With Phi = x^2 + y^2 - l^2, the constraint force on the mass is
/// -Phi_q^T lambda = -2 lambda (x, y); a rod tension T_rod pulls toward the pivot,
/// -T_rod (x, y)/l. Hence T_rod = 2 l lambda (lambda > 0 is tension). The radial equation
/// gives T_rod = m v^2/l + m g cos(theta) with cos(theta) = -y/l.
#[test]
fn multiplier_is_the_rod_tension() {
    let theta0: f64 = 2.0;
    let s = Pendulum::new(theta0);
    let o = SimulationOptions {
        t_end: 3.0,
        initial: InitialState::Consistent {
            q: vec![L * theta0.sin(), -L * theta0.cos()],
            qd: vec![0.0, 0.0],
        },
        integrator: IntegratorOptions {
            method: Method::Dopri5,
            rtol: 1e-10,
            atol: 1e-12,
            ..Default::default()
        },
        ..Default::default()
    };
    let tr = simulate_with_events(&s, &o).unwrap().trajectory;
    let m = 1.0;
    let mut worst = 0.0f64;
    for smp in tr.samples() {
        let v2 = smp.qd[0].powi(2) + smp.qd[1].powi(2);
        let tension = m * v2 / L - m * G * smp.q[1] / L;
        worst = worst.max((2.0 * L * smp.lambda[0] - tension).abs());
    }
    println!(
        "max |2 l lambda - T_rod| = {worst:e} N over {} samples",
        tr.len()
    );
    // Tension reaches m g (3 - 2 cos theta0) ~ 37 N at the bottom; both sides are computed
    // from the same projected state, so they agree to round-off.
    assert!(worst < 1e-10);
    let bottom = tr.samples().map(|s| s.lambda[0]).fold(0.0, f64::max) * 2.0 * L;
    assert!((bottom / (m * G * (3.0 - 2.0 * theta0.cos())) - 1.0).abs() < 1e-3);
}
