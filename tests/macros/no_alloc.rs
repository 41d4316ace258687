//! The emitted methods allocate nothing: a counting global allocator sees zero allocations
//! while every method of every library mechanism runs (and `evaluate`, the one the solver
//! calls in its step loop; the robotics methods, every frame of the link declarations; and
//! the derivatives of the dynamics, with and without constraint rows).
//!
//! The counter is thread-local so that the test harness's other threads cannot disturb it.

use std::hint::black_box;

use mechanism::Mechanism;
use mechanism::builtin::{
    CartesianPendulum, ChaplyginSleigh, ClosedChain4, FiveBar, Panda, PlanarFourBar,
    PlanarSliderCrank, RollingDisc, SpatialCrankSlider, SpatialFourBar, WhippleBicycle,
};
use nalgebra::SVector;

/// Runs every method once and returns the number of allocations they made.
fn count<T: Mechanism<N, M> + Default, const N: usize, const M: usize>() -> usize {
    let mech = T::default();
    let q = SVector::<f64, N>::from(T::INITIAL_GUESS);
    let qd = SVector::<f64, N>::from_fn(|i, _| 0.3 + i as f64);
    let t = 0.25;
    let before = mechanism_test_support::allocations();
    black_box(mech.mass_matrix(black_box(&q)));
    black_box(mech.coriolis_matrix(&q, &qd));
    black_box(mech.coriolis_forces(&q, &qd));
    black_box(mech.gravity(&q));
    black_box(mech.generalized_forces(t, &q, &qd));
    black_box(mech.constraints(t, &q));
    black_box(mech.constraint_jacobian(t, &q));
    black_box(mech.constraint_time_derivative(t, &q));
    black_box(mech.constraint_gamma(t, &q, &qd));
    black_box(mech.kinetic_energy(&q, &qd));
    black_box(mech.potential_energy(&q));
    black_box(mech.parameter(0));
    // The initial values at the current parameters, and a parameter set (its range checked).
    black_box(mech.initial_guess());
    black_box(mech.independent(black_box(0)));
    let mut set = mech.clone();
    black_box(
        set.set_parameter(0, black_box(mech.parameter(0).unwrap_or(0.0)))
            .ok(),
    );
    black_box(mech.evaluate(black_box(t), &q, &qd));
    // The caller-buffer form the solvers call (with velocity rows: their A, a and gamma
    // among the rows of Phi_q, Phi_t and gamma).
    let mut e = mechanism::StaticEvaluation::<N, M>::zeros();
    mech.evaluate_into(t, &q, &qd, &mut e);
    black_box(&e);
    // The robotics methods (every frame of a declaration with links).
    black_box(mech.mass_and_bias(t, &q, &qd));
    black_box(mech.bias(t, &q, &qd));
    black_box(mech.inverse_dynamics(t, &q, &qd, &qd));
    black_box(mech.forward_dynamics(t, &q, &qd, &qd));
    for frame in 0..T::FRAMES.len() {
        black_box(mech.frame_placement(frame, &q));
        black_box(mech.frame_jacobian(frame, &q));
    }
    // The derivatives of the dynamics: by the motion, by the parameters (into a
    // caller's buffer), the forward dynamics' and the constrained dynamics'.
    black_box(mech.inverse_dynamics_derivatives(t, &q, &qd, &qd));
    let mut dp = [0.0; 1024];
    let dp = &mut dp[..N * T::PARAMETERS.len()];
    assert!(mech.inverse_dynamics_parameter_derivatives(t, &q, &qd, &qd, dp));
    black_box(dp);
    black_box(mech.forward_dynamics_derivatives(t, &q, &qd, &qd));
    black_box(mech.constraint_tangent(t, &q, &qd, &qd));
    let solved = mech.constrained_dynamics_derivatives(t, &q, &qd, &qd);
    assert!(black_box(solved).is_ok(), "the derivatives are computed");
    mechanism_test_support::allocations() - before
}

#[test]
fn the_counter_counts() {
    // Guards the test itself: an allocation between two readings is seen.
    let before = mechanism_test_support::allocations();
    let v: Vec<u8> = black_box(Vec::with_capacity(16));
    assert!(mechanism_test_support::allocations() > before);
    drop(v);
}

#[test]
fn emitted_methods_do_not_allocate() {
    assert_eq!(
        count::<SpatialCrankSlider, 4, 3>(),
        0,
        "spatial_crank_slider"
    );
    assert_eq!(count::<PlanarFourBar, 3, 2>(), 0, "planar_four_bar");
    assert_eq!(count::<SpatialFourBar, 4, 3>(), 0, "spatial_four_bar");
    assert_eq!(count::<ClosedChain4, 4, 2>(), 0, "closed_chain");
    assert_eq!(count::<PlanarSliderCrank, 3, 2>(), 0, "planar_slider_crank");
    assert_eq!(count::<CartesianPendulum, 2, 1>(), 0, "cartesian_pendulum");
    assert_eq!(count::<Panda, 7, 0>(), 0, "panda");
    assert_eq!(count::<FiveBar, 4, 2>(), 0, "five_bar");
    // Velocity constraints: the rolling rows of the bicycle and the disc, the sleigh's
    // knife edge.
    assert_eq!(count::<WhippleBicycle, _, _>(), 0, "whipple_bicycle");
    assert_eq!(count::<RollingDisc, _, _>(), 0, "rolling_disc");
    assert_eq!(count::<ChaplyginSleigh, _, _>(), 0, "chaplygin_sleigh");
}

mechanism::mechanism! {
    pub struct FloatingArm;
    parameters { g = 9.81; }
    gravity = [0, 0, -g];
    link base { joint = floating(base); mass = 2.0; inertia = diag(0.1, 0.2, 0.3); }
    link arm {
        parent = base; joint = revolute(q1, [0, 1, 0]); xyz = [0.1, 0, 0];
        mass = 1.0; com = [0.2, 0, 0]; inertia = diag(0.01, 0.02, 0.02);
    }
}

/// The floating-base methods, the provided ones (centre of mass, centroidal momentum
/// matrix, integrate, the forward dynamics' derivatives) included, allocate nothing either.
#[test]
fn floating_base_methods_do_not_allocate() {
    use mechanism::FloatingBase;
    let robot = FloatingArm::default();
    let q = FloatingArm::neutral();
    let v = SVector::<f64, 7>::from_fn(|i, _| 0.3 + i as f64);
    let t = 0.25;
    let before = mechanism_test_support::allocations();
    black_box(robot.mass_matrix(black_box(&q)));
    black_box(robot.coriolis_forces(&q, &v));
    black_box(robot.gravity(&q));
    black_box(robot.generalized_forces(t, &q, &v));
    black_box(robot.kinetic_energy(&q, &v));
    black_box(robot.potential_energy(&q));
    black_box(robot.mass_and_bias(t, &q, &v));
    black_box(robot.bias(t, &q, &v));
    black_box(robot.inverse_dynamics(t, &q, &v, &v));
    black_box(robot.forward_dynamics(t, &q, &v, &v));
    black_box(robot.center_of_mass(&q));
    black_box(robot.centroidal_momentum_matrix(&q));
    black_box(FloatingArm::integrate(&q, &v, 0.01));
    black_box(robot.inverse_dynamics_derivatives(t, &q, &v, &v));
    black_box(robot.forward_dynamics_derivatives(t, &q, &v, &v));
    for frame in 0..FloatingArm::FRAMES.len() {
        black_box(robot.frame_placement(frame, &q));
        black_box(robot.frame_jacobian(frame, &q));
    }
    assert_eq!(mechanism_test_support::allocations() - before, 0);
}
