//! Assembly: consistent initial states and the typed errors of the position Newton.

use crate::common::{CrankSlider, FourBar, Pendulum};
use mechanism::{AssemblyOptions, Error, Independent, assemble, assemble_from};

/// ERRATA item 2: at phi = 0, gamma0 = acos((h + l1)/l2), beta0 = asin(d/(l2 sin gamma0)),
/// x_c0 = 0.2 m; the rates follow from Phi_q q' = 0 with phi' = 2 pi.
#[test]
fn seed_initial_state_matches_closed_forms() {
    let s = CrankSlider::seed();
    let st = assemble(&s, 0.0, &AssemblyOptions::default()).unwrap();
    let (h, l1, l2, d): (f64, f64, f64, f64) = (0.12, 0.08, 0.3, 0.1);
    let g0 = ((h + l1) / l2).acos();
    let b0 = (d / (l2 * g0.sin())).asin();
    println!(
        "assembled q = {:?}, closed form beta0 = {b0}, gamma0 = {g0}",
        st.q
    );
    assert_eq!(st.q[0], 0.0);
    assert!((st.q[1] - b0).abs() < 1e-14, "beta0 {} vs {b0}", st.q[1]);
    assert!((st.q[2] - g0).abs() < 1e-14, "gamma0 {} vs {g0}", st.q[2]);
    assert!((st.q[3] - 0.2).abs() < 1e-14, "x_c0 {}", st.q[3]);
    // Rates: at phi = 0, f3' = -l1 sin(phi) phi' + l2 sin(gamma) gamma' = 0 gives gamma' = 0;
    // f2' = -l1 cos(phi) phi' + l2 sin(g) cos(b) beta' = 0 gives beta' = l1 phi'/(l2 sg cb);
    // f1' = l2 cos(g) cos(b) gamma' - l2 sg sb beta' - x_c' = 0 gives x_c' = -l2 sg sb beta'.
    let w = 2.0 * std::f64::consts::PI;
    let bd = l1 * w / (l2 * g0.sin() * b0.cos());
    assert!((st.qd[0] - w).abs() < 1e-15);
    assert!((st.qd[1] - bd).abs() < 1e-13, "beta' {} vs {bd}", st.qd[1]);
    assert!(st.qd[2].abs() < 1e-13);
    assert!((st.qd[3] + l2 * g0.sin() * b0.sin() * bd).abs() < 1e-13);
}

#[test]
fn four_bar_assembles_on_the_declared_branch() {
    let s = FourBar::crank_rocker();
    let st = assemble(&s, 0.0, &AssemblyOptions::default()).unwrap();
    // C = D + l3 (cos th3, sin th3) must lie above the x-axis, and |C - B| = l2.
    let c = (0.35 + 0.3 * st.q[2].cos(), 0.3 * st.q[2].sin());
    assert!(c.1 > 0.0);
    let b = (0.1 * st.q[0].cos(), 0.1 * st.q[0].sin());
    assert!(((c.0 - b.0).hypot(c.1 - b.1) - 0.4).abs() < 1e-15);
    // Circle intersection by hand (see the test-system notes): th2 = 0.52353719685628..., th3 = 1.58272168743425...
    assert!(
        (st.q[1] - 0.5235371968562865).abs() < 1e-12
            && (st.q[2] - 1.5827216874342542).abs() < 1e-12
    );
}

#[test]
fn newton_failure_is_a_typed_error() {
    let s = CrankSlider::seed();
    let opts = AssemblyOptions {
        max_iterations: 2,
        ..Default::default()
    };
    match assemble(&s, 0.0, &opts) {
        Err(Error::NewtonDidNotConverge {
            iterations,
            residual,
            q,
            ..
        }) => {
            assert_eq!(iterations, 2);
            assert!(residual > 1e-12 && residual.is_finite() && q.len() == 4);
        }
        other => panic!("expected NewtonDidNotConverge, got {other:?}"),
    }
}

#[test]
fn unreachable_position_is_reported_with_its_residual_and_rows() {
    // The locking four-bar cannot reach th1 = pi (|BD| = 0.55 > l2 + l3 = 0.5): Newton ends
    // at the least-squares point where coupler and rocker are in line, 0.05 m short. The
    // crank reaches th1 <= th1* = acos(-0.625) only: the given value is out of reach, and
    // the nearest reachable value is named.
    let s = FourBar::locking();
    let ind = [Independent {
        coordinate: 0,
        position: std::f64::consts::PI,
        velocity: 0.0,
    }];
    let err = assemble_from(
        &s,
        0.0,
        &ind,
        &s.info.initial_guess,
        &AssemblyOptions::default(),
    )
    .unwrap_err();
    match &err {
        Error::GivenOutOfReach {
            residual,
            rows,
            values,
            ..
        } => {
            // The gap is |BD| - (l2 + l3) = 0.05 m, shared between the x and y rows; Newton
            // stalls near (not exactly at) that least-squares point, within 10 %.
            assert!(*residual > 0.02 && *residual <= 0.055, "{err}");
            assert!(!rows.is_empty(), "{err}");
            let (name, given, th1) = &values[0];
            assert_eq!((name.as_str(), *given), ("th1", std::f64::consts::PI));
            // Reachable (cos th1 >= -0.625) and at the edge of the reach: the free
            // iteration moves th1 back from pi by about its share of the 0.05 m gap.
            let th1 = *th1;
            let edge = (-0.625_f64).acos();
            assert!(th1 <= edge + 1e-6 && th1 > edge - 0.2, "{err}");
        }
        other => panic!("expected GivenOutOfReach, got {other:?}"),
    }
    // With the ground link stretched to d = 2 no crank angle near these closes the loop
    // (|BD| >= 1.8 > 0.5): the constraints themselves cannot be met.
    let mut far = FourBar::locking();
    far.p[6] = 2.0;
    let err = assemble_from(
        &far,
        0.0,
        &ind,
        &far.info.initial_guess,
        &AssemblyOptions::default(),
    )
    .unwrap_err();
    assert!(
        matches!(err, Error::ConstraintsUnsatisfiable { .. }),
        "{err}"
    );
}

