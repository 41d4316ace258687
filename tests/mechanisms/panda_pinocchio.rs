//! The Franka Panda imported from its URDF (`mechanisms/panda.mech`, from
//! `mechanisms/urdf/panda.urdf` with the fingers locked at 0) against Pinocchio 4.1 at 24
//! random states (`tests/fixtures/panda_pinocchio.json`, written by
//! `benches/baselines/pinocchio/panda_fixture.py`): M (`crba`), C q' + g
//! (`nonLinearEffects`), g, tau (`rnea`), q'' (`aba`), the placements of the link frames and
//! the hand's Jacobian (`LOCAL_WORLD_ALIGNED`).
//!
//! Tolerance: 1e-12 of each quantity's largest entry (at least 1). Pinocchio's own
//! identities hold to 2e-14 at these states (the fixture's self-check), both sides sum
//! O(100) products in f64, and the forward dynamics is scaled by cond(M) < 1e3 here.

use mechanism::Mechanism;
use mechanism::builtin::Panda;
use nalgebra::{SMatrix, SVector};
use serde_json::Value;

type V = SVector<f64, 7>;

fn fixture() -> Value {
    let text = include_str!("../fixtures/panda_pinocchio.json");
    serde_json::from_str(text).unwrap()
}

fn vector(v: &Value) -> V {
    V::from_iterator(v.as_array().unwrap().iter().map(|x| x.as_f64().unwrap()))
}

fn matrix<const R: usize, const C: usize>(v: &Value) -> SMatrix<f64, R, C> {
    let rows = v.as_array().unwrap();
    assert_eq!(rows.len(), R);
    SMatrix::from_fn(|i, j| rows[i][j].as_f64().unwrap())
}

fn check<const R: usize, const C: usize>(
    what: &str,
    k: usize,
    ours: &SMatrix<f64, R, C>,
    theirs: &SMatrix<f64, R, C>,
) {
    let scale = theirs.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    let err = (ours - theirs).iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    assert!(
        err <= 1e-12 * scale,
        "{what} at state {k}: max |ours - Pinocchio| = {err:e} (scale {scale})"
    );
}

#[test]
fn panda_dynamics_match_pinocchio() {
    let data = fixture();
    let states = data["states"].as_array().unwrap();
    assert!(states.len() >= 20);
    let names: Vec<&str> = data["joints"]
        .as_array()
        .unwrap()
        .iter()
        .map(|j| j.as_str().unwrap())
        .collect();
    assert_eq!(Panda::COORDINATES.to_vec(), names);
    let robot = Panda::default();
    for (k, s) in states.iter().enumerate() {
        let (q, qd, qdd) = (vector(&s["q"]), vector(&s["qd"]), vector(&s["qdd"]));
        let e = robot.evaluate(0.0, &q, &qd);
        check("M", k, &e.mass, &matrix::<7, 7>(&s["M"]));
        check("C q' + g", k, &(e.coriolis + e.gravity), &vector(&s["nle"]));
        check("bias", k, &robot.bias(0.0, &q, &qd), &vector(&s["nle"]));
        let (mass, bias) = robot.mass_and_bias(0.0, &q, &qd);
        check("M (mass_and_bias)", k, &mass, &matrix::<7, 7>(&s["M"]));
        check("bias (mass_and_bias)", k, &bias, &vector(&s["nle"]));
        check("g", k, &robot.gravity(&q), &vector(&s["g"]));
        let tau = robot.inverse_dynamics(0.0, &q, &qd, &qdd);
        check("tau", k, &tau, &vector(&s["tau"]));
        let fd = robot.forward_dynamics(0.0, &q, &qd, &vector(&s["tau_in"]));
        check("q''", k, &fd.unwrap(), &vector(&s["aba"]));
        for (frame, p) in s["placements"].as_object().unwrap() {
            let f = Panda::frame_index(frame).unwrap();
            let (r, x) = robot.frame_placement(f, &q).unwrap();
            check(frame, k, &r, &matrix::<3, 3>(&p["R"]));
            check(
                frame,
                k,
                &x,
                &SMatrix::<f64, 3, 1>::from_iterator(
                    p["p"]
                        .as_array()
                        .unwrap()
                        .iter()
                        .map(|v| v.as_f64().unwrap()),
                ),
            );
        }
        let hand = Panda::frame_index("panda_hand").unwrap();
        let jac = robot.frame_jacobian(hand, &q).unwrap();
        check(
            "J(hand)",
            k,
            &jac,
            &matrix::<6, 7>(&s["jacobian_panda_hand"]),
        );
    }
}

