//! The Unitree G1 humanoid imported from its URDF (`mechanisms/urdf/g1_29dof_rev_1_0.urdf`,
//! 29 revolute joints, the pelvis fixed) and derived at run time, against Pinocchio 4.1 at 8
//! random states (`tests/fixtures/g1_pinocchio.json`, written by
//! `benches/baselines/pinocchio/g1_fixture.py`): M (`crba`), C q' + g (`nonLinearEffects`),
//! g, the free motion's q'' (`aba` with no joint torque), and the torques of a prescribed
//! motion (`rnea`) from our inverse dynamics (every joint driven, the driver constraints
//! solved), a route that shares only the derived M, C q' and g with the checks above.
//!
//! Unlike the Panda (a serial arm), the G1 is a tree whose two arms hang from a torso that
//! three waist joints move, so M couples the branches through their common ancestors: the
//! route through the importer, the tree derivation and the interpreter is checked where a
//! wrong parent frame or a missed ancestor would show.
//!
//! Tolerances: M, C q' + g and g to 1e-12 of each quantity's largest entry (at least 1), as
//! for the Panda: both sides sum O(100) products of O(1) terms in f64, and Pinocchio's own
//! identities hold to 2e-14 at these states (the fixture's self-check); tau likewise (the
//! driven system with every coordinate driven has E = I: lambda_d is read off the rows
//! without amplification). q'' to
//! 1e-14 cond(M) of its largest entry: a solve of M q'' = -(C q' + g) moves the solution by
//! cond(M) times the relative error of M and of the right-hand side (each about 1e-15).

use mechanism::{
    AssemblyOptions, Dynamics, Evaluation, Interpreted, Kinematic, System, inverse_dynamics,
    parse_drive,
};
use mechanism_codegen::{UrdfOptions, urdf_to_mech};
use serde_json::Value;

fn fixture() -> Value {
    serde_json::from_str(include_str!("../fixtures/g1_pinocchio.json")).unwrap()
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// The largest |ours - theirs| against `tol` times the largest |theirs| (at least 1).
fn check(what: &str, k: usize, ours: &[f64], theirs: &[f64], tol: f64) {
    assert_eq!(ours.len(), theirs.len(), "{what}");
    let scale = theirs.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    let err = ours
        .iter()
        .zip(theirs)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        err <= tol * scale,
        "{what} at state {k}: max |ours - Pinocchio| = {err:e} (scale {scale}, tolerance {tol:e})"
    );
}

#[test]
fn g1_tree_dynamics_match_pinocchio() {
    let data = fixture();
    let urdf = include_str!("../../mechanisms/urdf/g1_29dof_rev_1_0.urdf");
    let options = UrdfOptions {
        file_name: "g1_29dof_rev_1_0.urdf".into(),
        ..Default::default()
    };
    let text = urdf_to_mech(urdf, &options).expect("imported");
    let system = Interpreted::from_source(&text).expect("derived");
    let info = system.info().clone();
    let (n, m) = (info.n(), info.m());
    assert_eq!((n, m), (29, 0));
    // Pinocchio numbers the joints depth-first, the importer in the file's link order (for
    // this file the two coincide); matched by name all the same: the coordinate named
    // after Pinocchio's joint j is ours at order[j].
    let joints: Vec<&str> = data["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j.as_str().unwrap())
        .collect();
    let order: Vec<usize> = joints
        .iter()
        .map(|j| info.coordinates.iter().position(|c| c == j).unwrap())
        .collect();
    let ours_of = |v: &[f64]| {
        let mut out = vec![0.0; n];
        for (j, &i) in order.iter().enumerate() {
            out[i] = v[j];
        }
        out
    };
    let theirs_of = |v: &[f64]| order.iter().map(|&i| v[i]).collect::<Vec<f64>>();
    let mut e = Evaluation::zeros(n, m);
    let mut dynamics = Dynamics::new(&info);
    let states = data["states"].as_array().unwrap();
    assert!(states.len() >= 8);
    for (k, s) in states.iter().enumerate() {
        let (q, qd) = (ours_of(&numbers(&s["q"])), ours_of(&numbers(&s["qd"])));
        system.evaluate(0.0, &q, &qd, &mut e);
        assert!(
            e.forces.iter().all(|&f| f == 0.0),
            "no joint torque declared"
        );
        let mass: Vec<f64> = order
            .iter()
            .flat_map(|&r| order.iter().map(move |&c| (r, c)))
            .map(|(r, c)| e.mass[(r, c)])
            .collect();
        let theirs_m: Vec<f64> = s["M"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(numbers)
            .collect();
        check("M", k, &mass, &theirs_m, 1e-12);
        let nle: Vec<f64> = e
            .coriolis
            .iter()
            .zip(&e.gravity)
            .map(|(c, g)| c + g)
            .collect();
        check("C q' + g", k, &theirs_of(&nle), &numbers(&s["nle"]), 1e-12);
        check(
            "g",
            k,
            &theirs_of(e.gravity.as_slice()),
            &numbers(&s["g"]),
            1e-12,
        );
        // Each joint on q + q' t + q'' t^2 / 2: at t = 0 the driving forces are rnea's tau.
        let qdd = ours_of(&numbers(&s["qdd"]));
        let drives = (0..n)
            .map(|i| {
                let (name, a) = (&info.coordinates[i], 0.5 * qdd[i]);
                let text = format!("{name} = {:?} + {:?}*t + {a:?}*t*t", q[i], qd[i]);
                parse_drive(&system, &text).expect("drive")
            })
            .collect();
        let inverse = inverse_dynamics(&system, drives, &[0.0], &AssemblyOptions::default())
            .expect("inverse dynamics");
        let tau = &inverse.samples[0].driving;
        check("tau", k, &theirs_of(tau), &numbers(&s["tau"]), 1e-12);
        dynamics.solve(&system, 0.0, &q, &qd).expect("solved");
        let cond = s["cond_M"].as_f64().unwrap();
        check(
            "q''",
            k,
            &theirs_of(dynamics.accelerations()),
            &numbers(&s["aba_free"]),
            1e-14 * cond,
        );
    }
}
