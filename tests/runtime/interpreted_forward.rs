//! The interpreter's generated forward dynamics (`System::forward_dynamics`, the tape of
//! `Role::ForwardDynamics`) against the dense route (M and the bias evaluated, M factored by
//! nalgebra's Cholesky) and, for the Panda, against the macro's `forward_dynamics`: on the
//! Panda (the factorisation M = L^T D L chosen) and on a 40-link chain (the articulated-body
//! recursion chosen), at random states with random efforts.

use crate::common::chain_source;
use mechanism::builtin::{Panda, builtin_source};
use mechanism::{Evaluation, Interpreted, Kinematic, Mechanism, System};
use mechanism_codegen::{Role, compile_forward_dynamics, derive, parse_model_str};
use nalgebra::{DVector, SVector};

/// A small deterministic generator of values in [-1, 1) (xorshift64*).
struct Random(u64);

impl Random {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
        2.0 * (bits as f64 / (1u64 << 53) as f64) - 1.0
    }

    fn vector(&mut self, n: usize, scale: f64) -> Vec<f64> {
        (0..n).map(|_| scale * self.next()).collect()
    }
}

/// Checks the generated q'' of `system` at `states` random states with random efforts: its
/// backward error |M q'' - (u - b)| against the dense M and b of the evaluation, and its
/// distance from the dense Cholesky solve, both to round-off; returns the largest q''.
fn check_against_dense(system: &Interpreted, states: usize, seed: u64) -> Vec<Vec<f64>> {
    let n = system.info().n();
    let mut random = Random(seed);
    let mut e = Evaluation::zeros(n, 0);
    let (mut qdd, mut forces) = (vec![0.0; n], vec![0.0; n]);
    let mut solutions = Vec::new();
    for k in 0..states {
        let (q, qd, u) = (
            random.vector(n, 1.5),
            random.vector(n, 2.0),
            random.vector(n, 5.0),
        );
        let solved = system.forward_dynamics(0.0, &q, &qd, &u, &mut qdd, &mut forces);
        assert_eq!(solved, Some(true), "state {k}");
        system.evaluate(0.0, &q, &qd, &mut e);
        assert_eq!(forces.as_slice(), e.forces.as_slice(), "tau at state {k}");
        // u - b = u + tau - C q' - g.
        let rhs = DVector::from_fn(n, |i, _| u[i] + e.forces[i] - e.coriolis[i] - e.gravity[i]);
        let x = DVector::from_column_slice(&qdd);
        // Backward error: a stable solve leaves a residual of a few eps times
        // |M| |q''| + |u - b| (n-term sums in f64, n <= 40: 1e-12 is ~100 n eps, a wrong
        // route misses by O(1)).
        let residual = &e.mass * &x - &rhs;
        let scale = e.mass.abs() * x.abs() + rhs.abs();
        for i in 0..n {
            assert!(
                residual[i].abs() <= 1e-12 * scale[i],
                "state {k}, row {i}: residual {:e} of {:e}",
                residual[i],
                scale[i]
            );
        }
        // Forward error against the dense route: both solves are backward stable, so they
        // differ by at most cond(M) times the backward errors; cond(M) is computed.
        let dense = e
            .mass
            .clone()
            .cholesky()
            .expect("M positive definite")
            .solve(&rhs);
        let eig = e.mass.clone().symmetric_eigen().eigenvalues;
        let cond = eig.max() / eig.min();
        let err = (&x - &dense).amax();
        assert!(
            err <= 1e-13 * cond * dense.amax().max(1.0),
            "state {k}: q'' differs by {err:e} (cond(M) = {cond:e})"
        );
        solutions.push(qdd.clone());
    }
    solutions
}

#[test]
fn the_pandas_generated_forward_dynamics_agrees_with_the_dense_route_and_the_macro() {
    let panda = Interpreted::from_source(builtin_source("panda").unwrap()).unwrap();
    let solutions = check_against_dense(&panda, 20, 0x5eed_0001);
    // The macro's forward dynamics at the same states (the same generator sequence).
    let robot = Panda::default();
    let mut random = Random(0x5eed_0001);
    type V = SVector<f64, 7>;
    for (k, ours) in solutions.iter().enumerate() {
        let q = V::from_column_slice(&random.vector(7, 1.5));
        let qd = V::from_column_slice(&random.vector(7, 2.0));
        let u = V::from_column_slice(&random.vector(7, 5.0));
        let theirs = robot.forward_dynamics(0.0, &q, &qd, &u).unwrap();
        // The same program run by the tape and by the emitted code, its cache slots
        // numbered apart: the same operations, so the same q'' to a few ulps of its largest
        // entry (cond(M) < 1e3 here amplifies no difference in the inputs, there is none).
        let scale = theirs.amax().max(1.0);
        for i in 0..7 {
            assert!(
                (ours[i] - theirs[i]).abs() <= 1e-14 * scale,
                "state {k}, q''[{i}]: tape {} against macro {}",
                ours[i],
                theirs[i]
            );
        }
    }
}

