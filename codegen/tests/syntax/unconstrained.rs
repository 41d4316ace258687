//! A declaration without constraint rows needs no `independent`: every coordinate is
//! independent, at its declared value, at rest. With rows it still does, and the message
//! naming the candidates fits a line however many there are.

use mechanism_codegen::{Error, derive, parse_model_str};

/// `n` free particles on springs: T = 1/2 sum q_i'^2, Pi = sum q_i^2, with `rows` written
/// as constraints.
fn particles(n: usize, rows: &str) -> String {
    let coordinates: String = (1..=n).map(|i| format!("q{i} = 0.{i}; ")).collect();
    let rates: Vec<String> = (1..=n).map(|i| format!("der(q{i})^2")).collect();
    let springs: Vec<String> = (1..=n).map(|i| format!("q{i}^2")).collect();
    format!(
        "struct Free;\ncoordinates {{ {coordinates}}}\nkinetic = 1/2*({});\npotential = {};\n{rows}",
        rates.join(" + "),
        springs.join(" + ")
    )
}

#[test]
fn an_unconstrained_declaration_frees_every_coordinate_at_its_value() {
    let mut model = parse_model_str(&particles(3, "")).unwrap();
    let given: Vec<(&str, f64, f64)> = model
        .independent
        .iter()
        .map(|i| {
            let name = model.coordinates[i.coordinate].name.as_str();
            (name, i.position, i.velocity)
        })
        .collect();
    assert_eq!(
        given,
        [("q1", 0.1, 0.0), ("q2", 0.2, 0.0), ("q3", 0.3, 0.0)]
    );
    let eqs = derive(&mut model).unwrap();
    assert_eq!((eqs.n, eqs.m), (3, 0));
}

#[test]
fn a_constrained_declaration_still_needs_independent_and_lists_few_candidates() {
    let e = parse_model_str(&particles(40, "constraints { q1 - q2; }")).unwrap_err();
    let Error::Declaration { .. } = &e else {
        panic!("{e:?}");
    };
    let text = e.to_string();
    assert!(
        text.contains(
            "set 39 more of q1, q2, q3, q4, q5, q6, q7, q8, q9, q10, q11, q12, ... (28 more)"
        ),
        "{text}"
    );
    assert!(text.len() < 400, "{} bytes: {text}", text.len());
}

/// Velocity rows are rows: a sleigh-like declaration with one velocity row and no
/// `independent` is asked for the n - m coordinates whose rates are free, not handed an
/// `independent` it never wrote that names every coordinate.
#[test]
fn velocity_rows_count_as_rows() {
    let text = particles(3, "velocity_constraints { der(q1) - der(q2); }");
    let e = parse_model_str(&text).unwrap_err();
    let text = e.to_string();
    assert!(
        text.contains("n - m = 3 - 1 = 2 degrees of freedom but `independent` sets 0 (none)"),
        "{text}"
    );
}
