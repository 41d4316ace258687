//! The step loop allocates nothing: a counting global allocator (counting only on this
//! test's thread, while armed) sees zero allocations over hundreds of steps after warm-up,
//! for every integrator and stabilisation, on the compiled and the interpreted routes (a
//! step that records a singular passage allocates that record, and is not counted), with
//! velocity constraints too (the bicycle); and the constraint rows' tangent of the
//! linearisation.

use crate::common::{CrankSlider, FourBar};
use mechanism::builtin::builtin_source;
use mechanism::{
    ConstraintTangent, Independent, InitialState, IntegratorOptions, Interpreted, Kinematic,
    Method, SimulationOptions, Simulator, Stabilization, System, assemble,
};

/// Where a case starts: its declared state, except for the Whipple bicycle. Declared
/// upright and straight at 5 m/s, it is in steady motion, which the integrator crosses in a
/// few steps as long as nothing else excites it; its lean rate is kicked by 0.5 rad/s (the
/// nonholonomic tests' kick) so that its steps resolve a motion and record samples.
fn initial_state(system: &dyn System) -> InitialState {
    let info = system.info();
    if info.name != "WhippleBicycle" {
        return InitialState::Declared;
    }
    InitialState::Independent(
        info.independent
            .iter()
            .map(|i| Independent {
                velocity: if info.coordinates[i.coordinate] == "phi" {
                    0.5
                } else {
                    i.velocity
                },
                ..*i
            })
            .collect(),
    )
}

fn allocations_in_steps(
    system: &dyn System,
    method: Method,
    stabilization: Stabilization,
    steps: usize,
) -> (usize, usize) {
    let o = SimulationOptions {
        t_end: 100.0,
        initial: initial_state(system),
        stabilization,
        integrator: IntegratorOptions {
            method,
            rtol: 1e-9,
            atol: 1e-11,
            ..Default::default()
        },
        ..Default::default()
    };
    let mut sim = Simulator::new(system, &o).unwrap();
    for _ in 0..20 {
        sim.step().unwrap();
    }
    let before = sim.trajectory().len();
    // A step that records a singular passage allocates its record (A02 passes one about
    // every second); every other step must allocate nothing, and most steps are such.
    let (mut made, mut quiet) = (0, 0);
    for _ in 0..steps {
        let passages = sim.trajectory().singular_passages.len();
        let counted = mechanism_test_support::allocations();
        sim.step().unwrap();
        let step = mechanism_test_support::allocations() - counted;
        if sim.trajectory().singular_passages.len() == passages {
            made += step;
            quiet += 1;
        }
    }
    assert!(
        quiet >= steps / 2,
        "{quiet} of {steps} steps recorded no passage"
    );
    (made, sim.trajectory().len() - before)
}

