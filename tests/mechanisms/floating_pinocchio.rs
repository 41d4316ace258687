//! Two floating-base robots imported from their URDFs with a free-flyer root, Solo12 (12
//! joints) and Talos (30 joints, the grippers locked), against Pinocchio 4.1 with
//! `JointModelFreeFlyer` at 24 random states each (random unit quaternion and position;
//! `tests/fixtures/{solo12,talos}_floating_pinocchio.json`, written by
//! `benches/baselines/pinocchio/floating_fixture.py`): M (`crba`), C v + g
//! (`nonLinearEffects`, both from `mass_and_bias` and from `bias`), g, the inverse dynamics
//! (`rnea`), the forward dynamics (`aba`), every link frame's placement, the
//! LOCAL_WORLD_ALIGNED Jacobians of the feet, hands, head and base, the centroidal momentum
//! matrix (`ccrba`) and the centre of mass, and `integrate` (q moved by v dt on
//! SE(3) x R^joints).
//!
//! Two routes run the same compiled routines: the type `mechanism!(urdf = .., floating =
//! true)` emits (Solo12), and codegen's tapes of `compile_floating`'s routines (Solo12 and
//! Talos: the macro's Talos would add a minute and a half of compilation to the suite), whose
//! centroidal momentum matrix and centre of mass the test forms from M itself.
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

use std::cell::RefCell;
use std::collections::HashMap;

use mechanism::{FloatingBase, integrate_floating};
use mechanism_codegen::{Role, Routines, Source, Tape, UrdfOptions};
use nalgebra::{DMatrix, Matrix3, SMatrix, SVector, Vector3};
use serde_json::Value;

mechanism::mechanism!(urdf = "mechanisms/urdf/solo12.urdf", floating = true);

/// What the test reads of a floating-base robot, by either route.
trait Route<const NQ: usize, const NV: usize> {
    fn velocities(&self) -> Vec<String>;
    fn frame(&self, name: &str) -> usize;
    fn mass_and_bias(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
    ) -> (SMatrix<f64, NV, NV>, SVector<f64, NV>);
    fn mass_matrix(&self, q: &SVector<f64, NQ>) -> SMatrix<f64, NV, NV>;
    fn bias(&self, q: &SVector<f64, NQ>, v: &SVector<f64, NV>) -> SVector<f64, NV>;
    fn gravity(&self, q: &SVector<f64, NQ>) -> SVector<f64, NV>;
    fn inverse_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
    ) -> SVector<f64, NV>;
    fn forward_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
        u: &SVector<f64, NV>,
    ) -> SVector<f64, NV>;
    fn placement(&self, frame: usize, q: &SVector<f64, NQ>) -> (Matrix3<f64>, Vector3<f64>);
    fn jacobian(&self, frame: usize, q: &SVector<f64, NQ>) -> SMatrix<f64, 6, NV>;
    fn centroidal(&self, q: &SVector<f64, NQ>) -> (SMatrix<f64, 6, NV>, Vector3<f64>);
}

/// The macro's type.
struct Emitted<R>(R);

impl<R: FloatingBase<NQ, NV>, const NQ: usize, const NV: usize> Route<NQ, NV> for Emitted<R> {
    fn velocities(&self) -> Vec<String> {
        R::VELOCITIES.iter().map(|s| s.to_string()).collect()
    }
    fn frame(&self, name: &str) -> usize {
        R::frame_index(name).unwrap_or_else(|| panic!("frame {name}"))
    }
    fn mass_and_bias(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
    ) -> (SMatrix<f64, NV, NV>, SVector<f64, NV>) {
        self.0.mass_and_bias(0.0, q, v)
    }
    fn mass_matrix(&self, q: &SVector<f64, NQ>) -> SMatrix<f64, NV, NV> {
        self.0.mass_matrix(q)
    }
    fn bias(&self, q: &SVector<f64, NQ>, v: &SVector<f64, NV>) -> SVector<f64, NV> {
        self.0.bias(0.0, q, v)
    }
    fn gravity(&self, q: &SVector<f64, NQ>) -> SVector<f64, NV> {
        self.0.gravity(q)
    }
    fn inverse_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
    ) -> SVector<f64, NV> {
        self.0.inverse_dynamics(0.0, q, v, a)
    }
    fn forward_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
        u: &SVector<f64, NV>,
    ) -> SVector<f64, NV> {
        self.0
            .forward_dynamics(0.0, q, v, u)
            .expect("M positive definite")
    }
    fn placement(&self, frame: usize, q: &SVector<f64, NQ>) -> (Matrix3<f64>, Vector3<f64>) {
        self.0.frame_placement(frame, q).unwrap()
    }
    fn jacobian(&self, frame: usize, q: &SVector<f64, NQ>) -> SMatrix<f64, 6, NV> {
        self.0.frame_jacobian(frame, q).unwrap()
    }
    fn centroidal(&self, q: &SVector<f64, NQ>) -> (SMatrix<f64, 6, NV>, Vector3<f64>) {
        (
            self.0.centroidal_momentum_matrix(q),
            self.0.center_of_mass(q),
        )
    }
}

