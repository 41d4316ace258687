//! Two floating-base robots imported from their URDFs by `mechanism!(urdf = .., floating =
//! true)`, Solo12 (12 joints) and Talos (30 joints, the grippers locked), against
//! Pinocchio 4.1 with `JointModelFreeFlyer` at 24 random states each (random unit
//! quaternion and position; `tests/fixtures/{solo12,talos}_floating_pinocchio.json`,
//! written by `benches/baselines/pinocchio/floating_fixture.py`): M (`crba`), C v + g
//! (`nonLinearEffects`, both from `mass_and_bias` and from `bias`), g, the inverse dynamics
//! (`rnea`), the forward dynamics (`aba`), every link frame's placement, the
//! LOCAL_WORLD_ALIGNED Jacobians of the feet, hands, head and base, the centroidal momentum
//! matrix (`ccrba`) and the centre of mass, and `integrate` (q moved by v dt on
//! SE(3) x R^joints).
//!
//! Pinocchio numbers the joints depth-first, the importer in the file's link order: the
//! entries are matched by name.
//!
//! Tolerances: 1e-12 of each quantity's largest entry (at least 1): both sides sum O(100)
//! products of O(1) terms in f64, and Pinocchio's own identities hold to 2e-13 at these
//! states (the fixture's self-check). The forward dynamics too: a solve of M a = tau - b
//! may move a by cond(M) (up to 8e4 on Talos) times the relative error of M and of the
//! right-hand side (each about 1e-16), so 1e-12 holds with a margin of 1e-11 / 1e-12 only
//! in the worst case; measured, the worst relative difference is 3e-15.

use mechanism::FloatingBase;
use nalgebra::{DMatrix, SMatrix, SVector};
use serde_json::Value;

mechanism::mechanism!(urdf = "mechanisms/urdf/solo12.urdf", floating = true);
mechanism::mechanism!(
    urdf = "mechanisms/urdf/talos_reduced.urdf",
    lock = ["gripper_left_joint", "gripper_right_joint"],
    floating = true,
    name = Talos
);

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

fn rows(v: &Value) -> DMatrix<f64> {
    let rows: Vec<Vec<f64>> = v.as_array().unwrap().iter().map(numbers).collect();
    DMatrix::from_fn(rows.len(), rows[0].len(), |i, j| rows[i][j])
}

/// The largest |ours - theirs| against `tol` times the largest |theirs| (at least 1).
fn check(what: &str, k: usize, ours: &DMatrix<f64>, theirs: &DMatrix<f64>, tol: f64) -> f64 {
    assert_eq!(ours.shape(), theirs.shape(), "{what}");
    let scale = theirs.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    let err = (ours - theirs).abs().max();
    assert!(
        err <= tol * scale,
        "{what} at state {k}: max |ours - Pinocchio| = {err:e} (scale {scale}, tolerance {tol:e})"
    );
    err / scale
}

/// Pinocchio's order and ours: `v_of[j]` is our index of Pinocchio's v entry j, `q_of[j]`
/// of its q entry j (the root's seven and six in place, the joints matched by name).
fn orders<R: FloatingBase<NQ, NV>, const NQ: usize, const NV: usize>(
    joints: &[String],
) -> (Vec<usize>, Vec<usize>) {
    let ours = |j: &String| R::VELOCITIES.iter().position(|v| v == j).unwrap();
    let v_of: Vec<usize> = (0..6).chain(joints.iter().map(ours)).collect();
    let q_of: Vec<usize> = (0..7).chain(joints.iter().map(|j| ours(j) + 1)).collect();
    (q_of, v_of)
}

