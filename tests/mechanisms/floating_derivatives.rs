//! The derivatives of a floating base's dynamics by the tangent of its configuration
//! manifold: Solo12 imported with a free-flyer root (`mechanism!(urdf = .., floating =
//! true)`, the type of `floating_pinocchio.rs`) against Pinocchio 4.1's
//! `computeRNEADerivatives` and `computeABADerivatives` with `JointModelFreeFlyer` at 24
//! random states (`tests/fixtures/solo12_floating_derivatives.json`, written by
//! `benches/baselines/pinocchio/floating_derivatives_fixture.py`), and against central
//! differences of our own inverse dynamics on the manifold (q moved by `integrate`).
//!
//! Tolerances: 1e-10 of each matrix's largest entry (at least 1) against Pinocchio: both
//! sides form each entry from O(100) products of O(10) terms in f64 (about 1e-14), and the
//! forward dynamics' derivatives pass through M^-1, whose condition number on Solo12 is
//! below 1e4 at these states, so 1e-10 leaves a margin of 100 over the worst expected
//! round-off. Against central differences, 1e-7: the step h = 1e-5 leaves a truncation
//! h^2 |tau'''| / 6 of about 1e-10 of the scale and a round-off eps |tau| / h of about
//! 1e-11.

use mechanism::{FloatingBase, integrate_floating};
use nalgebra::{DMatrix, SMatrix, SVector};
use serde_json::Value;

use crate::floating_interpreted::solo12_floating_text;
use crate::floating_pinocchio::{Solo, check, numbers, rows};

#[test]
fn solo12_floating_derivatives_match_pinocchio() {
    let data: Value =
        serde_json::from_str(include_str!("../fixtures/solo12_floating_derivatives.json")).unwrap();
    let joints: Vec<&str> = (data["joints"].as_array().unwrap().iter())
        .map(|j| j.as_str().unwrap())
        .collect();
    // Pinocchio numbers the joints depth-first, the importer in the file's order: v_of[j] is
    // our index of Pinocchio's v entry j (the root's six in place), q_of[j] of its q entry j.
    let ours = |j: &str| Solo::VELOCITIES.iter().position(|v| *v == j).unwrap();
    let v_of: Vec<usize> = (0..6).chain(joints.iter().map(|j| ours(j))).collect();
    let q_of: Vec<usize> = (0..7).chain(joints.iter().map(|j| ours(j) + 1)).collect();
    let solo = Solo::default();
    let mut worst = [0.0_f64; 5];
    for (k, s) in data["states"].as_array().unwrap().iter().enumerate() {
        let mut q = SVector::<f64, 19>::zeros();
        for (j, x) in numbers(&s["q"]).into_iter().enumerate() {
            q[q_of[j]] = x;
        }
        let in_v = |name: &str| {
            let mut out = SVector::<f64, 18>::zeros();
            for (j, x) in numbers(&s[name]).into_iter().enumerate() {
                out[v_of[j]] = x;
            }
            out
        };
        let (v, a, tau) = (in_v("v"), in_v("a"), in_v("tau"));
        let theirs =
            |m: &SMatrix<f64, 18, 18>| DMatrix::from_fn(18, 18, |r, c| m[(v_of[r], v_of[c])]);
        let (dq, dv) = solo.inverse_dynamics_derivatives(0.0, &q, &v, &a);
        let (fq, fv, minv) = solo
            .forward_dynamics_derivatives(0.0, &q, &v, &tau)
            .expect("M positive definite");
        let pairs = [
            ("dtau/dq", &dq, "dtau_dq"),
            ("dtau/dv", &dv, "dtau_dv"),
            ("da/dq", &fq, "ddq_dq"),
            ("da/dv", &fv, "ddq_dv"),
            ("M^-1", &minv, "minv"),
        ];
        for (w, (what, ours, key)) in pairs.into_iter().enumerate() {
            let e = check(what, k, &theirs(ours), &rows(&s[key]), 1e-10);
            worst[w] = worst[w].max(e);
        }
    }
    eprintln!("worst relative differences (dtau/dq, dtau/dv, da/dq, da/dv, M^-1): {worst:?}");
}

/// Central differences of `inverse_dynamics` along q (+) (+-h e_k) and v +- h e_k.
fn differences(
    solo: &Solo,
    q: &SVector<f64, 19>,
    v: &SVector<f64, 18>,
    a: &SVector<f64, 18>,
) -> (SMatrix<f64, 18, 18>, SMatrix<f64, 18, 18>) {
    let h = 1e-5;
    let tau = |q: &SVector<f64, 19>, v: &SVector<f64, 18>| solo.inverse_dynamics(0.0, q, v, a);
    let mut dq = SMatrix::<f64, 18, 18>::zeros();
    let mut dv = SMatrix::<f64, 18, 18>::zeros();
    for k in 0..18 {
        let e = SVector::<f64, 18>::from_fn(|i, _| if i == k { 1.0 } else { 0.0 });
        let (up, down) = (integrate_floating(q, &e, h), integrate_floating(q, &e, -h));
        dq.set_column(k, &((tau(&up, v) - tau(&down, v)) / (2.0 * h)));
        dv.set_column(
            k,
            &((tau(q, &(v + e * h)) - tau(q, &(v - e * h))) / (2.0 * h)),
        );
    }
    (dq, dv)
}