/// codegen's tapes of the routines `compile_floating` gives for the URDF imported with
/// `floating = true`, the parameters at their defaults.
struct Tapes {
    routines: Routines,
    tapes: RefCell<HashMap<Role, Tape>>,
    symbols: usize,
    parameters: Vec<f64>,
    cache: Vec<f64>,
    velocities: Vec<String>,
    frames: Vec<String>,
}

impl Tapes {
    fn new(urdf: &str, lock: &[&str]) -> Tapes {
        let options = UrdfOptions {
            file_name: "robot.urdf".into(),
            lock: lock.iter().map(|s| s.to_string()).collect(),
            floating: true,
            ..Default::default()
        };
        let text = mechanism_codegen::urdf_to_mech(urdf, &options).unwrap();
        let mut model = mechanism_codegen::parse_model_str(&text).unwrap();
        let eqs = mechanism_codegen::derive(&mut model).unwrap();
        let routines = mechanism_codegen::compile_floating(&mut model, &eqs).unwrap();
        let symbols = routines
            .sources()
            .iter()
            .map(|(s, _)| s.index() + 1)
            .max()
            .unwrap_or(0);
        let mut tapes = Tapes {
            routines,
            tapes: RefCell::new(HashMap::new()),
            symbols,
            parameters: model.parameters.iter().map(|p| p.default).collect(),
            cache: Vec::new(),
            velocities: model.coordinates.iter().map(|c| c.name.clone()).collect(),
            frames: eqs.frames.iter().map(|f| f.name.clone()).collect(),
        };
        tapes.cache = tapes.run(Role::ParameterCache, &[], &[], &[], &[]);
        tapes
    }

    /// The outputs of `role` at q, v, a and the efforts u, row-major one after another.
    fn run(&self, role: Role, q: &[f64], v: &[f64], a: &[f64], u: &[f64]) -> Vec<f64> {
        let mut inputs = vec![0.0; self.symbols];
        for (s, source) in self.routines.sources().iter() {
            let at = |x: &[f64], k: usize| x.get(k).copied().unwrap_or(0.0);
            inputs[s.index()] = match source {
                Source::Coordinate(k) => at(q, k),
                Source::Rate(k) => at(v, k),
                Source::Acceleration(k) => at(a, k),
                Source::Effort(k) => at(u, k),
                Source::Parameter(k) => self.parameters[k],
                Source::Cache(k) => at(&self.cache, k),
                Source::Time | Source::Multiplier(_) => 0.0,
            };
        }
        let mut tapes = self.tapes.borrow_mut();
        let tape = tapes
            .entry(role)
            .or_insert_with(|| Tape::new(self.routines.program(role).unwrap()));
        let mut out = vec![0.0; tape.output_len()];
        tape.eval(&inputs, &mut out).unwrap();
        out
    }
}

fn square<const N: usize>(x: &[f64]) -> SMatrix<f64, N, N> {
    SMatrix::from_fn(|i, j| x[i * N + j])
}

