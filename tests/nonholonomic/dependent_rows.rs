//! Velocity rows that are a combination of the rows above them: a row that contradicts the
//! position rows (the time derivative of a position row with another right-hand side), one
//! that repeats them, and two velocity rows that contradict each other. Each is refused at
//! assembly, naming the rows; the command line says it in one line.

use mechanism::{Error, Interpreted, assemble};

/// A point (x, y) of mass m on the line y = x (a position row), with `rows` as its
/// velocity constraints.
fn on_a_line(rows: &str) -> String {
    format!(
        "pub struct OnALine;
parameters {{ m = 1.0; }}
coordinates {{ x = 0.0; y = 0.0; z = 0.0; }}
independent {{ x = 0.0; z = 0.0; der(x) = 1.0; }}
kinetic = m/2*(der(x)^2 + der(y)^2 + der(z)^2);
constraints {{ y - x; }}
velocity_constraints {{ {rows} }}
"
    )
}

/// The same with only x independent (z then follows from the velocity rows).
fn only_x(text: &str) -> String {
    text.replace(
        "independent { x = 0.0; z = 0.0; der(x) = 1.0; }",
        "independent { x = 0.0; der(x) = 1.0; }",
    )
}

fn assembly_error(text: &str) -> Error {
    let system = Interpreted::from_source(text).expect("derives");
    assemble(&system, 0.0, &Default::default()).expect_err("refused")
}

#[test]
fn a_velocity_row_that_contradicts_a_position_row_is_refused_naming_both() {
    // d/dt (y - x) = y' - x' = 0, but the row asks y' - x' = -0.5.
    let e = assembly_error(&on_a_line("der(y) - der(x) + 0.5;"));
    let message = e.to_string();
    println!("{message}");
    let Error::VelocityRowContradicts {
        row, of, mismatch, ..
    } = &e
    else {
        panic!("{e:?}")
    };
    // The velocity row (the second of m = 2 rows) against the position row.
    assert_eq!(row, "velocity constraint 1");
    assert_eq!(of, &["constraint 1"]);
    // a_2 - c a_1 with c = 1 (A_2 = A_1) and a_1 = Phi_t = 0: exactly the 0.5 declared.
    assert_eq!(*mismatch, 0.5);
    assert!(message.contains("contradicts constraint 1"), "{message}");
}

#[test]
fn a_velocity_row_that_repeats_the_position_rows_is_refused_as_redundant() {
    // 2 (y' - x') = 0: twice the time derivative of the position row.
    let e = assembly_error(&on_a_line("2*der(y) - 2*der(x);"));
    println!("{e}");
    let Error::VelocityRowRedundant { row, of, .. } = &e else {
        panic!("{e:?}")
    };
    assert_eq!(
        (row.as_str(), of.as_slice()),
        ("velocity constraint 1", &["constraint 1".to_string()][..])
    );
}

#[test]
fn two_velocity_rows_that_contradict_each_other_are_refused() {
    // z' = x' and z' = x' - 0.25: the second asks what the first forbids.
    // Only x is independent: z' follows from the first row.
    let text = only_x(&on_a_line("der(z) - der(x); 2*der(z) - 2*der(x) + 0.5;"));
    let e = assembly_error(&text);
    println!("{e}");
    let Error::VelocityRowContradicts {
        row, of, mismatch, ..
    } = &e
    else {
        panic!("{e:?}")
    };
    assert_eq!(
        (row.as_str(), of.as_slice()),
        (
            "velocity constraint 2",
            &["velocity constraint 1".to_string()][..]
        )
    );
    // 0.5 - 2 * 0.
    assert!((mismatch - 0.5).abs() <= 4.0 * f64::EPSILON, "{mismatch}");
}

#[test]
fn independent_velocity_rows_still_assemble() {
    // z' = x' + y' is not a combination of y' - x' = 0: the rates follow, z' = 2 x'.
    let text = only_x(&on_a_line("der(z) - der(x) - der(y);"));
    let system = Interpreted::from_source(&text).expect("derives");
    let s = assemble(&system, 0.0, &Default::default()).expect("assembles");
    // The least-squares solve by SVD: within a few ulps of the exact rates.
    for (got, want) in s.qd.iter().zip([1.0, 1.0, 2.0]) {
        assert!(
            (got - want).abs() <= 4.0 * f64::EPSILON * want,
            "{:?}",
            s.qd
        );
    }
}

#[test]
fn the_command_line_refuses_a_contradicting_row_in_one_line() {
    // Removed when the guard drops, also when an assertion fails.
    let guard = tempfile::Builder::new()
        .prefix("contradicting-row-")
        .tempdir()
        .unwrap();
    let dir = guard.path();
    let file = dir.join("on_a_line.mech");
    std::fs::write(&file, on_a_line("der(y) - der(x) + 0.5;")).unwrap();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_mechanism"))
        .arg("simulate")
        .arg(&file)
        .arg("--out")
        .arg(dir.join("out"))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.lines().count(), 1, "{stderr}");
    assert!(
        stderr.contains("the velocity row `velocity constraint 1` contradicts constraint 1"),
        "{stderr}"
    );
}

/// A velocity row whose coefficients all vanish at the assembled configuration (sin(x) = 0
/// there) restricts nothing and is refused as redundant; the message says that the row
/// vanishes rather than naming an empty list of rows.
#[test]
fn a_velocity_row_that_vanishes_is_refused_saying_so() {
    let text = "pub struct Vanishing;
parameters { m = 1.0; }
coordinates { x = 0.0; y = 0.0; }
independent { x = 0.0; y = 0.0; der(x) = 1.0; der(y) = 0.0; }
kinetic = m/2*(der(x)^2 + der(y)^2);
velocity_constraints { sin(x)*der(y); }
";
    let e = assembly_error(text);
    let message = e.to_string();
    let Error::VelocityRowRedundant { of, .. } = &e else {
        panic!("{e:?}")
    };
    assert!(of.is_empty());
    assert!(
        message.contains("coefficients of the rates all vanish"),
        "{message}"
    );
}
