//! Energy balance: T + Pi conserved with tau = 0; T + Pi - W constant with tau != 0, and
//! with a driving row that moves with t (W then holds its work, the integral of
//! lambda . Phi_t).

use crate::common::{CrankSlider, FourBar, drift, driven_slider_crank_source};
use mechanism::{IntegratorOptions, Interpreted, Method, SimulationOptions, simulate};

/// Four-bar, tau = 0, DOP853 at rtol = 1e-12 with projection: |T + Pi - E0| relative to
/// max(|T| + |Pi|) below 1e-9 over 10 s.
#[test]
fn four_bar_conserves_energy() {
    let s = FourBar::crank_rocker();
    let o = SimulationOptions {
        t_end: 10.0,
        integrator: IntegratorOptions {
            method: Method::Dop853,
            rtol: 1e-12,
            atol: 1e-12,
            ..Default::default()
        },
        ..Default::default()
    };
    let tr = simulate(&s, &o).unwrap();
    let (abs, rel) = drift(&tr);
    let max_phi = tr.samples().map(|s| s.constraint_error).fold(0.0, f64::max);
    println!(
        "four-bar DOP853 rtol 1e-12: energy drift {abs:e} J (relative {rel:e}), {} steps, max |Phi| {max_phi:e}",
        tr.stats.steps
    );
    assert!(rel < 1e-9, "relative energy drift {rel:e}");
    assert_eq!(tr.len(), 1001);
}

/// Seed crank-slider with tau = 0.005 sin(2 pi t): T + Pi - W constant (W integrated as an
/// extra state), DOPRI5 at rtol = 1e-10.
#[test]
fn seed_energy_balance_with_work() {
    let s = CrankSlider::seed();
    let o = SimulationOptions {
        t_end: 10.0,
        integrator: IntegratorOptions {
            method: Method::Dopri5,
            rtol: 1e-10,
            atol: 1e-12,
            ..Default::default()
        },
        ..Default::default()
    };
    let tr = simulate(&s, &o).unwrap();
    let (abs, rel) = drift(&tr);
    let w_max = tr.samples().map(|s| s.work.abs()).fold(0.0, f64::max);
    println!(
        "seed DOPRI5 rtol 1e-10: T+Pi-W drift {abs:e} J (relative {rel:e}), |W|max {w_max:e} J, {} steps, {} rejected, {} rhs",
        tr.stats.steps, tr.stats.rejected_steps, tr.stats.rhs_evaluations
    );
    assert!(
        w_max > 1e-4,
        "the torque must do measurable work for this test to mean anything"
    );
    assert!(rel < 1e-8, "relative drift {rel:e}");
}

/// The library's slider-crank with its crank driven by the row th - pi/4 - 10 t (no degree of
/// freedom left, no declared force): the row's force does all the work, |W| up to 0.5 J.
/// W integrates lambda . Phi_t, so T + Pi - W stays constant: to 1e-9 J with DOP853 at
/// 1e-12 (measured 2e-12 J), and to 1e-4 J with HHT at h = 1e-4 s, whose own energy error
/// is first order in h (2.4e-4 J at h = 1e-3 s, 2.5e-5 J at 1e-4 s, measured). Without the
/// row's work the balance would be off by all of it (0.525 J, measured before W held it).
#[test]
fn a_driving_row_does_the_work_of_the_drive() {
    let s = Interpreted::from_source(&driven_slider_crank_source())
        .expect("the driven slider-crank derives");
    for (method, tolerance) in [
        (Method::Dop853, 1e-9),
        (
            Method::Hht {
                h: 1e-4,
                alpha: -0.05,
            },
            1e-4,
        ),
    ] {
        let o = SimulationOptions {
            t_end: 1.0,
            integrator: IntegratorOptions {
                method,
                rtol: 1e-12,
                atol: 1e-12,
                ..Default::default()
            },
            ..Default::default()
        };
        let tr = simulate(&s, &o).expect("the driven run");
        let (abs, _) = drift(&tr);
        let work = tr.samples().map(|s| s.work.abs()).fold(0.0, f64::max);
        println!("{method:?}: max |W| = {work} J, max |T + Pi - W - E0| = {abs:e} J");
        assert!(work > 0.4, "the row must do measurable work: {work}");
        assert!(abs < tolerance, "{method:?}: {abs:e}");
    }
}
