//! Bad input: a velocity constraint not linear in the rates, a wheel whose axis is vertical,
//! a linearisation at a state that is not steady: each one error naming the cause.

use mechanism::{
    AssemblyOptions, Interpreted, Kinematic, SteadyOptions, assemble_from, linearize_steady,
};

use crate::common::{independent_with, load, source};

/// The sleigh with its constraint row replaced by `row`.
fn sleigh_with(row: &str) -> String {
    source("chaplygin_sleigh").replace(
        "-sin(theta)*der(x) + cos(theta)*der(y) - a*der(theta);",
        row,
    )
}

#[test]
fn a_row_not_linear_in_the_rates_is_refused_at_the_row() {
    let text = sleigh_with("der(x)*der(theta) + der(y);");
    let e = Interpreted::from_source(&text).unwrap_err();
    let message = e.to_string();
    println!("{message}");
    assert!(
        message.contains("velocity constraint 1 is not linear in the rates"),
        "{message}"
    );
    assert!(message.contains("der(x)"), "{message}");
    let l = e.location().expect("located");
    let line = text
        .lines()
        .position(|l| l.contains("der(x)*der(theta)"))
        .unwrap()
        + 1;
    assert_eq!((l.line, l.column), (line, 5));
    // The linear row next to it builds.
    assert!(Interpreted::from_source(&sleigh_with("der(x)*cos(theta) + der(y);")).is_ok());
}

#[test]
fn a_vertical_wheel_axis_is_refused() {
    let text = source("rolling_disc").replace("phi = 0.0; th = 0.0; }", "phi = pi/2; th = 0.0; }");
    let e = mechanism_codegen::parse_model_str(&text).unwrap_err();
    let message = e.to_string();
    println!("{message}");
    assert!(
        message.contains("the axis of the wheel `disc` is vertical"),
        "{message}"
    );
}

#[test]
fn a_state_that_is_not_steady_is_refused() {
    let system = load("whipple_bicycle", &[]);
    // Leaning 0.1 rad while running straight at 5 m/s: it falls.
    let mut independent = independent_with(&system, &[]);
    let lean = independent.iter_mut().find(|i| i.coordinate == 4).unwrap();
    lean.position = 0.1;
    let guess = &system.info().initial_guess;
    let s = assemble_from(
        &system,
        0.0,
        &independent,
        guess,
        &AssemblyOptions::default(),
    )
    .unwrap();
    let e = linearize_steady(&system, 0.0, &s.q, &s.qd, &SteadyOptions::default()).unwrap_err();
    let message = e.to_string();
    println!("{message}");
    assert!(
        message.starts_with("the state is not a steady motion: der2("),
        "{message}"
    );
}

#[test]
fn the_command_line_linearises_and_refuses_in_one_line() {
    let exe = env!("CARGO_BIN_EXE_mechanism");
    let file = format!(
        "{}/mechanisms/whipple_bicycle.mech",
        env!("CARGO_MANIFEST_DIR")
    );
    // Removed when the guard drops, also when an assertion fails.
    let guard = tempfile::Builder::new()
        .prefix("nonholonomic-cli-")
        .tempdir()
        .unwrap();
    let out = guard.path().join("out");
    let run = |extra: &[&str]| {
        std::process::Command::new(exe)
            .args(["linearize", &file, "--out"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap()
    };
    let ok = run(&["--set", "v=5"]);
    let stdout = String::from_utf8_lossy(&ok.stdout);
    println!("{stdout}");
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    assert!(stdout.contains("structural zero eigenvalues (6): x, y, psi, thR, thF, der(thR)"));
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("linearization.json")).unwrap())
            .unwrap();
    let eigenvalues = json["eigenvalues_without_structural_zeros"]
        .as_array()
        .unwrap();
    // v = 5 m/s in Table 2: the castering mode first.
    assert!((eigenvalues[0][0].as_f64().unwrap() + 14.0783896927982).abs() < 1e-10);
    assert_eq!(json["eigenvalues"].as_array().unwrap().len(), 10);
    assert_eq!(json["state_matrix"].as_array().unwrap().len(), 10);
    let bad = run(&["--init", "phi=0.1"]);
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert_eq!(bad.status.code(), Some(1));
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(stderr.contains("not a steady motion"), "{stderr}");
}