#[test]
fn solo12_floating_derivatives_match_central_differences_on_the_manifold() {
    let solo = Solo::default();
    // A tilted, turning, moving state (a unit quaternion far from the identity).
    let mut q = Solo::neutral();
    let quat = [0.3, -0.5, 0.2, 0.7];
    let norm = quat.iter().map(|x| x * x).sum::<f64>().sqrt();
    for (i, x) in quat.iter().enumerate() {
        q[3 + i] = x / norm;
    }
    q[0] = 0.4;
    q[2] = 0.3;
    for j in 7..19 {
        q[j] = 0.3 * ((j as f64) * 1.7).sin();
    }
    let v = SVector::<f64, 18>::from_fn(|i, _| ((i as f64) * 0.9 + 0.4).cos());
    let a = SVector::<f64, 18>::from_fn(|i, _| 2.0 * ((i as f64) * 1.3).sin());
    let (dq, dv) = solo.inverse_dynamics_derivatives(0.0, &q, &v, &a);
    let (fq, fv) = differences(&solo, &q, &v, &a);
    let d = |m: &SMatrix<f64, 18, 18>| DMatrix::from_column_slice(18, 18, m.as_slice());
    check("dtau/dq", 0, &d(&dq), &d(&fq), 1e-7);
    check("dtau/dv", 0, &d(&dv), &d(&fv), 1e-7);
    // The dynamics in the root's axes do not see the root's position: the columns of the
    // base's translation are zero, and those of its rotation are not (gravity turns).
    assert_eq!(dq.fixed_columns::<3>(0).amax(), 0.0);
    assert!(dq.fixed_columns::<3>(3).amax() > 1.0);
}

/// The run-time route: `InterpretedFloating::for_derivatives` and `FloatingDerivatives` on
/// Solo12 imported with `floating = true`, against the same fixture and tolerance.
#[test]
fn interpreted_solo12_floating_derivatives_match_pinocchio() {
    let text = solo12_floating_text();
    let model = mechanism_codegen::parse_model_str(&text).unwrap();
    let robot = mechanism::InterpretedFloating::for_derivatives(model).unwrap();
    let data: Value =
        serde_json::from_str(include_str!("../fixtures/solo12_floating_derivatives.json")).unwrap();
    let joints: Vec<&str> = (data["joints"].as_array().unwrap().iter())
        .map(|j| j.as_str().unwrap())
        .collect();
    let ours = |j: &str| robot.velocities().iter().position(|v| v == j).unwrap();
    let v_of: Vec<usize> = (0..6).chain(joints.iter().map(|j| ours(j))).collect();
    let q_of: Vec<usize> = (0..7).chain(joints.iter().map(|j| ours(j) + 1)).collect();
    let mut d = mechanism::FloatingDerivatives::new(&robot);
    let (mut dq, mut dv) = (vec![0.0; 18 * 18], vec![0.0; 18 * 18]);
    for (k, s) in data["states"].as_array().unwrap().iter().enumerate() {
        let mut q = vec![0.0; 19];
        for (j, x) in numbers(&s["q"]).into_iter().enumerate() {
            q[q_of[j]] = x;
        }
        let in_v = |name: &str| {
            let mut out = vec![0.0; 18];
            for (j, x) in numbers(&s[name]).into_iter().enumerate() {
                out[v_of[j]] = x;
            }
            out
        };
        let (v, a, tau) = (in_v("v"), in_v("a"), in_v("tau"));
        let theirs = |m: &[f64]| DMatrix::from_fn(18, 18, |r, c| m[v_of[r] * 18 + v_of[c]]);
        assert!(robot.inverse_dynamics_derivatives(0.0, &q, &v, &a, (&mut dq, &mut dv)));
        d.compute(&robot, 0.0, &q, &v, &tau).unwrap();
        let pairs = [
            ("dtau/dq", &dq[..], "dtau_dq"),
            ("dtau/dv", &dv[..], "dtau_dv"),
            ("da/dq", d.da_dq(), "ddq_dq"),
            ("da/dv", d.da_dv(), "ddq_dv"),
            ("M^-1", d.m_inverse(), "minv"),
        ];
        for (what, ours, key) in pairs {
            check(what, k, &theirs(ours), &rows(&s[key]), 1e-10);
        }
    }
    // Built without them, the robot says so.
    let plain = mechanism::InterpretedFloating::from_text(&text).unwrap();
    assert!(!plain.inverse_dynamics_derivatives(
        0.0,
        &plain.neutral(),
        &[0.0; 18],
        &[0.0; 18],
        (&mut dq, &mut dv)
    ));
    let e = mechanism::FloatingDerivatives::new(&plain)
        .compute(&plain, 0.0, &plain.neutral(), &[0.0; 18], &[0.0; 18])
        .unwrap_err();
    assert!(
        e.to_string()
            .contains("InterpretedFloating::for_derivatives"),
        "{e}"
    );
}