impl<const NQ: usize, const NV: usize> Route<NQ, NV> for Tapes {
    fn velocities(&self) -> Vec<String> {
        self.velocities.clone()
    }
    fn frame(&self, name: &str) -> usize {
        self.frames
            .iter()
            .position(|f| f == name)
            .unwrap_or_else(|| panic!("frame {name}"))
    }
    fn mass_and_bias(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
    ) -> (SMatrix<f64, NV, NV>, SVector<f64, NV>) {
        let out = self.run(Role::MassAndBias, q.as_slice(), v.as_slice(), &[], &[]);
        (square(&out), SVector::from_column_slice(&out[NV * NV..]))
    }
    fn mass_matrix(&self, q: &SVector<f64, NQ>) -> SMatrix<f64, NV, NV> {
        square(&self.run(Role::Mass, q.as_slice(), &[], &[], &[]))
    }
    fn bias(&self, q: &SVector<f64, NQ>, v: &SVector<f64, NV>) -> SVector<f64, NV> {
        SVector::from_column_slice(&self.run(Role::Bias, q.as_slice(), v.as_slice(), &[], &[]))
    }
    fn gravity(&self, q: &SVector<f64, NQ>) -> SVector<f64, NV> {
        SVector::from_column_slice(&self.run(Role::Gravity, q.as_slice(), &[], &[], &[]))
    }
    fn inverse_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
    ) -> SVector<f64, NV> {
        let out = self.run(
            Role::InverseDynamics,
            q.as_slice(),
            v.as_slice(),
            a.as_slice(),
            &[],
        );
        SVector::from_column_slice(&out)
    }
    fn forward_dynamics(
        &self,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
        u: &SVector<f64, NV>,
    ) -> SVector<f64, NV> {
        let out = self.run(
            Role::ForwardDynamics,
            q.as_slice(),
            v.as_slice(),
            &[],
            u.as_slice(),
        );
        SVector::from_column_slice(&out[..NV])
    }
    fn placement(&self, frame: usize, q: &SVector<f64, NQ>) -> (Matrix3<f64>, Vector3<f64>) {
        let out = self.run(Role::FramePlacement(frame), q.as_slice(), &[], &[], &[]);
        (square(&out), Vector3::from_column_slice(&out[9..]))
    }
    fn jacobian(&self, frame: usize, q: &SVector<f64, NQ>) -> SMatrix<f64, 6, NV> {
        let out = self.run(Role::FrameJacobian(frame), q.as_slice(), &[], &[], &[]);
        SMatrix::from_fn(|i, j| out[i * NV + j])
    }
    /// From M's root rows, formed here (the momentum in the root's axes about its origin):
    /// h from the block -[h]x, c = x + R h / m, A_g = [[R, 0], [-[c - x]x R, R]] M[0..6, :].
    fn centroidal(&self, q: &SVector<f64, NQ>) -> (SMatrix<f64, 6, NV>, Vector3<f64>) {
        let m: SMatrix<f64, NV, NV> = Route::<NQ, NV>::mass_matrix(self, q);
        let x = Vector3::new(q[0], q[1], q[2]);
        let quat = nalgebra::Quaternion::new(q[6], q[3], q[4], q[5]);
        let r = *nalgebra::UnitQuaternion::from_quaternion(quat)
            .to_rotation_matrix()
            .matrix();
        let skew = m.fixed_view::<3, 3>(0, 3).into_owned();
        let h = Vector3::new(skew[(1, 2)], skew[(2, 0)], skew[(0, 1)]);
        let c = x + r * h / m[(0, 0)];
        let mut ag = SMatrix::<f64, 6, NV>::zeros();
        for j in 0..NV {
            let p = r * m.fixed_view::<3, 1>(0, j);
            let l = r * m.fixed_view::<3, 1>(3, j) - (c - x).cross(&p);
            ag.fixed_view_mut::<3, 1>(0, j).copy_from(&p);
            ag.fixed_view_mut::<3, 1>(3, j).copy_from(&l);
        }
        (ag, c)
    }
}

/// The numbers of the JSON array `v`.
pub(crate) fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// The row-major rows of `v`.
pub(crate) fn rows(v: &Value) -> DMatrix<f64> {
    let rows: Vec<Vec<f64>> = v.as_array().unwrap().iter().map(numbers).collect();
    DMatrix::from_fn(rows.len(), rows[0].len(), |i, j| rows[i][j])
}

/// The largest |ours - theirs| against `tol` times the largest |theirs| (at least 1); the
/// relative error.
pub(crate) fn check(
    what: &str,
    k: usize,
    ours: &DMatrix<f64>,
    theirs: &DMatrix<f64>,
    tol: f64,
) -> f64 {
    assert_eq!(ours.shape(), theirs.shape(), "{what}");
    let scale = theirs.iter().fold(1.0_f64, |m, x| m.max(x.abs()));
    let err = (ours - theirs).abs().max();
    assert!(
        err <= tol * scale,
        "{what} at state {k}: max |ours - reference| = {err:e} (scale {scale}, tolerance {tol:e})"
    );
    err / scale
}

/// Pinocchio's order and ours: `v_of[j]` is our index of Pinocchio's v entry j, `q_of[j]`
/// of its q entry j (the root's seven and six in place, the joints matched by name).
fn orders(velocities: &[String], joints: &[String]) -> (Vec<usize>, Vec<usize>) {
    let ours = |j: &String| velocities.iter().position(|v| v == j).unwrap();
    let v_of: Vec<usize> = (0..6).chain(joints.iter().map(ours)).collect();
    let q_of: Vec<usize> = (0..7).chain(joints.iter().map(|j| ours(j) + 1)).collect();
    (q_of, v_of)
}

