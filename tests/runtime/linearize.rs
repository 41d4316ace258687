//! Linearisation and parameter sweeps: the hanging Cartesian pendulum's tangent dynamics in
//! x have omega = sqrt(g/l), swept over l in parallel; the crank-rocker's linearised
//! frequency about its equilibrium matches the period of a small free oscillation.

use crate::common::{FourBar, Pendulum};
use mechanism::{
    AssemblyOptions, Error, Event, EventAction, Independent, InitialState, IntegratorOptions,
    Method, SimulationOptions, assemble_from, linearize, simulate_with_events, sweep,
};

#[test]
fn pendulum_frequency_over_a_parameter_sweep() {
    let s = Pendulum::new(0.0);
    let sets: Vec<_> = [0.25, 0.5, 1.0, 2.0, 4.0]
        .iter()
        .map(|&l| vec![("l".to_string(), l)])
        .collect();
    let results = sweep(&s, &sets, |p| {
        let l = p.p[1];
        let lin = linearize(
            p,
            0.0,
            &[0.0, -l],
            &[0.0, 0.0],
            &[0],
            &AssemblyOptions::default(),
        )?;
        Ok((l, lin))
    });
    for r in results {
        let (l, lin) = r.unwrap();
        let w = (9.81 / l).sqrt();
        println!(
            "l = {l}: omega = {:.10} rad/s (sqrt(g/l) = {w:.10}), f = {:.6} Hz, M_r = {:.6}, K_r = {:.6}",
            lin.frequencies_rad_s[0],
            lin.frequencies_hz[0],
            lin.mass[(0, 0)],
            lin.stiffness[(0, 0)]
        );
        assert_eq!(lin.frequencies_rad_s.len(), 1);
        assert!((lin.frequencies_rad_s[0] / w - 1.0).abs() < 1e-6);
        // x = l sin(theta): M_r = m, K_r = m g / l.
        assert!(
            (lin.mass[(0, 0)] - 1.0).abs() < 1e-12
                && (lin.stiffness[(0, 0)] / (9.81 / l) - 1.0).abs() < 1e-6
        );
    }
    let bad = sweep(&s, &[vec![("length".to_string(), 1.0)]], |_| Ok(()));
    assert!(matches!(bad[0], Err(Error::UnknownParameter { .. })));
}

/// The crank-rocker under gravity alone has a stable equilibrium; found by Newton on the
/// linearised crank acceleration, its small-oscillation period 2 pi / omega must match a
/// nonlinear simulation released 1e-4 rad from it. The potential is not symmetric about the
/// equilibrium, so the half-periods between crossings differ at first order in the
/// amplitude (measured 6e-5 relative at 1e-3 rad, 6e-6 at 1e-4 rad).
#[test]
fn four_bar_linearised_frequency_matches_simulation() {
    let s = FourBar::crank_rocker();
    let opts = AssemblyOptions::default();
    let state_at = |th1: f64| {
        assemble_from(
            &s,
            0.0,
            &[Independent {
                coordinate: 0,
                position: th1,
                velocity: 0.0,
            }],
            &s.info.initial_guess,
            &opts,
        )
        .unwrap()
    };
    // Newton on u''(th1) = 0 (slope from the linearisation's state matrix) from a few
    // starting angles; keep the first equilibrium that is stable (da/du < 0).
    let mut found = None;
    for start in [-1.0f64, -2.0, 0.0, 1.0, 2.0, 3.0] {
        let mut th = start;
        for _ in 0..40 {
            let st = state_at(th);
            let lin = linearize(&s, 0.0, &st.q, &st.qd, &[0], &opts).unwrap();
            let mut d = mechanism::Dynamics::new(&s.info);
            d.solve(&s, 0.0, &st.q, &st.qd).unwrap();
            let step = -d.accelerations()[0] / lin.a[(1, 0)];
            th += step.clamp(-0.5, 0.5);
            if step.abs() < 1e-12 {
                if lin.a[(1, 0)] < 0.0 {
                    found = Some(th);
                }
                break;
            }
        }
        if found.is_some() {
            break;
        }
    }
    let th = found.expect("a stable equilibrium of the crank-rocker under gravity");
    let eq = state_at(th);
    let lin = linearize(&s, 0.0, &eq.q, &eq.qd, &[0], &opts).unwrap();
    assert_eq!(
        lin.frequencies_rad_s.len(),
        1,
        "stable equilibrium expected, eigenvalues {:?}",
        lin.eigenvalues
    );
    let period_lin = 2.0 * std::f64::consts::PI / lin.frequencies_rad_s[0];
    let start = state_at(th + 1e-4);
    let o = SimulationOptions {
        t_end: 3.0 * period_lin,
        initial: InitialState::Consistent {
            q: start.q.clone(),
            qd: start.qd.clone(),
        },
        integrator: IntegratorOptions {
            method: Method::Dop853,
            rtol: 1e-12,
            atol: 1e-14,
            ..Default::default()
        },
        events: vec![Event::new(
            "th1 = eq",
            EventAction::Record,
            move |_, q, _| q[0] - th,
        )],
        ..Default::default()
    };
    let ev = simulate_with_events(&s, &o).unwrap().events;
    let period_sim = 2.0 * (ev[ev.len() - 1].t - ev[0].t) / (ev.len() - 1) as f64;
    println!(
        "four-bar equilibrium th1 = {th:.10} rad: linearised period {period_lin:.9} s ({:.6} Hz), simulated {period_sim:.9} s",
        lin.frequencies_hz[0]
    );
    assert!((period_sim / period_lin - 1.0).abs() < 2e-5);
}
