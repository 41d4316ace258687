//! The fixed-size (no_std) solvers against the run-time ones and against their own
//! equations: the KKT solve reproduces the LU route's q'' and constraint forces and satisfies
//! both rows of the augmented system; the fixed step is fourth order, keeps Phi = 0 to its
//! tolerance, and neither allocates.

use mechanism::builtin::{PlanarFourBar, PlanarFourBarBodies, SpatialCrankSlider, SpatialFourBar};
use mechanism::fixed::{FixedError, FixedStep, State, kkt_solve};
use mechanism::{
    Compiled, Dynamics, IntegratorOptions, Kinematic, Mechanism, Method, Sample, SimulationOptions,
    Trajectory, simulate,
};
use nalgebra::SVector;

/// A DOP853 run to `t_end` at tolerance `rtol` from the declared assembly.
fn reference<T: Mechanism<N, M>, const N: usize, const M: usize>(
    m: &T,
    t_end: f64,
    rtol: f64,
) -> Trajectory {
    let options = SimulationOptions {
        t_end,
        integrator: IntegratorOptions {
            method: Method::Dop853,
            rtol,
            atol: rtol * 1e-2,
            ..Default::default()
        },
        ..Default::default()
    };
    simulate(&Compiled::new(m.clone()), &options).unwrap()
}

/// One sample as a fixed-size state.
fn state_of<const N: usize>(s: Sample<'_>) -> State<N> {
    State {
        t: s.t,
        q: SVector::from_column_slice(s.q),
        qd: SVector::from_column_slice(s.qd),
    }
}

/// `count` states along 0.6 s of motion (DOP853 at rtol 1e-11).
fn states<T: Mechanism<N, M>, const N: usize, const M: usize>(
    m: &T,
    count: usize,
) -> Vec<State<N>> {
    let trajectory = reference(m, 0.6, 1e-11);
    let stride = (trajectory.len() / count).max(1);
    trajectory.samples().step_by(stride).map(state_of).collect()
}

/// The KKT solve against `Dynamics` (LU with the same equations) on q'' and on the
/// constraint forces Phi_q^T lambda (unique even where lambda is not), and its own residuals.
fn agrees_with_the_runtime<T: Mechanism<N, M>, const N: usize, const M: usize>(m: T) {
    let system = Compiled::new(m.clone());
    let mut dynamics = Dynamics::new(system.info());
    for s in states(&m, 12) {
        let e = m.evaluate(s.t, &s.q, &s.qd);
        let fixed = kkt_solve(&e, s.t).unwrap();
        dynamics
            .solve(&system, s.t, s.q.as_slice(), s.qd.as_slice())
            .unwrap();
        let qdd = SVector::<f64, N>::from_column_slice(dynamics.accelerations());
        let lambda = SVector::<f64, M>::from_column_slice(dynamics.min_norm_multipliers());
        let jt = e.phi_q.transpose();
        let load = e.forces - e.coriolis - e.gravity;
        // Both are backward-stable solves of one system whose condition number is at most
        // about 1.1e3 on these states (Dynamics' estimate; the redundant four-bar goes
        // through its augmented Lagrangian, accurate to round-off in q''): 1e-11 of the
        // scale is 1e3 * 2.2e-16 with a factor 40 for growth. Measured: 8e-15 at most.
        let scale = qdd.amax().max(1.0);
        assert!(
            (fixed.qdd - qdd).amax() <= 1e-11 * scale,
            "{} t = {}: q'' {} vs {}",
            T::NAME,
            s.t,
            fixed.qdd,
            qdd
        );
        let force_scale = (jt * lambda).amax().max(load.amax()).max(1e-3);
        assert!(
            (jt * fixed.lambda - jt * lambda).amax() <= 1e-11 * force_scale,
            "{} t = {}: Phi_q^T lambda {} vs {}",
            T::NAME,
            s.t,
            jt * fixed.lambda,
            jt * lambda
        );
        // Its own equations, to round-off of the terms: M q'' + Phi_q^T lambda = Q and
        // Phi_q q'' = gamma.
        let r1 = e.mass * fixed.qdd + jt * fixed.lambda - load;
        let r2 = e.phi_q * fixed.qdd - e.gamma;
        let term = (e.mass * fixed.qdd).amax().max(load.amax()).max(1e-3);
        assert!(
            r1.amax() <= 1e-12 * term,
            "{}: force residual {r1}",
            T::NAME
        );
        let accel = (e.phi_q * fixed.qdd).amax().max(e.gamma.amax()).max(1e-3);
        assert!(
            r2.amax() <= 1e-12 * accel,
            "{}: gamma residual {r2}",
            T::NAME
        );
    }
}

