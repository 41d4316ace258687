//! Loop closure over 10 s: projection keeps |Phi| < 1e-12; Baumgarte and no stabilisation
//! are measured and printed for the book's solvers chapter (`docs/src/solvers.md`).

use crate::common::{CrankSlider, FourBar};
use mechanism::{IntegratorOptions, Method, SimulationOptions, Stabilization, System, simulate};

fn max_errors(s: &dyn System, stab: Stabilization, rtol: f64) -> (f64, f64) {
    let o = SimulationOptions {
        t_end: 10.0,
        stabilization: stab,
        integrator: IntegratorOptions {
            method: Method::Dopri5,
            rtol,
            atol: rtol * 1e-2,
            ..Default::default()
        },
        ..Default::default()
    };
    let tr = simulate(s, &o).unwrap();
    let p = tr.samples().map(|x| x.constraint_error).fold(0.0, f64::max);
    let v = tr
        .samples()
        .map(|x| x.velocity_constraint_error)
        .fold(0.0, f64::max);
    (p, v)
}

#[test]
fn projection_closes_the_loops_to_round_off() {
    for (name, s) in [
        ("four-bar", &FourBar::crank_rocker() as &dyn System),
        ("seed", &CrankSlider::seed()),
    ] {
        let (p, v) = max_errors(s, Stabilization::Projection, 1e-8);
        println!("{name} projection (DOPRI5 rtol 1e-8): max |Phi| {p:e}, max |Phi_q q'| {v:e}");
        assert!(p < 1e-12, "{name}: |Phi| = {p:e}");
        assert!(v < 1e-12, "{name}: |Phi_q q'| = {v:e}");
    }
}

#[test]
fn baumgarte_and_none_drift_more() {
    let s = FourBar::crank_rocker();
    let (pn, vn) = max_errors(&s, Stabilization::None, 1e-8);
    let (pb, vb) = max_errors(
        &s,
        Stabilization::Baumgarte {
            alpha: 10.0,
            beta: 10.0,
        },
        1e-8,
    );
    let (pp, _) = max_errors(&s, Stabilization::Projection, 1e-8);
    println!(
        "four-bar DOPRI5 rtol 1e-8 over 10 s: none |Phi| {pn:e} |Phi'| {vn:e}; Baumgarte(10,10) |Phi| {pb:e} |Phi'| {vb:e}; projection |Phi| {pp:e}"
    );
    // Without stabilisation the drift is set by the integration error, far above round-off.
    assert!(pn > 1e3 * pp.max(1e-16));
    // Baumgarte bounds the drift below what no stabilisation gives.
    assert!(pb < pn);
}