/// The interpreter route from the URDF itself (imported and derived at run time, as the
/// command-line tool and the Python package do) with the robotics routines
/// (`Interpreted::from_model_with`): the `System` face's M, C q' + g, inverse dynamics,
/// frame placements and hand Jacobian against the same fixture, to the same tolerance; a
/// parameter change reaches the robotics routines' own cache (the effort scales with the
/// gravity parameter at rest).
#[test]
fn interpreted_panda_from_its_urdf_matches_pinocchio() {
    use mechanism::{Evaluation, Interpreted, Kinematic, System};
    use mechanism_codegen::{Tangents, UrdfOptions, parse_model_str, urdf_to_mech};
    use nalgebra::{DMatrix, Matrix3, Vector3};

    let options = UrdfOptions {
        file_name: "panda.urdf".into(),
        lock: vec!["panda_finger_joint1".into(), "panda_finger_joint2".into()],
        ..UrdfOptions::default()
    };
    let text = urdf_to_mech(include_str!("../../mechanisms/urdf/panda.urdf"), &options).unwrap();
    let model = parse_model_str(&text).unwrap();
    let mut robot = Interpreted::from_model_with(model, Tangents::None, true).unwrap();
    let data = fixture();
    let n = robot.info().n();
    let to = |v: &[f64]| V::from_column_slice(v);
    let mut e = Evaluation::zeros(n, 0);
    let mut u = vec![0.0; n];
    let (mut r, mut p) = (Matrix3::zeros(), Vector3::zeros());
    let mut jac = DMatrix::zeros(6, n);
    for (k, s) in data["states"].as_array().unwrap().iter().enumerate() {
        let (q, qd, qdd) = (vector(&s["q"]), vector(&s["qd"]), vector(&s["qdd"]));
        robot.evaluate(0.0, q.as_slice(), qd.as_slice(), &mut e);
        let mass = SMatrix::<f64, 7, 7>::from_fn(|i, j| e.mass[(i, j)]);
        check("M", k, &mass, &matrix::<7, 7>(&s["M"]));
        let nle = to((&e.coriolis + &e.gravity).as_slice());
        check("C q' + g", k, &nle, &vector(&s["nle"]));
        robot
            .inverse_dynamics(0.0, q.as_slice(), qd.as_slice(), qdd.as_slice(), &mut u)
            .unwrap();
        check("tau", k, &to(&u), &vector(&s["tau"]));
        for (frame, placement) in s["placements"].as_object().unwrap() {
            let f = robot.info().frame_index(frame).unwrap();
            robot
                .frame_placement(f, q.as_slice(), &mut r, &mut p)
                .unwrap();
            check(frame, k, &r, &matrix::<3, 3>(&placement["R"]));
            let theirs = placement["p"].as_array().unwrap();
            let theirs = Vector3::from_iterator(theirs.iter().map(|v| v.as_f64().unwrap()));
            check(frame, k, &p, &theirs);
        }
        let hand = robot.info().frame_index("panda_hand").unwrap();
        robot.frame_jacobian(hand, q.as_slice(), &mut jac).unwrap();
        let jac = SMatrix::<f64, 6, 7>::from_fn(|i, j| jac[(i, j)]);
        check(
            "J(hand)",
            k,
            &jac,
            &matrix::<6, 7>(&s["jacobian_panda_hand"]),
        );
    }
    // At rest the effort is g(q) alone, linear in the gravity parameter g.
    let q = vector(&data["states"][0]["q"]);
    let zero = [0.0; 7];
    robot
        .inverse_dynamics(0.0, q.as_slice(), &zero, &zero, &mut u)
        .unwrap();
    let before = to(&u);
    let g = robot.info().parameter_index("g").unwrap();
    robot.set_parameter(g, 2.0 * 9.81).unwrap();
    robot
        .inverse_dynamics(0.0, q.as_slice(), &zero, &zero, &mut u)
        .unwrap();
    check("tau(2 g)", 0, &to(&u), &(before * 2.0));
    assert_eq!(
        robot.frame_placement(99, q.as_slice(), &mut r, &mut p),
        None
    );
}
