//! The KKT solve that follows M's pattern (the emitted `constrained_dynamics`: M = L^T D L
//! in straight-line code, the m x m Schur complement at run time) against the dense
//! augmented-Lagrangian `kkt_solve` on every constrained mechanism of `mechanisms/`, a URDF
//! with a `<mimic>` row and a closed loop, at states along their motion: q'' and the
//! constraint forces Phi_q^T lambda (unique where lambda is not) agree to round-off, and
//! where the tree route is not emitted (M singular, as for the seed's massless angles) the
//! method is the dense solve itself.

use mechanism::builtin::{
    Bricard, CartesianPendulum, ChaplyginSleigh, ClosedChain4, FiveBar, NFourBar40, PlanarFourBar,
    PlanarFourBarBodies, PlanarSliderCrank, RollingDisc, SpatialCrankSlider,
    SpatialCrankSliderRigid, SpatialFourBar, SpatialFourBarBodies, WhippleBicycle,
};
use mechanism::fixed::kkt_solve;
use mechanism::{Compiled, IntegratorOptions, Mechanism, SimulationOptions, simulate};
use nalgebra::SVector;

mechanism::mechanism!(
    urdf = "tests/runtime/mimic_gripper.urdf",
    name = MimicGripper
);

/// `count` states (t, q, q') along `t_end` of motion from the declared assembly (DOP853 at
/// rtol 1e-10), so that the redundant rows of the overconstrained mechanisms are redundant.
fn states<T: Mechanism<N, M>, const N: usize, const M: usize>(
    m: &T,
    t_end: f64,
    count: usize,
) -> Vec<(f64, SVector<f64, N>, SVector<f64, N>)> {
    let options = SimulationOptions {
        t_end,
        integrator: IntegratorOptions::dop853(1e-10),
        ..Default::default()
    };
    let run = simulate(&Compiled::new(m.clone()), &options).expect("simulated");
    let stride = (run.len() / count).max(1);
    run.samples()
        .step_by(stride)
        .map(|s| {
            let q = SVector::from_column_slice(s.q);
            (s.t, q, SVector::from_column_slice(s.qd))
        })
        .collect()
}

/// The largest difference of q'' and of Phi_q^T lambda between the two routes, each
/// relative to its scale (the largest |q''|, or the largest generalized force), over the
/// states; asserted below `tolerance`.
fn agree<T: Mechanism<N, M>, const N: usize, const M: usize>(
    m: T,
    t_end: f64,
    count: usize,
    tolerance: f64,
) {
    let mut worst = (0.0_f64, 0.0_f64);
    for (t, q, qd) in states(&m, t_end, count) {
        let e = m.evaluate(t, &q, &qd);
        let dense = kkt_solve(&e, t).expect("dense solve");
        let tree = m.constrained_dynamics(t, &q, &qd).expect("tree solve");
        let jt = e.phi_q.transpose();
        let scale = dense.qdd.amax().max(1.0);
        let load = (e.forces - e.coriolis - e.gravity).amax();
        let force_scale = (jt * dense.lambda).amax().max(load).max(1e-3);
        let dq = (tree.qdd - dense.qdd).amax() / scale;
        let df = (jt * tree.lambda - jt * dense.lambda).amax() / force_scale;
        worst = (worst.0.max(dq), worst.1.max(df));
    }
    println!(
        "{}: q'' {:.1e}, Phi_q^T lambda {:.1e}",
        T::NAME,
        worst.0,
        worst.1
    );
    assert!(
        worst.0 <= tolerance && worst.1 <= tolerance,
        "{}: the routes differ by {:e} in q'' and {:e} in Phi_q^T lambda",
        T::NAME,
        worst.0,
        worst.1
    );
}

// Both routes are backward-stable direct solves of one system; their difference is about
// the KKT matrix's condition number times 2.2e-16. The mechanisms below have condition
// numbers up to about 1e3 on these states (`Dynamics`' estimate, as in `fixed.rs`), so
// 1e-11 allows a factor 40 of growth on top.
const ROUND_OFF: f64 = 1e-11;