#[test]
fn kkt_solve_matches_the_runtime_on_the_seed_with_its_singular_mass_matrix() {
    // beta and gamma carry no inertia: M is singular, M + alpha Phi_q^T Phi_q is not.
    agrees_with_the_runtime(SpatialCrankSlider::default());
}

#[test]
fn kkt_solve_matches_the_runtime_on_four_bars() {
    agrees_with_the_runtime(PlanarFourBar::default());
    agrees_with_the_runtime(SpatialFourBar::default());
}

#[test]
fn kkt_solve_handles_redundant_rows() {
    // 20 rows of rank 17: lambda is not unique, q'' and Phi_q^T lambda are.
    agrees_with_the_runtime(PlanarFourBarBodies::default());
}

mechanism::mechanism! {
    /// x is held by a constraint; y carries no mass and nothing holds it.
    pub struct Loose;
    parameters { m = 1.0; }
    coordinates { x = 0.5; y = 0.0; }
    independent { y = 0.0; }
    kinetic = 1/2*m*der(x)^2;
    potential = 0;
    constraints { x - 0.5; }
}

#[test]
fn an_undetermined_motion_is_an_error_naming_the_coordinate() {
    let (q, qd) = (SVector::from([0.5, 0.0]), SVector::from([0.0, 1.0]));
    let e = Loose::default().evaluate(0.25, &q, &qd);
    assert_eq!(
        kkt_solve(&e, 0.25),
        Err(FixedError::UndeterminedMotion {
            coordinate: 1,
            t: 0.25
        })
    );
}

#[test]
fn a_nan_state_is_an_error_not_a_nan_result() {
    let m = PlanarFourBar::default();
    let mut state = states(&m, 1)[0];
    state.qd[0] = f64::NAN;
    let before = state;
    let e = m.evaluate(state.t, &state.q, &state.qd);
    assert!(matches!(
        kkt_solve(&e, state.t),
        Err(FixedError::NotFinite { .. })
    ));
    let err = FixedStep::new(1e-3).step(&m, &mut state).unwrap_err();
    assert!(matches!(err, FixedError::NotFinite { .. }), "{err}");
    // The state is left as it was (NaN compares unequal, so compare bits).
    assert_eq!(state.q, before.q);
}

/// max |q(0.2) - q_ref(0.2)| after fixed steps of h from the reference's start.
fn error_at_02<T: Mechanism<N, M>, const N: usize, const M: usize>(m: &T, h: f64) -> f64 {
    let reference = reference(m, 0.2, 1e-13);
    let mut state = state_of(reference.sample(0));
    let stepper = FixedStep::new(h);
    let steps = (0.2 / h).round() as usize;
    for _ in 0..steps {
        stepper.step(m, &mut state).unwrap();
        // Projected after every step to the stepper's tolerance.
        assert!(m.constraints(state.t, &state.q).amax() <= stepper.tolerance);
        let v = m.constraint_jacobian(state.t, &state.q) * state.qd
            + m.constraint_time_derivative(state.t, &state.q);
        assert!(v.amax() <= 1e-11, "velocity constraint {v}");
    }
    let end = reference.last().unwrap();
    assert!((end.t - state.t).abs() < 1e-12);
    (state.q - SVector::<f64, N>::from_column_slice(end.q)).amax()
}

