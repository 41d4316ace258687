//! Runs that cannot succeed stop early with their own typed error: a step size that
//! collapsed (projected steps beyond 10 x max_steps, tested from step 1000 on), a fixed step
//! that needs more steps than allowed and an output larger than memory allows (refused
//! before any work), a state that diverged (1e12 times its starting scale).

use std::time::Instant;

use mechanism::builtin::builtin;
use mechanism::{
    Error, IntegratorOptions, Interpreted, MAX_OUTPUT_BYTES, Method, SimulationOptions, Simulator,
    System, inverse_dynamics, simulate_recording,
};

fn options(t_end: f64, method: Method) -> SimulationOptions {
    SimulationOptions {
        t_end,
        integrator: IntegratorOptions {
            method,
            ..Default::default()
        },
        ..Default::default()
    }
}

fn set(system: &mut dyn System, name: &str, value: f64) {
    let k = system.info().parameter_index(name).expect("declared");
    assert!(system.set_parameter(k, value).is_ok());
}

#[test]
fn a_step_far_too_small_for_the_span_stops_after_a_thousand_steps_not_ten_million() {
    // g = 1e23 on a 0.1 m crank: the adaptive step is about 1e-13 s from the start, so 1 s
    // would take some 1e13 steps. Before the test the run spent 10 million steps (30 s and
    // more) to say "too many steps". The step is steady (it never was larger), so the
    // span, not a collapse, is named.
    let mut system = builtin("planar_four_bar").expect("built in");
    set(system.as_mut(), "g", 1e23);
    let started = Instant::now();
    let run = simulate_recording(system.as_ref(), &options(1.0, Method::Dop853)).expect("starts");
    let steps = run.trajectory.stats.steps;
    match run.failure {
        Some(Error::SpanTooLong {
            h,
            h_run,
            steps_needed,
            max_steps,
            ..
        }) => {
            assert!(h < 1e-9, "h = {h:e}");
            assert!(h >= 0.1 * h_run, "h = {h:e}, run mean {h_run:e}");
            assert!(steps_needed > 10.0 * max_steps as f64, "{steps_needed:e}");
        }
        other => panic!("expected SpanTooLong, got {other:?}"),
    }
    assert!((1000..1100).contains(&steps), "{steps} steps");
    assert!(
        started.elapsed().as_secs_f64() < 5.0,
        "{:?}",
        started.elapsed()
    );
}

#[test]
fn a_healthy_adaptive_run_is_not_stopped() {
    // The seed for 10 s at the CLI's tolerance (1216 steps): the step size varies over the
    // crank's turn but never collapses.
    let system = builtin("spatial_crank_slider").expect("built in");
    let mut o = options(10.0, Method::Dop853);
    (o.integrator.rtol, o.integrator.atol) = (1e-10, 1e-10);
    let run = simulate_recording(system.as_ref(), &o).expect("starts");
    assert!(run.failure.is_none(), "{:?}", run.failure);
    assert!(run.trajectory.stats.steps > 1000, "the test ran");
}

#[test]
fn a_fixed_step_that_cannot_reach_the_end_is_refused_before_any_work() {
    let system = builtin("planar_four_bar").expect("built in");
    for method in [
        Method::Rk4 { h: 1e-9 },
        Method::Hht {
            h: 1e-9,
            alpha: -0.05,
        },
    ] {
        let started = Instant::now();
        let o = options(10.0, method);
        let err = Simulator::new(system.as_ref(), &o).err().expect("refused");
        let text = err.to_string();
        match err {
            Error::FixedStepTooSmall {
                steps, max_steps, ..
            } => {
                assert_eq!(steps, 1e10);
                assert_eq!(max_steps, IntegratorOptions::default().max_steps);
            }
            other => panic!("expected FixedStepTooSmall, got {other}"),
        }
        assert!(
            text.contains("1.0e10 steps") && text.contains("at least 1e-6 s"),
            "{text}"
        );
        assert!(started.elapsed().as_secs_f64() < 0.5);
    }
    // Exactly max_steps steps is allowed.
    let o = SimulationOptions {
        t_end: 0.01,
        integrator: IntegratorOptions {
            method: Method::Rk4 { h: 1e-3 },
            max_steps: 10,
            ..Default::default()
        },
        ..Default::default()
    };
    assert!(Simulator::new(system.as_ref(), &o).is_ok());
}

#[test]
fn an_unstable_integration_is_named_divergence() {
    // x'' = -1e6 x with RK4 at h = 0.01 s: h sqrt(k) = 10, far outside RK4's stability
    // interval (2.8), so |x| grows some 400-fold per step.
    let system = Interpreted::from_source(
        "struct StiffSpring;\nparameters { k = 1e6; }\ncoordinates { x = 0.1; }\n\
         independent { x = 0.1; }\nkinetic = 1/2*der(x)^2;\npotential = 1/2*k*x^2;\n",
    )
    .expect("derives");
    let run = simulate_recording(&system, &options(1.0, Method::Rk4 { h: 0.01 })).expect("starts");
    match &run.failure {
        Some(Error::Diverged {
            coordinate,
            value,
            limit,
            t,
            ..
        }) => {
            assert_eq!(coordinate, "x");
            assert!(value.abs() > *limit, "{value:e} vs {limit:e}");
            assert!(*t < 0.1, "caught within a few steps: t = {t}");
        }
        other => panic!("expected Diverged, got {other:?}"),
    }
    // The samples before the divergence are kept.
    assert!(run.trajectory.len() >= 2);
}

#[test]
fn outputs_beyond_the_memory_limit_are_refused_before_any_work() {
    // 1e5 s at 100 samples per second: 1e7 samples of 21 values (within the sample count
    // limit) take 1.7 GB.
    let system = builtin("spatial_crank_slider").expect("built in");
    let o = options(1e5, Method::Dop853);
    let started = Instant::now();
    match Simulator::new(system.as_ref(), &o).err() {
        Some(Error::TooMuchOutput {
            samples,
            columns,
            bytes,
            limit,
        }) => {
            assert_eq!(
                (samples, columns, limit),
                (10_000_001, 21, MAX_OUTPUT_BYTES)
            );
            assert!((bytes - 1.68e9).abs() < 1e7, "{bytes:e}");
        }
        other => panic!("expected TooMuchOutput, got {other:?}"),
    }
    assert!(started.elapsed().as_secs_f64() < 0.5);
    // Inverse dynamics: 5e6 samples of 9 values, kept as vectors (1.4 GB).
    let pendulum = builtin("cartesian_pendulum").expect("built in");
    let drive = mechanism::parse_drive(pendulum.as_ref(), "x = 0.1*sin(t)").expect("drive");
    let times: Vec<f64> = (0..5_000_000).map(|i| i as f64 * 1e-2).collect();
    let err = inverse_dynamics(pendulum.as_ref(), vec![drive], &times, &Default::default())
        .expect_err("refused");
    assert!(
        matches!(err, Error::TooMuchOutput { columns: 9, .. }),
        "{err}"
    );
}

#[test]
fn non_finite_tolerances_are_refused() {
    let system = builtin("planar_four_bar").expect("built in");
    for (rtol, atol) in [(f64::INFINITY, 1e-10), (1e-8, f64::NAN)] {
        let mut o = options(1.0, Method::Dop853);
        o.integrator.rtol = rtol;
        o.integrator.atol = atol;
        let err = Simulator::new(system.as_ref(), &o).err().expect("refused");
        assert!(matches!(err, Error::InvalidOption { .. }), "{err}");
    }
}