#[test]
fn the_tree_route_agrees_with_the_dense_solve_on_linkages() {
    agree(SpatialCrankSlider::default(), 0.6, 8, ROUND_OFF);
    agree(SpatialCrankSliderRigid::default(), 0.6, 8, ROUND_OFF);
    agree(PlanarFourBar::default(), 0.6, 8, ROUND_OFF);
    agree(SpatialFourBar::default(), 0.6, 8, ROUND_OFF);
    agree(SpatialFourBarBodies::default(), 0.6, 8, ROUND_OFF);
    agree(PlanarFourBarBodies::default(), 0.6, 8, ROUND_OFF);
    agree(ClosedChain4::default(), 0.6, 8, ROUND_OFF);
    agree(PlanarSliderCrank::default(), 0.6, 8, ROUND_OFF);
    agree(CartesianPendulum::default(), 0.6, 8, ROUND_OFF);
    agree(FiveBar::default(), 0.6, 8, ROUND_OFF);
}

#[test]
fn the_tree_route_agrees_with_the_dense_solve_on_redundant_rows() {
    // Bricard: 30 rows of rank 29; the 40-bar: 81 rows of rank 81 (41 where flat).
    agree(Bricard::default(), 0.3, 6, ROUND_OFF);
    agree(NFourBar40::default(), 0.1, 4, ROUND_OFF);
}

#[test]
fn the_tree_route_agrees_with_the_dense_solve_on_velocity_rows() {
    agree(WhippleBicycle::default(), 0.6, 8, ROUND_OFF);
    agree(RollingDisc::default(), 0.6, 8, ROUND_OFF);
    agree(ChaplyginSleigh::default(), 0.6, 8, ROUND_OFF);
}

#[test]
fn the_tree_route_agrees_with_the_dense_solve_on_a_mimic_row() {
    agree(MimicGripper::default(), 0.3, 8, ROUND_OFF);
}

/// Whether `mechanism!` emits the tree route for `source` (its `ConstrainedDynamics`
/// program has outputs): by operation count, and never for an M singular at every q.
fn emits_the_tree_route(source: &str) -> bool {
    let mut model = mechanism_codegen::parse_model_str(source).expect("parses");
    let eqs = mechanism_codegen::derive(&mut model).expect("derives");
    let tangent = mechanism_codegen::residual_tangent(&mut model, &eqs).expect("tangent");
    let r = mechanism_codegen::compile(&mut model, &eqs, &tangent).expect("compiles");
    let program = r.get(mechanism_codegen::Role::ConstrainedDynamics);
    program.is_some_and(|p| !p.outputs().is_empty())
}

#[test]
fn the_route_is_chosen_where_m_is_invertible() {
    // The seed's beta and gamma carry no inertia: M's pivots are identically 0, the dense
    // augmented solve (M + alpha Phi_q^T Phi_q) stays.
    let seed = include_str!("../../mechanisms/spatial_crank_slider.mech");
    assert!(!emits_the_tree_route(seed));
    // A five-bar of link frames and the mimic gripper: M positive definite, and the tree
    // route counts fewer operations.
    assert!(emits_the_tree_route(include_str!(
        "../../mechanisms/five_bar.mech"
    )));
    let urdf = include_str!("mimic_gripper.urdf");
    let options = mechanism_codegen::UrdfOptions {
        file_name: "mimic_gripper.urdf".into(),
        ..Default::default()
    };
    let text = mechanism_codegen::urdf_to_mech(urdf, &options).expect("imported");
    assert!(emits_the_tree_route(&text));
}

#[test]
fn a_nan_state_is_the_dense_solves_error() {
    let m = FiveBar::default();
    let (t, q, mut qd) = states(&m, 0.1, 1)[0];
    qd[0] = f64::NAN;
    let e = m.evaluate(t, &q, &qd);
    assert_eq!(m.constrained_dynamics(t, &q, &qd), kkt_solve(&e, t));
    assert!(m.constrained_dynamics(t, &q, &qd).is_err());
}

#[test]
fn the_tree_route_and_the_fixed_step_allocate_nothing() {
    use mechanism::fixed::{FixedStep, State};
    let m = MimicGripper::default();
    let (t, q, qd) = states(&m, 0.1, 1)[0];
    let mut state = State { t, q, qd };
    let stepper = FixedStep::new(1e-3);
    stepper.step(&m, &mut state).unwrap();
    let before = mechanism_test_support::allocations();
    for _ in 0..200 {
        stepper.step(&m, &mut state).unwrap();
        m.constrained_dynamics(state.t, &state.q, &state.qd)
            .unwrap();
    }
    assert_eq!(mechanism_test_support::allocations() - before, 0);
}
