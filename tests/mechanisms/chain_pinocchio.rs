//! A serial chain of 200 revolute links (`benches/scale/serial_chain.py`: axes alternating
//! z, y, x, 0.1 m apart, 1 kg links with a full inertia tensor), imported from its URDF and
//! derived at run time, against Pinocchio 4.1 at 10 states
//! (`tests/fixtures/chain200_pinocchio.json`, written by
//! `benches/baselines/pinocchio/chain_fixture.py`): the diagonal of M and M x for a fixed x
//! (`crba`; the whole of M is 40,000 numbers a state, and M x differs from Pinocchio's
//! wherever an entry does), C q' + g (`nonLinearEffects`) and M q'' + C q' + g (`rnea`).
//!
//! Tolerance: 1e-12 of each quantity's largest entry (at least 1). Both sides sum O(200)
//! products per entry in f64 (a relative round-off of a few 1e-14 of the largest term),
//! and Pinocchio's own rnea = M q'' + nle holds to 3e-15 at these states (the fixture's
//! self-check). The generated forward dynamics at the same states: M q'' + C q' + g = tau
//! for Pinocchio's tau, to 1e-13 of its scale.

use mechanism::{Evaluation, Interpreted, Kinematic, System};
use mechanism_codegen::{Tangents, UrdfOptions, derive, parse_model_str, urdf_to_mech};
use serde_json::Value;

/// The URDF of `serial_chain.py`, byte for byte: `n` revolute links below a fixed base.
fn serial_chain_urdf(n: usize) -> String {
    let axes = ["0 0 1", "0 1 0", "1 0 0"];
    let mut out =
        format!("<?xml version=\"1.0\"?>\n<robot name=\"chain{n}\">\n  <link name=\"base\"/>\n");
    for i in 1..=n {
        let parent = if i == 1 {
            "base".to_string()
        } else {
            format!("link{}", i - 1)
        };
        let z = if i == 1 { "0.0" } else { "0.1" };
        let axis = axes[(i - 1) % 3];
        out.push_str(&format!(
            "  <link name=\"link{i}\">\n    <inertial>\n      <origin xyz=\"0.01 0 0.05\" rpy=\"0 0 0\"/>\n      <mass value=\"1\"/>\n      <inertia ixx=\"0.0042\" ixy=\"0.0001\" ixz=\"-0.0002\" iyy=\"0.0041\" iyz=\"0.0003\" izz=\"0.0008\"/>\n    </inertial>\n  </link>\n  <joint name=\"j{i}\" type=\"revolute\">\n    <parent link=\"{parent}\"/>\n    <child link=\"link{i}\"/>\n    <origin xyz=\"0 0 {z}\" rpy=\"0 0 0\"/>\n    <axis xyz=\"{axis}\"/>\n    <limit lower=\"-3\" upper=\"3\" effort=\"100\" velocity=\"10\"/>\n  </joint>\n"
        ));
    }
    out.push_str("</robot>\n");
    out
}

/// q, q', q'' of state k and the vector x (the fixture script's formulas).
fn state(n: usize, k: usize) -> [Vec<f64>; 3] {
    let at = |i: usize| (7 * k + 3 * i) as f64;
    [
        (0..n).map(|i| 1.5 * (0.37 * at(i) + 0.2).sin()).collect(),
        (0..n).map(|i| 0.5 * (0.61 * at(i) + 1.0).cos()).collect(),
        (0..n).map(|i| 2.0 * (0.23 * at(i) + 2.0).sin()).collect(),
    ]
}

fn numbers(v: &Value) -> Vec<f64> {
    let all = v.as_array().unwrap().iter();
    all.map(|x| x.as_f64().unwrap()).collect()
}

/// The largest |ours - theirs| against 1e-12 times the largest |theirs| (at least 1).
fn check(what: &str, k: usize, ours: &[f64], theirs: &[f64]) {
    assert_eq!(ours.len(), theirs.len(), "{what}");
    let scale = theirs.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    let err = ours
        .iter()
        .zip(theirs)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
    assert!(
        err <= 1e-12 * scale,
        "{what} at state {k}: max |ours - Pinocchio| = {err:e} (scale {scale})"
    );
}

