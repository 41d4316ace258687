//! The derivatives of the dynamics against Pinocchio 4.1 on three robots imported from
//! their URDFs: the Panda (`mechanisms/panda.mech`, fingers locked), the UR5 and Solo12
//! with its base fixed (`mechanisms/urdf/ur5_robot.urdf`, `mechanisms/urdf/solo12.urdf`
//! through `mechanism!(urdf = ..)`), at 24 random states each
//! (`tests/fixtures/{panda,ur5,solo12}_derivatives.json`, written by
//! `benches/baselines/pinocchio/derivatives_fixture.py`, where both models are described):
//! `inverse_dynamics_derivatives` against `computeRNEADerivatives` (dtau/dq, dtau/dv) and
//! `forward_dynamics_derivatives` against `computeABADerivatives` (ddq/dq, ddq/dv, M^-1),
//! the emitted code and the interpreter route (`Interpreted::for_derivatives`) alike.
//!
//! Tolerance: 1e-10 of each matrix's largest entry (at least 1). Both sides sum a few
//! hundred products of O(10) terms in f64 (round-off near 1e-14 relative), the forward
//! dynamics' derivatives are scaled by cond(M) (below 1e4 at these states), and Pinocchio's
//! own identities hold to 1e-13 there (the generator's self-checks): 1e-10 leaves room
//! for both and would still catch a wrong sign, term or axis, which is O(1).

use mechanism::{Interpreted, Mechanism, System, Tangent};
use nalgebra::{DMatrix, SMatrix, SVector};
use serde_json::Value;

mechanism::mechanism!(urdf = "mechanisms/urdf/ur5_robot.urdf", name = Ur5);
mechanism::mechanism!(urdf = "mechanisms/urdf/solo12.urdf", name = Solo12);

fn fixture(text: &str) -> Value {
    serde_json::from_str(text).unwrap()
}

fn numbers(v: &Value) -> Vec<f64> {
    let mut out = Vec::new();
    match v {
        Value::Array(a) => a.iter().for_each(|x| out.extend(numbers(x))),
        x => out.push(x.as_f64().unwrap()),
    }
    out
}

fn vector<const N: usize>(v: &Value) -> SVector<f64, N> {
    SVector::from_iterator(numbers(v))
}

/// A row-major fixture matrix.
fn matrix<const N: usize>(v: &Value) -> SMatrix<f64, N, N> {
    SMatrix::from_row_iterator(numbers(v))
}

fn check<const N: usize>(what: &str, k: usize, ours: &SMatrix<f64, N, N>, theirs: &Value) {
    let theirs = matrix::<N>(theirs);
    let scale = theirs.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    let err = (ours - theirs).amax();
    assert!(
        err <= 1e-10 * scale,
        "{what} at state {k}: max |ours - Pinocchio| = {err:e} (scale {scale:e})"
    );
}

/// Every state of `text` through the emitted methods of `robot`.
fn against_pinocchio<T: Mechanism<N, 0>, const N: usize>(robot: &T, text: &str) {
    let data = fixture(text);
    let joints: Vec<&str> = (data["joints"].as_array().unwrap().iter())
        .map(|j| j.as_str().unwrap())
        .collect();
    assert_eq!(T::COORDINATES.to_vec(), joints);
    let states = data["states"].as_array().unwrap();
    assert_eq!(states.len(), 24);
    for (k, s) in states.iter().enumerate() {
        let (q, qd) = (vector::<N>(&s["q"]), vector::<N>(&s["qd"]));
        let (qdd, tau) = (vector::<N>(&s["qdd"]), vector::<N>(&s["tau"]));
        let (dq, dqd) = robot.inverse_dynamics_derivatives(0.0, &q, &qd, &qdd);
        check("dtau/dq", k, &dq, &s["dtau_dq"]);
        check("dtau/dq'", k, &dqd, &s["dtau_dv"]);
        let (dq, dqd, inverse) = robot
            .forward_dynamics_derivatives(0.0, &q, &qd, &tau)
            .expect("M positive definite");
        check("dq''/dq", k, &dq, &s["ddq_dq"]);
        check("dq''/dq'", k, &dqd, &s["ddq_dv"]);
        check("M^-1", k, &inverse, &s["minv"]);
    }
}

/// Every state of `text` through the interpreter route of the declaration `source`.
fn interpreted_against_pinocchio<const N: usize>(source: &str, text: &str) {
    let model = mechanism_codegen::parse_model_str(source).unwrap();
    let system = Interpreted::for_derivatives(model).unwrap();
    let data = fixture(text);
    let mut out = Tangent::zeros(N);
    for (k, s) in data["states"].as_array().unwrap().iter().enumerate() {
        let (q, qd, qdd) = (numbers(&s["q"]), numbers(&s["qd"]), numbers(&s["qdd"]));
        system
            .inverse_dynamics_derivatives(0.0, &q, &qd, &qdd, &mut out)
            .expect("compiled with its derivatives");
        let fixed = |m: &DMatrix<f64>| SMatrix::<f64, N, N>::from_fn(|i, j| m[(i, j)]);
        check(
            "dtau/dq (interpreted)",
            k,
            &fixed(&out.stiffness),
            &s["dtau_dq"],
        );
        check(
            "dtau/dq' (interpreted)",
            k,
            &fixed(&out.damping),
            &s["dtau_dv"],
        );
    }
}

#[test]
fn panda_derivatives_match_pinocchio() {
    let text = include_str!("../fixtures/panda_derivatives.json");
    against_pinocchio(&mechanism::builtin::Panda::default(), text);
    interpreted_against_pinocchio::<7>(include_str!("../../mechanisms/panda.mech"), text);
}

#[test]
fn ur5_derivatives_match_pinocchio() {
    against_pinocchio(
        &Ur5::default(),
        include_str!("../fixtures/ur5_derivatives.json"),
    );
}

#[test]
fn solo12_derivatives_match_pinocchio() {
    against_pinocchio(
        &Solo12::default(),
        include_str!("../fixtures/solo12_derivatives.json"),
    );
}