fn check_robot<const NQ: usize, const NV: usize>(route: &impl Route<NQ, NV>, fixture: &str) {
    let data: Value = serde_json::from_str(fixture).unwrap();
    let joints: Vec<String> = (data["joints"].as_array().unwrap().iter())
        .map(|j| j.as_str().unwrap().to_string())
        .collect();
    assert_eq!(joints.len(), NV - 6);
    let (q_of, v_of) = orders(&route.velocities(), &joints);
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
        let (mass, bias) = route.mass_and_bias(&q, &v);
        worst[0] = worst[0].max(check("M", k, &theirs_m(&mass), &rows(&s["M"]), 1e-12));
        let alone = theirs_m(&route.mass_matrix(&q));
        check("M alone", k, &alone, &rows(&s["M"]), 1e-12);
        let nle = column(&numbers(&s["nle"]));
        worst[1] = worst[1].max(check("C v + g", k, &theirs_v(&bias), &nle, 1e-12));
        check("bias", k, &theirs_v(&route.bias(&q, &v)), &nle, 1e-12);
        let g = column(&numbers(&s["g"]));
        check("g", k, &theirs_v(&route.gravity(&q)), &g, 1e-12);
        let tau = route.inverse_dynamics(&q, &v, &a);
        let rnea = column(&numbers(&s["tau"]));
        worst[2] = worst[2].max(check("rnea", k, &theirs_v(&tau), &rnea, 1e-12));
        let effort = ours_v(&numbers(&s["tau_in"]));
        let acc = route.forward_dynamics(&q, &v, &effort);
        let aba = column(&numbers(&s["aba"]));
        worst[3] = worst[3].max(check("aba", k, &theirs_v(&acc), &aba, 1e-12));
        check_frames(route, k, s, &q, &v_of);
        let (ag, c) = route.centroidal(&q);
        let ours = DMatrix::from_fn(6, NV, |r, col| ag[(r, v_of[col])]);
        check("ccrba", k, &ours, &rows(&s["Ag"]), 1e-12);
        let theirs = column(&numbers(&s["com"]));
        check(
            "com",
            k,
            &DMatrix::from_fn(3, 1, |i, _| c[i]),
            &theirs,
            1e-12,
        );
        let moved = integrate_floating(&q, &v, data["dt"].as_f64().unwrap());
        let theirs = column(&numbers(&s["integrate"]));
        let ours = DMatrix::from_fn(NQ, 1, |j, _| moved[q_of[j]]);
        check("integrate", k, &ours, &theirs, 1e-12);
    }
    eprintln!(
        "NV = {NV}: worst |ours - Pinocchio| / scale: M {:.1e}, C v + g {:.1e}, rnea {:.1e}, aba {:.1e}",
        worst[0], worst[1], worst[2], worst[3]
    );
}

/// Every link frame's placement and the named frames' Jacobians of state `k`.
fn check_frames<const NQ: usize, const NV: usize>(
    route: &impl Route<NQ, NV>,
    k: usize,
    s: &Value,
    q: &SVector<f64, NQ>,
    v_of: &[usize],
) {
    for (name, p) in s["placements"].as_object().unwrap() {
        let (r, x) = route.placement(route.frame(name), q);
        let what = format!("placement of {name}");
        let ours = DMatrix::from_fn(3, 3, |i, j| r[(i, j)]);
        check(&what, k, &ours, &rows(&p["R"]), 1e-12);
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
        let j = route.jacobian(route.frame(name), q);
        let ours = DMatrix::from_fn(6, NV, |r, c| j[(r, v_of[c])]);
        check(&format!("Jacobian of {name}"), k, &ours, &rows(jac), 1e-12);
    }
}

const SOLO12: &str = include_str!("../../mechanisms/urdf/solo12.urdf");
const TALOS: &str = include_str!("../../mechanisms/urdf/talos_reduced.urdf");

#[test]
fn solo12_free_flyer_matches_pinocchio() {
    assert_eq!((Solo::NQ, Solo::NV), (19, 18));
    let fixture = include_str!("../fixtures/solo12_floating_pinocchio.json");
    check_robot::<19, 18>(&Emitted(Solo::default()), fixture);
    check_robot::<19, 18>(&Tapes::new(SOLO12, &[]), fixture);
}

#[test]
fn talos_free_flyer_matches_pinocchio() {
    let fixture = include_str!("../fixtures/talos_floating_pinocchio.json");
    let talos = Tapes::new(TALOS, &["gripper_left_joint", "gripper_right_joint"]);
    assert_eq!(talos.velocities.len(), 36);
    check_robot::<37, 36>(&talos, fixture);
}