#[test]
fn a_chain_of_200_links_matches_pinocchio() {
    let data: Value =
        serde_json::from_str(include_str!("../fixtures/chain200_pinocchio.json")).unwrap();
    let n = data["n"].as_u64().unwrap() as usize;
    let urdf = serial_chain_urdf(n);
    assert_eq!(urdf.len() as u64, data["urdf_bytes"].as_u64().unwrap());
    let options = UrdfOptions {
        file_name: "chain200.urdf".into(),
        ..Default::default()
    };
    let text = urdf_to_mech(&urdf, &options).expect("imported");
    // As `mechanism simulate` builds it for an explicit integrator: without the residual's
    // tangent (an implicit integrator's), which for 200 links costs more than the rest.
    let mut model = parse_model_str(&text).expect("parsed");
    let eqs = derive(&mut model).expect("derived");
    let system = Interpreted::from_equations_with(model, eqs, Tangents::None).expect("compiled");
    let info = system.info().clone();
    assert_eq!((info.n(), info.m()), (n, 0));
    // The importer names each coordinate after its joint, in the file's order.
    assert!((0..n).all(|i| info.coordinates[i] == format!("j{}", i + 1)));
    let x: Vec<f64> = (0..n).map(|i| (0.7 * i as f64 + 0.3).cos()).collect();
    let mut e = Evaluation::zeros(n, 0);
    let states = data["states"].as_array().unwrap();
    assert_eq!(states.len(), 10);
    for (k, s) in states.iter().enumerate() {
        let [q, qd, qdd] = state(n, k);
        system.evaluate(0.0, &q, &qd, &mut e);
        let diag: Vec<f64> = (0..n).map(|i| e.mass[(i, i)]).collect();
        check("diag M", k, &diag, &numbers(&s["diag_M"]));
        let mx: Vec<f64> = (0..n)
            .map(|i| (0..n).map(|j| e.mass[(i, j)] * x[j]).sum())
            .collect();
        check("M x", k, &mx, &numbers(&s["M_x"]));
        let nle: Vec<f64> = (0..n).map(|i| e.coriolis[i] + e.gravity[i]).collect();
        check("C q' + g", k, &nle, &numbers(&s["nle"]));
        let tau: Vec<f64> = (0..n)
            .map(|i| nle[i] + (0..n).map(|j| e.mass[(i, j)] * qdd[j]).sum::<f64>())
            .collect();
        check("M q'' + C q' + g", k, &tau, &numbers(&s["tau"]));
        // The generated forward dynamics (the articulated-body recursion, which the
        // interpreter compiles at the default budget for 200 links and runs at every
        // integration stage) with Pinocchio's tau as the effort: its q'' must satisfy
        // M q'' + C q' + g = tau with the M and C q' + g just checked against Pinocchio.
        // The backward error, not q'' itself, is held: q'' differs from the fixture's by
        // up to cond(M) times it. Tolerance 1e-13 of tau's scale: a row of M q'' sums 200
        // products, each up to about tau's scale, so forming it here rounds by about
        // 200 eps ~ 4e-14 of that scale, and the recursion's own residual is of the same
        // order (measured: at most 3.6e-12 on scales of 750-1300, 3e-15 relative).
        let theirs_tau = numbers(&s["tau"]);
        let (mut generated, mut forces) = (vec![0.0; n], vec![0.0; n]);
        let solved =
            system.forward_dynamics(0.0, &q, &qd, &theirs_tau, &mut generated, &mut forces);
        assert_eq!(
            solved,
            Some(true),
            "the generated forward dynamics at state {k}"
        );
        let residual: Vec<f64> = (0..n)
            .map(|i| nle[i] + (0..n).map(|j| e.mass[(i, j)] * generated[j]).sum::<f64>())
            .collect();
        let scale = theirs_tau.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
        let err = residual
            .iter()
            .zip(&theirs_tau)
            .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
        assert!(
            err <= 1e-13 * scale,
            "M q''_generated + C q' + g - tau = {err:e} at state {k}"
        );
    }
}
