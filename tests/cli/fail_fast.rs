//! Runs that cannot succeed fail within a second with one line naming why: a step far too
//! small for the span, a fixed step too small for the span, a diverging state, an output too large.

use std::time::Instant;

use super::{assert_one_line_error, mechanism, out_dir};

/// Runs `args` and returns the output with the wall time it took (s).
fn timed(args: &[&str]) -> (std::process::Output, f64) {
    let started = Instant::now();
    let o = mechanism(args);
    (o, started.elapsed().as_secs_f64())
}

#[test]
fn a_step_far_too_small_for_the_span_fails_fast() {
    let dir = out_dir("collapse");
    let d = dir.to_str().unwrap();
    let args = [
        "simulate",
        "planar_four_bar",
        "--set",
        "g=1e23",
        "--t-end",
        "1",
        "--out",
        d,
    ];
    let (o, seconds) = timed(&args);
    assert_one_line_error(
        &o,
        "the time span is too long for this motion: its steps are a steady h = ",
    );
    assert_one_line_error(&o, "more steps, more than 10 times the limit of 10000000");
    assert!(seconds < 10.0, "{seconds} s");
}

#[test]
fn a_fixed_step_too_small_for_the_span_is_refused() {
    let (o, seconds) = timed(&[
        "simulate",
        "planar_four_bar",
        "--integrator",
        "rk4",
        "--step",
        "1e-9",
        "--out",
        out_dir("tiny-step").to_str().unwrap(),
    ]);
    assert_one_line_error(
        &o,
        "a fixed step of h = 1e-9 s over 10 s takes 1.0e10 steps",
    );
    assert_one_line_error(&o, "at least 1e-6 s");
    assert!(seconds < 5.0, "{seconds} s");
}

#[test]
fn a_diverging_integration_names_the_coordinate() {
    let dir = out_dir("diverge");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("stiff.mech");
    std::fs::write(
        &file,
        "struct StiffSpring;\nparameters { k = 1e6; }\ncoordinates { x = 0.1; }\n\
         independent { x = 0.1; }\nkinetic = 1/2*der(x)^2;\npotential = 1/2*k*x^2;\n",
    )
    .unwrap();
    let o = mechanism(&[
        "simulate",
        file.to_str().unwrap(),
        "--integrator",
        "rk4",
        "--step",
        "0.01",
        "--out",
        dir.join("out").to_str().unwrap(),
    ]);
    assert_one_line_error(&o, "the motion diverged at t = ");
    assert_one_line_error(&o, " of x is ");
}

#[test]
fn an_output_too_large_is_refused_with_its_size() {
    for (command, extra, file) in [
        ("simulate", vec![], "trajectory.csv"),
        ("inverse", vec!["--drive", "x = 0.1*sin(t)"], "inverse.csv"),
    ] {
        let dir = out_dir("too-large");
        let mut args = vec![command, "cartesian_pendulum", "--t-end", "1e5"];
        args.extend(extra);
        args.extend(["--out", dir.to_str().unwrap()]);
        let (o, seconds) = timed(&args);
        assert_one_line_error(&o, &format!("{file} would hold 10000001 samples of "));
        assert_one_line_error(
            &o,
            "GB, more than the 1 GB allowed: lower --samples-per-second",
        );
        assert!(seconds < 5.0, "{seconds} s");
    }
}
