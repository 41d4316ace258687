//! Energy balance: T + Pi conserved with tau = 0; T + Pi - W constant with tau != 0.

use crate::common::{CrankSlider, FourBar, drift};
use mechanism::{IntegratorOptions, Method, SimulationOptions, simulate};

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
