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