#[test]
fn step_loop_allocates_nothing() {
    let seed = CrankSlider::seed();
    let four_bar = FourBar::crank_rocker();
    let cases: [(&dyn System, Method, Stabilization); 6] = [
        (&seed, Method::Dopri5, Stabilization::Projection),
        (&seed, Method::Dop853, Stabilization::Projection),
        (&four_bar, Method::Dop853, Stabilization::None),
        (
            &four_bar,
            Method::Dopri5,
            Stabilization::Baumgarte {
                alpha: 5.0,
                beta: 5.0,
            },
        ),
        (
            &four_bar,
            Method::Rk4 { h: 1e-3 },
            Stabilization::Projection,
        ),
        (
            &seed,
            Method::Hht {
                h: 1e-3,
                alpha: -0.05,
            },
            Stabilization::Projection,
        ),
    ];
    // Redundant rows (20 rows of rank 17): the augmented Lagrangian route, its banded
    // factorisation, the minimum-norm multipliers of every sample and the rank watch.
    let redundant = mechanism::builtin::builtin("planar_four_bar_bodies").unwrap();
    // The interpreted route runs its tapes in a register file of the thread: grown during
    // warm-up, then reused by every evaluation, the tangent of HHT among them.
    let interpreted: &dyn System =
        &Interpreted::from_source(builtin_source("spatial_crank_slider").unwrap()).unwrap();
    // A02 with N = 40 on both routes: a large system whose M and Phi_q are written and
    // read at their structural pattern only (the sparse evaluation and Jacobian, the fixed
    // row spans of the augmented Lagrangian, the projection and the rank watch).
    let chain = mechanism::builtin::builtin("n_four_bar").unwrap();
    let chain_interpreted: &dyn System =
        &Interpreted::from_source(builtin_source("n_four_bar").unwrap()).unwrap();
    // Velocity constraints: the Whipple bicycle's rolling rows, compiled and interpreted
    // (A q' + a among the rows of the projection and of the KKT solve).
    let bicycle = mechanism::builtin::builtin("whipple_bicycle").unwrap();
    let bicycle_interpreted: &dyn System =
        &Interpreted::from_source(builtin_source("whipple_bicycle").unwrap()).unwrap();
    // A02 with N = 10 and every coupler row declared twice: the banded direct route with
    // rows left out at every solve (the consistent gamma, the minimum-norm multipliers of
    // the samples), and the projection on the coordinates' side (m > n).
    let redundant_chain: &dyn System = &crate::banded_kkt::a02(10, true);
    // A driving row that moves with t: every stage solves the multipliers too, for the
    // power lambda . Phi_t that W integrates.
    let driven: &dyn System =
        &Interpreted::from_source(&crate::common::driven_slider_crank_source()).unwrap();
    // No constraint rows and n = 45 (past the dense LU routes' 40): every stage's q'' by
    // the generated forward dynamics' tape (`System::forward_dynamics`), the samples by the
    // evaluation.
    let link_chain: &dyn System =
        &Interpreted::from_source(&crate::common::chain_source(45)).unwrap();
    let cases: Vec<(&dyn System, Method, Stabilization)> = cases
        .into_iter()
        .chain([
            (link_chain, Method::Dop853, Stabilization::None),
            (bicycle.as_ref(), Method::Dop853, Stabilization::Projection),
            (
                bicycle_interpreted,
                Method::Dop853,
                Stabilization::Projection,
            ),
            (redundant_chain, Method::Dop853, Stabilization::Projection),
            (driven, Method::Dop853, Stabilization::Projection),
            (
                driven,
                Method::Hht {
                    h: 1e-3,
                    alpha: -0.05,
                },
                Stabilization::Projection,
            ),
            (chain.as_ref(), Method::Dop853, Stabilization::Projection),
            (chain_interpreted, Method::Dop853, Stabilization::Projection),
            // HHT's Newton matrix of A02 (n + m = 163) factored in its band.
            (
                chain.as_ref(),
                Method::Hht {
                    h: 1e-3,
                    alpha: -0.05,
                },
                Stabilization::Projection,
            ),
            (
                chain_interpreted,
                Method::Hht {
                    h: 1e-3,
                    alpha: -0.05,
                },
                Stabilization::Projection,
            ),
            (interpreted, Method::Dopri5, Stabilization::Projection),
            (
                interpreted,
                Method::Hht {
                    h: 1e-3,
                    alpha: -0.05,
                },
                Stabilization::Projection,
            ),
            (
                redundant.as_ref(),
                Method::Dop853,
                Stabilization::Projection,
            ),
            (
                redundant.as_ref(),
                Method::Hht {
                    h: 1e-3,
                    alpha: -0.05,
                },
                Stabilization::Projection,
            ),
        ])
        .collect();
    for (s, method, stab) in cases {
        let (n, samples) = allocations_in_steps(s, method, stab, 400);
        println!(
            "{} {method:?} {stab:?}: {n} allocations in 400 steps ({samples} samples recorded)",
            s.info().name
        );
        assert!(
            samples > 0,
            "the steps must record samples, so that the output path is exercised"
        );
        assert_eq!(n, 0, "{} {method:?} {stab:?}", s.info().name);
    }
}

#[test]
fn the_constraint_tangent_allocates_nothing() {
    // The linearisation's exact tangent of the rows (velocity rows too), on the
    // interpreter's tapes, after the register file has grown on a first call.
    let model =
        mechanism_codegen::parse_model_str(builtin_source("whipple_bicycle").unwrap()).unwrap();
    let system = Interpreted::for_linearization(model).unwrap();
    let (n, m) = (system.info().n(), system.info().m());
    let s = assemble(&system, 0.0, &Default::default()).unwrap();
    let qdd = vec![0.1; n];
    let mut out = ConstraintTangent::zeros(m, n);
    assert!(
        system
            .constraint_tangent(0.0, &s.q, &s.qd, &qdd, &mut out)
            .is_some()
    );
    let before = mechanism_test_support::allocations();
    for k in 0..100 {
        let t = 0.01 * f64::from(k);
        assert!(
            system
                .constraint_tangent(t, &s.q, &s.qd, &qdd, &mut out)
                .is_some()
        );
    }
    assert_eq!(mechanism_test_support::allocations() - before, 0);
    // The rows' tangent is not all zero: the rolling rows depend on the configuration.
    assert!(out.velocity.iter().any(|v| *v != 0.0));
}

#[test]
fn the_interpreted_floating_step_allocates_nothing() {
    // Solo12 with a floating base on the run-time route: between two samples (one step
    // each) nothing is allocated once the first step has grown the register file.
    let options = mechanism_codegen::UrdfOptions {
        file_name: "solo12.urdf".into(),
        floating: true,
        ..Default::default()
    };
    let urdf = include_str!("../../mechanisms/urdf/solo12.urdf");
    let text = mechanism_codegen::urdf_to_mech(urdf, &options).unwrap();
    let robot = mechanism::InterpretedFloating::from_text(&text).unwrap();
    let q0 = robot.neutral();
    let v0: Vec<f64> = (0..robot.nv()).map(|k| 0.1 * k as f64).collect();
    let mut counts = Vec::with_capacity(200);
    mechanism::simulate_interpreted_floating(&robot, (&q0, &v0), (0.1, 1e-3, 1), |_, _, _| {
        counts.push(mechanism_test_support::allocations())
    })
    .unwrap();
    assert_eq!(counts.len(), 101);
    let grown = counts.windows(2).skip(1).map(|w| w[1] - w[0]).max();
    assert_eq!(grown, Some(0), "{counts:?}");
}