/// Issue 53, item 12: x = 1.5 is out of reach of a pendulum of length 1, and the message
/// says so (before: "start from a closer guess"). x = 0.5 from the guess y = 0, on the
/// symmetry line where Phi_y = 0 and Newton cannot move, is reachable (y = -+0.866): there
/// the residual has a maximum, not a floor, and the closer guess is the right advice.
#[test]
fn a_given_value_out_of_reach_is_told_from_a_guess_newton_cannot_leave() {
    let mut s = Pendulum::new(0.3);
    let at = |x: f64| {
        [Independent {
            coordinate: 0,
            position: x,
            velocity: 0.0,
        }]
    };
    let options = AssemblyOptions::default();
    let err = assemble_from(&s, 0.0, &at(1.5), &[1.5, -0.5], &options).unwrap_err();
    match &err {
        Error::GivenOutOfReach {
            values, residual, ..
        } => {
            // |Phi| is least at y = 0, x^2 - l^2 = 1.25; Newton stops within 1e-4 of it, where
            // y^2 adds less than 1e-8.
            assert!((residual - 1.25).abs() < 1e-8, "{err}");
            // The nearest reachable x is l = 1 (to the 7 digits kept).
            assert_eq!(values, &[("x".to_string(), 1.5, 1.0)]);
        }
        other => panic!("expected GivenOutOfReach, got {other:?}"),
    }
    let err = assemble_from(&s, 0.0, &at(0.5), &[0.5, 0.0], &options).unwrap_err();
    assert!(matches!(err, Error::NewtonDidNotConverge { .. }), "{err}");
    assert!(
        err.to_string().contains("start from a closer guess"),
        "{err}"
    );
    // With l = 2 the same x is within reach.
    s.p[1] = 2.0;
    let state = assemble_from(&s, 0.0, &at(1.5), &[1.5, -0.5], &options).unwrap();
    assert!((state.q[1] + (4.0_f64 - 2.25).sqrt()).abs() < 1e-12);
}

#[test]
fn redundant_constraints_assemble_and_their_mobility_is_reported() {
    // The pendulum's rod constraint declared twice: rank 1, one redundant row, one degree
    // of freedom (Grubler's n - m says 0).
    let s = Pendulum::redundant();
    let state = assemble(&s, 0.0, &AssemblyOptions::default()).unwrap();
    let mob = mechanism::mobility(&s, 0.0, &state.q).unwrap();
    assert_eq!((mob.n, mob.m, mob.rank), (2, 2, 1));
    assert_eq!((mob.degrees_of_freedom, mob.grubler), (1, 0));
    assert_eq!(mob.redundant_rows, vec![1]);
    assert_eq!(mob.indeterminate_rows, vec![0, 1]);
}

#[test]
fn an_independent_set_that_leaves_coordinates_free_is_reported() {
    // No independent coordinate: 3 dependent coordinates, 2 constraints.
    let s = FourBar::crank_rocker();
    let err = assemble_from(
        &s,
        0.0,
        &[],
        &s.info.initial_guess,
        &AssemblyOptions::default(),
    )
    .unwrap_err();
    match err {
        Error::IndependentSetDoesNotDetermine {
            dependent, rank, ..
        } => assert_eq!((dependent, rank), (3, 2)),
        other => panic!("{other:?}"),
    }
    // An index out of range is an unknown driver.
    let ind = [Independent {
        coordinate: 7,
        position: 0.0,
        velocity: 0.0,
    }];
    assert!(matches!(
        assemble_from(
            &s,
            0.0,
            &ind,
            &s.info.initial_guess,
            &AssemblyOptions::default()
        ),
        Err(Error::UnknownDriver {
            coordinate: 7,
            n: 3
        })
    ));
}

/// Two routes to the same consistent state: by default a square, well-conditioned Phi_v
/// is solved by LU (`conditioned_solve`), and a rank tolerance of 1e-6 sends the same
/// steps through the SVD (LU is then not used: its certificate, kappa < 1e7, would not
/// imply full rank at that tolerance). Both solve systems of condition below 100 with
/// backward-stable factorisations and stop at the same Newton tolerance, so the states
/// agree to a few units of round-off of q and q' (1e-12 leaves a margin of 100 over kappa
/// eps |x|).
#[test]
fn lu_and_svd_routes_assemble_the_same_state() {
    let svd_route = AssemblyOptions {
        rank_tolerance: 1e-6,
        ..Default::default()
    };
    let seed = CrankSlider::seed();
    let four_bar = FourBar::crank_rocker();
    for (name, lu, svd) in [
        (
            "seed",
            assemble(&seed, 0.0, &AssemblyOptions::default()).unwrap(),
            assemble(&seed, 0.0, &svd_route).unwrap(),
        ),
        (
            "four-bar",
            assemble(&four_bar, 0.0, &AssemblyOptions::default()).unwrap(),
            assemble(&four_bar, 0.0, &svd_route).unwrap(),
        ),
    ] {
        for (a, b) in lu.q.iter().zip(&svd.q).chain(lu.qd.iter().zip(&svd.qd)) {
            assert!(
                (a - b).abs() <= 1e-12 * (1.0 + b.abs()),
                "{name}: {a} vs {b}"
            );
        }
    }
}
