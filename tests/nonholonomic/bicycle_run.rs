//! The nonlinear bicycle after a lean-rate kick of 0.5 rad/s: at 5 m/s (self-stable) the
//! lean decays as the linearisation's modes predict, energy is conserved (rolling does no
//! work) and the rolling rows hold; at 3 m/s (below the weave speed) it grows.

use mechanism::nalgebra::{DMatrix, DVector};
use mechanism::{InitialState, SteadyOptions, System, Trajectory, linearize_steady, simulate};

use crate::common::{assemble_with, drifts, independent_with, load, tight};

const REAR_RADIUS: f64 = 0.3;
/// Index of the lean angle phi in q.
const LEAN: usize = 4;

/// The run from upright and straight at speed v with the lean rate `kick` (rad/s).
fn kicked(system: &dyn System, v: f64, kick: f64, t_end: f64) -> Trajectory {
    let rates = [("thR", v / REAR_RADIUS), ("phi", kick)];
    let initial = InitialState::Independent(independent_with(system, &rates));
    simulate(system, &tight(t_end, initial)).unwrap()
}

/// The relative RMS residual of the least-squares fit of the lean over t in [t0, t_end]
/// by e^(s t) cos(w t), e^(s t) sin(w t) (the weave s +- i w) and e^(c t) (the capsize c).
fn fit_residual(tr: &Trajectory, t0: f64, s: f64, w: f64, c: f64) -> f64 {
    let samples: Vec<(f64, f64)> = tr
        .samples()
        .filter(|x| x.t >= t0)
        .map(|x| (x.t, x.q[LEAN]))
        .collect();
    let basis = DMatrix::from_fn(samples.len(), 3, |i, j| {
        let t = samples[i].0 - t0;
        match j {
            0 => (s * t).exp() * (w * t).cos(),
            1 => (s * t).exp() * (w * t).sin(),
            _ => (c * t).exp(),
        }
    });
    let lean = DVector::from_iterator(samples.len(), samples.iter().map(|x| x.1));
    let coefficients = (basis.transpose() * &basis)
        .lu()
        .solve(&(basis.transpose() * &lean))
        .unwrap();
    let residual = &lean - &basis * coefficients;
    (residual.norm() / lean.norm()).abs()
}

/// The weave pair's real and imaginary parts and the capsize eigenvalue at speed v.
fn modes(system: &dyn System, v: f64) -> (f64, f64, f64) {
    let s = assemble_with(system, &[("thR", v / REAR_RADIUS)]);
    let lin = linearize_steady(system, 0.0, &s.q, &s.qd, &SteadyOptions::default()).unwrap();
    let weave = lin.reduced.iter().find(|e| e.im > 0.0).copied().unwrap();
    let capsize = (lin.reduced.iter())
        .filter(|e| e.im == 0.0)
        .map(|e| e.re)
        .fold(f64::NEG_INFINITY, f64::max);
    (weave.re, weave.im, capsize)
}

#[test]
fn kick_at_5_m_s_decays_at_the_weave_rate() {
    let system = load("whipple_bicycle", &[]);
    let v = 5.0;
    // A small kick (0.005 rad/s): the lean is the linear modes at 5 m/s to 1e-5 of itself,
    // and a weave decay rate 0.05 1/s off leaves a residual a thousand times larger.
    let (s, w, c) = modes(&system, v);
    let small = kicked(&system, v, 0.005, 10.0);
    let (fitted, off) = (
        fit_residual(&small, 2.0, s, w, c),
        fit_residual(&small, 2.0, s + 0.05, w, c),
    );
    println!("bicycle 5 m/s, kick 0.005 rad/s: lean fit {fitted:e} (weave rate + 0.05: {off:e})");
    assert!(
        fitted < 1e-4,
        "the lean is not the linear modes: residual {fitted:e}"
    );
    assert!(
        off > 100.0 * fitted,
        "a wrong decay rate fits as well: {off:e} vs {fitted:e}"
    );
    // The kick of 0.5 rad/s: energy conserved, rolling held. Its energy (a few J) moves
    // into the forward motion, so the lean decays with the modes of the speed the bicycle
    // settles at, v_end = rR thR' at 10 s.
    let tr = kicked(&system, v, 0.5, 10.0);
    let (energy, velocity) = drifts(&tr);
    let v_end = REAR_RADIUS * tr.sample(tr.len() - 1).qd[7];
    let (s, w, c) = modes(&system, v_end);
    let (fitted, off) = (
        fit_residual(&tr, 3.0, s, w, c),
        fit_residual(&tr, 3.0, s + 0.05, w, c),
    );
    println!(
        "bicycle 5 m/s, kick 0.5 rad/s: energy drift {energy:e}, max |A q' + a| {velocity:e}, v_end {v_end:.6} m/s, weave {s:.6} +- {w:.6} i, lean fit {fitted:e} (weave rate + 0.05: {off:e})"
    );
    assert!(energy < 1e-8, "relative energy drift {energy:e}");
    assert!(
        velocity < 1e-12,
        "velocity constraint residual {velocity:e}"
    );
    assert!(
        fitted < 2e-3,
        "the lean is not the linear modes: residual {fitted:e}"
    );
    assert!(
        off > 5.0 * fitted,
        "a wrong decay rate fits as well: {off:e} vs {fitted:e}"
    );
}

#[test]
fn kick_at_3_m_s_grows() {
    let system = load("whipple_bicycle", &[]);
    let tr = kicked(&system, 3.0, 0.5, 2.0);
    let peak = |a: f64, b: f64| {
        tr.samples()
            .filter(|x| x.t >= a && x.t <= b)
            .map(|x| x.q[LEAN].abs())
            .fold(0.0, f64::max)
    };
    let (early, late) = (peak(0.0, 0.5), peak(1.5, 2.0));
    println!(
        "bicycle 3 m/s kicked: |lean| max {early:.4} rad in [0, 0.5] s, {late:.4} rad in [1.5, 2] s"
    );
    // The weave grows at 1.7 1/s at 3 m/s (Table 2): e^(1.7 * 1.5) = 12.8.
    assert!(late > 3.0 * early, "no growth: {early} then {late}");
}