#[test]
fn a_long_chains_articulated_body_forward_dynamics_agrees_with_the_dense_route() {
    let text = chain_source(40);
    // The articulated-body recursion is the route compiled: it counts O(n) operations
    // (about 400 per link), the factorisation of the dense M more than 1,500 per link at
    // this length (n^3 / 6 multiply-adds and M's O(n^2) entries).
    let mut model = parse_model_str(&text).unwrap();
    let eqs = derive(&mut model).unwrap();
    let routines = compile_forward_dynamics(&mut model, &eqs).unwrap().unwrap();
    let ops = routines
        .program(Role::ForwardDynamics)
        .unwrap()
        .op_counts()
        .total();
    assert!(ops < 800 * 40, "{ops} operations: not the recursion");
    let chain = Interpreted::from_source(&text).unwrap();
    check_against_dense(&chain, 10, 0x5eed_0002);
}

#[test]
fn a_mechanism_with_constraint_rows_has_no_generated_forward_dynamics() {
    let slider = Interpreted::from_source(builtin_source("spatial_crank_slider").unwrap()).unwrap();
    let n = slider.info().n();
    let (q, mut qdd, mut forces) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let solved = slider.forward_dynamics(0.0, &q, &q, &q, &mut qdd, &mut forces);
    assert_eq!(solved, None);
}

#[test]
fn a_singular_mass_matrix_is_refused_and_the_run_stops_with_the_dense_routes_error() {
    // The second link turns about its own origin, where its only mass sits: its joint
    // moves no mass, M's second row and column vanish.
    let text = "pub struct IdleJoint;
        parameters { g = 9.81; }
        gravity = [0, 0, -g];
        link arm { joint = revolute(a, [0, 0, 1]); mass = 2; com = [0.5, 0, 0];
                   inertia = [[0.01, 0, 0], [0, 0.02, 0], [0, 0, 0.03]]; }
        link hub { parent = arm; joint = revolute(b, [0, 0, 1]); xyz = [1, 0, 0]; mass = 1; }";
    let system = Interpreted::from_source(text).unwrap();
    let (q, qd) = ([0.3, -0.4], [0.5, 1.0]);
    let (mut qdd, mut forces) = ([0.0; 2], [0.0; 2]);
    let solved = system.forward_dynamics(0.0, &q, &qd, &[1.0, 0.0], &mut qdd, &mut forces);
    assert_eq!(solved, Some(false));
    let options = mechanism::SimulationOptions {
        t_end: 0.1,
        initial: mechanism::InitialState::Consistent {
            q: q.to_vec(),
            qd: qd.to_vec(),
        },
        ..Default::default()
    };
    match mechanism::simulate(&system, &options) {
        Err(mechanism::Error::UndeterminedMotion { coordinates, .. }) => {
            assert_eq!(coordinates, ["b"])
        }
        other => panic!("expected an undetermined motion, got {other:?}"),
    }
}

/// A run of a 45-link chain (n past the 40 coordinates the dense LU routes serve) solves
/// every integration stage by the generated forward dynamics: only the start and the output
/// samples (which record T and Pi from the evaluation) take the dense route, one solve each.
/// The Panda (n = 7) stays on the dense routes, which cost as little at that size.
#[test]
fn a_long_chains_run_takes_the_generated_forward_dynamics_at_every_stage() {
    let chain = Interpreted::from_source(&chain_source(45)).unwrap();
    let options = mechanism::SimulationOptions {
        t_end: 0.05,
        ..Default::default()
    };
    let tr = mechanism::simulate(&chain, &options).unwrap();
    let samples = tr.len();
    assert!(tr.stats.generated_solves > 0);
    assert_eq!(
        tr.stats.generated_solves + samples + 1,
        tr.stats.rhs_evaluations,
        "{samples} samples"
    );
    let panda = Interpreted::from_source(builtin_source("panda").unwrap()).unwrap();
    let tr = mechanism::simulate(&panda, &options).unwrap();
    assert_eq!(tr.stats.generated_solves, 0);
}