fn check_robot<R: FloatingBase<NQ, NV> + Default, const NQ: usize, const NV: usize>(fixture: &str) {
    let data: Value = serde_json::from_str(fixture).unwrap();
    let joints: Vec<String> = (data["joints"].as_array().unwrap().iter())
        .map(|j| j.as_str().unwrap().to_string())
        .collect();
    assert_eq!(joints.len(), NV - 6);
    let (q_of, v_of) = orders::<R, NQ, NV>(&joints);
    let robot = R::default();
    let ours_q = |x: &[f64]| {
        let mut out = SVector::<f64, NQ>::zeros();
        q_of.iter().enumerate().for_each(|(j, &i)| out[i] = x[j]);
        out
    };
    let ours_v = |x: &[f64]| {
        let mut out = SVector::<f64, NV>::zeros();
        v_of.iter().enumerate().for_each(|(j, &i)| out[i] = x[j]);
        out
    };
    let theirs_v = |x: &SVector<f64, NV>| DMatrix::from_fn(NV, 1, |j, _| x[v_of[j]]);
    let theirs_m =
        |m: &SMatrix<f64, NV, NV>| DMatrix::from_fn(NV, NV, |r, c| m[(v_of[r], v_of[c])]);
    let column = |x: &[f64]| DMatrix::from_column_slice(x.len(), 1, x);
    let mut worst = [0.0_f64; 4];
    let states = data["states"].as_array().unwrap();
    assert_eq!(states.len(), 24);
    for (k, s) in states.iter().enumerate() {
        let q = ours_q(&numbers(&s["q"]));
        let v = ours_v(&numbers(&s["v"]));
        let a = ours_v(&numbers(&s["a"]));
        let (mass, bias) = robot.mass_and_bias(0.0, &q, &v);
        worst[0] = worst[0].max(check("M", k, &theirs_m(&mass), &rows(&s["M"]), 1e-12));
        check(
            "M alone",
            k,
            &theirs_m(&robot.mass_matrix(&q)),
            &rows(&s["M"]),
            1e-12,
        );
        let nle = column(&numbers(&s["nle"]));
        worst[1] = worst[1].max(check("C v + g", k, &theirs_v(&bias), &nle, 1e-12));
        check("bias", k, &theirs_v(&robot.bias(0.0, &q, &v)), &nle, 1e-12);
        let g = column(&numbers(&s["g"]));
        check("g", k, &theirs_v(&robot.gravity(&q)), &g, 1e-12);
        let tau = robot.inverse_dynamics(0.0, &q, &v, &a);
        let rnea = column(&numbers(&s["tau"]));
        worst[2] = worst[2].max(check("rnea", k, &theirs_v(&tau), &rnea, 1e-12));
        let effort = ours_v(&numbers(&s["tau_in"]));
        let acc = robot
            .forward_dynamics(0.0, &q, &v, &effort)
            .expect("definite");
        let aba = column(&numbers(&s["aba"]));
        worst[3] = worst[3].max(check("aba", k, &theirs_v(&acc), &aba, 1e-12));
        check_frames(&robot, k, s, &q, &v_of);
        let ag = robot.centroidal_momentum_matrix(&q);
        let ours = DMatrix::from_fn(6, NV, |r, c| ag[(r, v_of[c])]);
        check("ccrba", k, &ours, &rows(&s["Ag"]), 1e-12);
        let c = robot.center_of_mass(&q);
        let theirs = column(&numbers(&s["com"]));
        check(
            "com",
            k,
            &DMatrix::from_fn(3, 1, |i, _| c[i]),
            &theirs,
            1e-12,
        );
        let moved = R::integrate(&q, &v, data["dt"].as_f64().unwrap());
        let theirs = column(&numbers(&s["integrate"]));
        check(
            "integrate",
            k,
            &DMatrix::from_fn(NQ, 1, |j, _| moved[q_of[j]]),
            &theirs,
            1e-12,
        );
    }
    eprintln!(
        "{}: worst |ours - Pinocchio| / scale: M {:.1e}, C v + g {:.1e}, rnea {:.1e}, aba {:.1e}",
        R::NAME,
        worst[0],
        worst[1],
        worst[2],
        worst[3]
    );
}

/// Every link frame's placement and the named frames' Jacobians of state `k`.
fn check_frames<R: FloatingBase<NQ, NV>, const NQ: usize, const NV: usize>(
    robot: &R,
    k: usize,
    s: &Value,
    q: &SVector<f64, NQ>,
    v_of: &[usize],
) {
    let placements = s["placements"].as_object().unwrap();
    for (name, p) in placements {
        let f = R::frame_index(name).unwrap_or_else(|| panic!("frame {name}"));
        let (r, x) = robot.frame_placement(f, q).unwrap();
        let what = format!("placement of {name}");
        check(
            &what,
            k,
            &DMatrix::from_fn(3, 3, |i, j| r[(i, j)]),
            &rows(&p["R"]),
            1e-12,
        );
        let theirs = DMatrix::from_column_slice(3, 1, &numbers(&p["p"]));
        check(
            &what,
            k,
            &DMatrix::from_fn(3, 1, |i, _| x[i]),
            &theirs,
            1e-12,
        );
    }
    for (name, jac) in s["jacobians"].as_object().unwrap() {
        let f = R::frame_index(name).unwrap();
        let j = robot.frame_jacobian(f, q).unwrap();
        let ours = DMatrix::from_fn(6, NV, |r, c| j[(r, v_of[c])]);
        check(&format!("Jacobian of {name}"), k, &ours, &rows(jac), 1e-12);
    }
}

#[test]
fn solo12_free_flyer_matches_pinocchio() {
    assert_eq!((Solo::NQ, Solo::NV), (19, 18));
    let fixture = include_str!("../fixtures/solo12_floating_pinocchio.json");
    check_robot::<Solo, 19, 18>(fixture);
}

#[test]
fn talos_free_flyer_matches_pinocchio() {
    assert_eq!((Talos::NQ, Talos::NV), (37, 36));
    let fixture = include_str!("../fixtures/talos_floating_pinocchio.json");
    check_robot::<Talos, 37, 36>(fixture);
}
