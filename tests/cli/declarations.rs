//! Declarations whose numbers or physics cannot be right, given to the command-line tool as
//! `.mech` files: one line naming the file, the line and column and the rule, exit status
//! 1, and no output folder. Accepted, each would give a silently wrong model, or a run that
//! ends in a step-size underflow or a misleading diagnosis.

use super::{assert_one_line_error, mechanism, out_dir};

/// The library's Cartesian pendulum with `from` replaced by `to`, written to a file.
fn pendulum_with(name: &str, from: &str, to: &str) -> std::path::PathBuf {
    let text = include_str!("../../mechanisms/cartesian_pendulum.mech");
    assert!(text.contains(from), "{from}");
    let dir = out_dir(&format!("decl-{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.mech"));
    std::fs::write(&path, text.replace(from, to)).unwrap();
    path
}

#[test]
fn bad_declarations_fail_with_their_location_and_exit_status_1() {
    let t = "kinetic = 1/2*m*(der(x)^2 + der(y)^2);";
    let cases = [
        (
            "quartic",
            t,
            "kinetic = 1/2*m*(der(x)^4 + der(y)^2);",
            ":22:1: the kinetic energy is not a quadratic form in the rates",
        ),
        (
            "negative",
            t,
            "kinetic = -3*der(x)^2 + 1/2*m*der(y)^2;",
            ":22:1: the kinetic energy can be negative",
        ),
        (
            "overflow",
            t,
            "kinetic = 1/2*m*1e200*1e200*(der(x)^2 + der(y)^2);",
            ":22:11: the constants in `1/2*m*1e200*1e200*(der(x)^2 + der(y)^2)` overflow",
        ),
        (
            "dependent_rate",
            "independent { x = 0.479426; der(x) = 0.0; }",
            "independent { x = 0.479426; der(y) = 1.0; }",
            ":21:33: `der(y)` is given in `independent`, but `y` is not an independent coordinate",
        ),
    ];
    for (name, from, to, needle) in cases {
        let file = pendulum_with(name, from, to);
        let out = out_dir(&format!("decl-{name}-out"));
        let o = mechanism(&[
            "simulate",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_one_line_error(&o, needle);
        assert!(
            !out.join("trajectory.csv").exists(),
            "{name}: no trajectory"
        );
    }
    // The derivation's own overflow: Pi = 1e308 y^2 is finite, its gradient is not.
    let file = pendulum_with("gradient", "potential = m*g*y;", "potential = 1e308*y^2;");
    let o = mechanism(&["equations", file.to_str().unwrap()]);
    assert_one_line_error(
        &o,
        "deriving the equations of `CartesianPendulum` multiplies or adds constants beyond the largest f64",
    );
}

/// The derivation's budgets: over one, one line naming the figure, the budget and the
/// variable that raises it; raised to the figure named, the same file runs.
#[test]
fn the_derivation_budget_is_named_and_can_be_raised() {
    let file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/mechanisms/planar_four_bar.mech"
    );
    let run = |variable: &str, budget: &str| {
        let out = out_dir(&format!("budget-{variable}-{budget}"));
        assert_cmd::Command::cargo_bin("mechanism")
            .unwrap()
            .env(variable, budget)
            .args([
                "simulate",
                file,
                "--t-end",
                "0.1",
                "--out",
                out.to_str().unwrap(),
            ])
            .output()
            .unwrap()
    };
    // The figure the message names, as a number.
    let named = |o: &std::process::Output, before: &str| -> u64 {
        let text = super::stderr(o);
        let at = text.find(before).unwrap_or_else(|| panic!("{text}")) + before.len();
        text[at..]
            .split(|c: char| !c.is_ascii_digit())
            .next()
            .and_then(|d| d.parse().ok())
            .unwrap_or_else(|| panic!("{text}"))
    };
    let o = run("MECHANISM_MAX_ENTRIES", "1");
    assert_one_line_error(&o, "beyond its budget of 1; declare fewer coordinates");
    let entries = named(&o, "needs dM/dq with ");
    // The four-bar's M (3 coordinates) depends on th2 and th3 in some entries: more than
    // one nonzero of dM/dq, and fewer than the dense 3^3.
    assert!(entries > 1 && entries < 27, "{entries}");
    assert!(super::stderr(&o).contains(&format!("MECHANISM_MAX_ENTRIES={entries}")));
    assert_eq!(
        run("MECHANISM_MAX_ENTRIES", &entries.to_string())
            .status
            .code(),
        Some(0)
    );

    let o = run("MECHANISM_MAX_WORK", "100");
    assert_one_line_error(
        &o,
        "units of work (building expressions), beyond its budget of 100",
    );
    let raised = named(&o, "MECHANISM_MAX_WORK=");
    assert!(raised > 100, "{raised}");

    let o = run("MECHANISM_MAX_WORK", "lots");
    assert_one_line_error(&o, "MECHANISM_MAX_WORK=lots is not a positive whole number");
}

/// The size budget of the derivation's expressions: a body turned by 8 chained rotations
/// needs far less than 2^24 but more than 2,000; under that budget, one line naming the size
/// reached, the budget and the variable that raises it.
#[test]
fn the_expression_budget_is_named() {
    let axes = ["z", "x", "y"];
    let k = 8;
    let coordinates: String = (0..k).map(|i| format!("a{i} = 0.{}; ", i + 1)).collect();
    let independent: String = (0..k)
        .map(|i| format!("a{i} = 0.{}; der(a{i}) = 1.0; ", i + 1))
        .collect();
    let orientation: Vec<String> = (0..k)
        .map(|i| format!("rot_{}(a{i})", axes[i % 3]))
        .collect();
    let text = format!(
        "struct Rot;\nparameters {{ m = 1.0; }}\ncoordinates {{ {coordinates}}}\nindependent {{ {independent}}}\nbody b {{ mass = m; position = [0, 0, 0]; orientation = {}; inertia = diag(1, 2, 2.5); }}\n",
        orientation.join(" * ")
    );
    let dir = out_dir("size-budget");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("rot8.mech");
    std::fs::write(&file, text).unwrap();
    let run = |budget: Option<&str>| {
        let mut c = assert_cmd::Command::cargo_bin("mechanism").unwrap();
        c.env_remove("MECHANISM_MAX_SIZE");
        if let Some(b) = budget {
            c.env("MECHANISM_MAX_SIZE", b);
        }
        c.args(["equations", file.to_str().unwrap()])
            .output()
            .unwrap()
    };
    let o = run(Some("2000"));
    assert_one_line_error(&o, "nodes and child references, beyond its budget of 2000");
    assert!(
        super::stderr(&o).contains("MECHANISM_MAX_SIZE="),
        "{}",
        super::stderr(&o)
    );
    assert_eq!(run(None).status.code(), Some(0));
}