#[test]
fn the_fixed_step_is_fourth_order() {
    // Halving h divides a fourth-order global error by 16; projection must not spoil it
    // (accept 12: the h^5 term is not negligible at the coarser step).
    let cases = [
        (
            "seed",
            error_at_02(&SpatialCrankSlider::default(), 4e-3),
            error_at_02(&SpatialCrankSlider::default(), 2e-3),
        ),
        (
            "four-bar",
            error_at_02(&PlanarFourBar::default(), 4e-3),
            error_at_02(&PlanarFourBar::default(), 2e-3),
        ),
    ];
    for (name, coarse, fine) in cases {
        assert!(
            coarse / fine >= 12.0 && fine < 1e-6,
            "{name}: error {coarse:e} at h = 4e-3, {fine:e} at 2e-3 (ratio {})",
            coarse / fine
        );
    }
}

#[test]
fn the_fixed_step_and_the_kkt_solve_allocate_nothing() {
    let m = SpatialCrankSlider::default();
    let mut state = states(&m, 1)[0];
    let stepper = FixedStep::new(1e-3);
    stepper.step(&m, &mut state).unwrap();
    let before = mechanism_test_support::allocations();
    for _ in 0..200 {
        stepper.step(&m, &mut state).unwrap();
        let e = m.evaluate(state.t, &state.q, &state.qd);
        kkt_solve(&e, state.t).unwrap();
    }
    assert_eq!(mechanism_test_support::allocations() - before, 0);
}

mod driven {
    mechanism::mechanism!(file = "examples/driven_four_bar.mech");
}

/// max |th1(t) - th1_d(t)| over 1 s when the crank torque of the driven four-bar is the
/// inverse-dynamics torque for th1_d, held over each step at its mid-step value.
fn open_loop_tracking_error(h: f64) -> f64 {
    use mechanism::{AssemblyOptions, inverse_dynamics, parse_drive};
    let mut model = driven::DrivenFourBar::default();
    let system = Compiled::new(model.clone());
    let drive = "th1 = pi/2 + 2*pi*t + 0.3*sin(2*pi*t)";
    let steps = (1.0 / h).round() as usize;
    let times: Vec<f64> = (0..=steps).map(|k| k as f64 * h).collect();
    let mid: Vec<f64> = (0..steps).map(|k| (k as f64 + 0.5) * h).collect();
    let assembly = AssemblyOptions::default();
    let at = |times: &[f64]| {
        inverse_dynamics(
            &system,
            vec![parse_drive(&system, drive).unwrap()],
            times,
            &assembly,
        )
        .unwrap()
        .samples
    };
    let (exact, torque) = (at(&times), at(&mid));
    let mut state = State {
        t: 0.0,
        q: SVector::from_column_slice(&exact[0].q),
        qd: SVector::from_column_slice(&exact[0].qd),
    };
    let stepper = FixedStep::new(h);
    let mut worst = 0.0_f64;
    for (k, sample) in torque.iter().enumerate() {
        model.u = sample.driving[0];
        stepper.step(&model, &mut state).unwrap();
        worst = worst.max((state.q[0] - exact[k + 1].q[0]).abs());
    }
    worst
}

#[test]
fn inverse_dynamics_torque_reproduces_its_motion_in_the_fixed_step() {
    // Two independent routes: the inverse dynamics (run-time augmented Lagrangian with the
    // drive as a constraint) gives the torque; the fixed-size KKT solve and RK4 integrate
    // the motion it causes. The torque held at its mid-step value is a second-order
    // approximation, so halving h divides the error by about 4 (RK4's own error is
    // O(h^4), far below). The error converging at that order to zero is what shows the
    // two routes describe one motion; its size (6.7e-5 rad at h = 1 ms after one open-loop
    // revolution) is the hold's, and the bound 1e-4 only guards against a regression.
    let (coarse, fine) = (
        open_loop_tracking_error(2e-3),
        open_loop_tracking_error(1e-3),
    );
    assert!(
        fine < 1e-4 && (3.5..4.5).contains(&(coarse / fine)),
        "error {coarse:e} at h = 2e-3, {fine:e} at 1e-3 (ratio {})",
        coarse / fine
    );
}
