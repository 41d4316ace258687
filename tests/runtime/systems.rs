//! Guards the hand-derived test systems of `tests/common`: each derived quantity must match
//! finite differences of the energies and constraints it comes from, so that the other
//! runtime tests rest on correct equations.

use crate::common::{CrankSlider, FourBar, Pendulum};
use mechanism::nalgebra::DMatrix;
use mechanism::{Evaluation, System};

/// Checks M = d2T/dq'2, C q' = (dM/dt) q' - dT/dq, g = dPi/dq, Phi_q = dPhi/dq and
/// gamma = -(d/dt Phi_q) q' at (q, q') by central differences (step 1e-5: truncation error
/// about 1e-10 relative, round-off about 1e-11 for these magnitudes).
fn check(system: &dyn System, q: &[f64], qd: &[f64]) {
    let (n, m) = (system.info().n(), system.info().m());
    let mut e = Evaluation::zeros(n, m);
    system.evaluate(0.3, q, qd, &mut e);
    let d = 1e-5;
    let eval_at = |q: &[f64], qd: &[f64]| {
        let mut e = Evaluation::zeros(n, m);
        system.evaluate(0.3, q, qd, &mut e);
        e
    };
    let shift = |x: &[f64], i: usize, s: f64| {
        let mut y = x.to_vec();
        y[i] += s;
        y
    };
    let tol = 1e-7;
    for i in 0..n {
        // dT/dq'_i = (M q')_i
        let dt = (eval_at(q, &shift(qd, i, d)).kinetic - eval_at(q, &shift(qd, i, -d)).kinetic)
            / (2.0 * d);
        let mq: f64 = (0..n).map(|j| e.mass[(i, j)] * qd[j]).sum();
        assert!(
            (dt - mq).abs() < tol,
            "{}: (M q')_{i} {mq} vs dT/dq' {dt}",
            system.info().name
        );
        // g_i = dPi/dq_i
        let dp = (eval_at(&shift(q, i, d), qd).potential - eval_at(&shift(q, i, -d), qd).potential)
            / (2.0 * d);
        assert!(
            (dp - e.gravity[i]).abs() < tol,
            "{}: g_{i}",
            system.info().name
        );
        // Phi_q column i
        let (ep, em) = (eval_at(&shift(q, i, d), qd), eval_at(&shift(q, i, -d), qd));
        for r in 0..m {
            let fd = (ep.phi[r] - em.phi[r]) / (2.0 * d);
            assert!(
                (fd - e.phi_q[(r, i)]).abs() < tol,
                "{}: Phi_q[{r},{i}]",
                system.info().name
            );
        }
    }
    // C q' = (dM/dt) q' - dT/dq with dM/dt = sum_k dM/dq_k q'_k.
    let mut mdot = DMatrix::zeros(n, n);
    for k in 0..n {
        let (ep, em) = (eval_at(&shift(q, k, d), qd), eval_at(&shift(q, k, -d), qd));
        mdot += (ep.mass - em.mass) / (2.0 * d) * qd[k];
    }
    for i in 0..n {
        let dtq = (eval_at(&shift(q, i, d), qd).kinetic - eval_at(&shift(q, i, -d), qd).kinetic)
            / (2.0 * d);
        let cq: f64 = (0..n).map(|j| mdot[(i, j)] * qd[j]).sum::<f64>() - dtq;
        assert!(
            (cq - e.coriolis[i]).abs() < tol,
            "{}: (C q')_{i} {} vs {cq}",
            system.info().name,
            e.coriolis[i]
        );
    }
    // gamma = -(d/dt Phi_q) q': Phi_q along q + s q', differentiated in s.
    let qp: Vec<f64> = q.iter().zip(qd).map(|(a, b)| a + d * b).collect();
    let qm: Vec<f64> = q.iter().zip(qd).map(|(a, b)| a - d * b).collect();
    let (ep, em) = (eval_at(&qp, qd), eval_at(&qm, qd));
    for r in 0..m {
        let g: f64 = -(0..n)
            .map(|j| (ep.phi_q[(r, j)] - em.phi_q[(r, j)]) / (2.0 * d) * qd[j])
            .sum::<f64>();
        assert!(
            (g - e.gamma[r]).abs() < 1e-6,
            "{}: gamma_{r} {} vs {g}",
            system.info().name,
            e.gamma[r]
        );
    }
}

#[test]
fn hand_derived_systems_match_finite_differences() {
    check(&Pendulum::new(0.4), &[0.3, -0.7], &[1.1, -0.4]);
    check(
        &FourBar::crank_rocker(),
        &[0.7, 0.4, 1.9],
        &[3.0, -1.2, 2.1],
    );
    check(
        &CrankSlider::seed(),
        &[0.6, 0.45, 0.9, 0.21],
        &[6.0, 0.7, -1.3, 0.4],
    );
    let mut skew = CrankSlider::seed();
    skew.p[4] = 0.3; // alpha != 0 exercises the sin(alpha) terms
    check(&skew, &[0.6, 0.45, 0.9, 0.21], &[6.0, 0.7, -1.3, 0.4]);
}
