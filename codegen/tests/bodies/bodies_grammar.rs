//! The body sections of the declaration grammar: what they accept (vector rows, explicit
//! matrices, full inertia tensors, `cross`/`dot`/`norm`) and the errors they report, one line
//! per case.

use mechanism_codegen::{Error, Model, SymbolId, derive, eval, parse_model_str};

/// A declaration around `body` (one coordinate pair x, y; parameters m, l, g).
fn declaration(body: &str) -> String {
    format!(
        "/// Test.
         pub struct T;
         parameters {{ m = 1.0; l = 0.5; g = 9.81; }}
         coordinates {{ x = 0.5; y = 0.0; }}
         independent {{ x = 0.5; der(x) = 0.0; y = 0.0; der(y) = 0.0; }}
         {body}"
    )
}

fn error_of(body: &str) -> Error {
    match parse_model_str(&declaration(body)) {
        Ok(_) => panic!("accepted: {body}"),
        Err(e) => e,
    }
}

/// Each case: the body sections, then a phrase the error message must contain.
const ERRORS: &[(&str, &str)] = &[
    // Orientations that are not rotations at the declared values and guesses (issue 29,
    // item 6): the zero matrix, a scaled one, a reflection, one whose entry 3 x is not 1 at
    // the guess x = 0.5.
    (
        "body b { mass = m; position = [x, y, 0]; orientation = [[0, 0, 0], [0, 0, 0], [0, 0, 0]]; inertia = diag(1, 1, 1); }",
        "the orientation of body `b` is not a rotation at t = 0: max |(R^T R - I)_ij| = 1.000e0",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x) * diag(2, 1, 1); inertia = diag(1, 1, 1); }",
        "max |(R^T R - I)_ij| = 3.000e0 (at most 1e-6 allowed), det R = 2.000000",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; orientation = [[1, 0, 0], [0, 1, 0], [0, 0, -1]]; inertia = diag(1, 1, 1); }",
        "det R = -1.000000",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; orientation = [[cos(x), -sin(x), 0], [sin(x), cos(x), 0], [0, 0, 3*x]]; inertia = diag(1, 1, 1); }",
        "the orientation of body `b` is not a rotation at t = 0, x = 0.5: max |(R^T R - I)_ij| = 1.250e0",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; inertia = diag(1, 1, 1); }",
        "no `orientation`",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; point P = [1, 0, 0]; }",
        "give the body an `orientation`",
    ),
    ("body b { mass = m; position = [x, y]; }", "3-vector"),
    (
        "body b { mass = m; position = [x, yy, 0]; }",
        "unknown symbol `yy`",
    ),
    (
        "body b { masss = m; position = [x, y, 0]; }",
        "not an entry of a body",
    ),
    ("body b { mass = m; }", "needs `position"),
    (
        "body b { mass = m; position = [der(x), y, 0]; }",
        "position-level",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; mass = 2; }",
        "given twice",
    ),
    (
        "body m { mass = 1; position = [x, y, 0]; }",
        "already a parameter or coordinate",
    ),
    (
        "point P = [0, 0, 0]; point P = [1, 0, 0]; body b { mass = m; position = [x, y, 0]; }",
        "declared twice",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x) * [1, 0, 0]; }",
        "3x3",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x); inertia = [1, 2, 3]; }",
        "3x3",
    ),
    (
        "point O = [0, 0, 0]; body b { mass = m; position = [x, y, 0]; } joints { revolute(b, O, O, O); }",
        "must be the name of an axis",
    ),
    (
        "point O = [0, 0, 0]; body b { mass = m; position = [x, y, 0]; } joints { b = 0; }",
        "differ in shape",
    ),
    (
        "point O = [0, 0, 0]; body b { mass = m; position = [x, y, 0]; } joints { b.x = spherical(b, O); }",
        "is a joint",
    ),
    (
        "point O = [0, 0, 0]; body b { mass = m; position = [x, y, 0]; } joints { b.w = 0; }",
        "expected `x`, `y` or `z`",
    ),
    (
        "point O = [0, 0, 0]; body b { mass = m; position = [x, y, 0]; } spring s { between = b, O; }",
        "needs `stiffness",
    ),
    (
        "point O = [0, 0, 0]; body b { mass = m; position = [x, y, 0]; } damper d { between = b, O; stiffness = 1; }",
        "not an entry of a damper",
    ),
    (
        "axis a = [0, 0, 0]; body b { mass = m; position = [x, y, 0]; }",
        "zero vector",
    ),
    (
        "body b { mass = m; position = [x, y, 0] + 1; }",
        "one shape",
    ),
    (
        "gravity = [0, 0, -g]; gravity = [0, 0, g]; body b { mass = m; position = [x, y, 0]; }",
        "given twice",
    ),
    (
        "body b { mass = m; position = [x, y, 0] }",
        "expected `;` after the last statement of the block, found `}`",
    ),
    (
        "point O = [0, 0, 0]; body b { mass = m; position = [x, y, 0]; } joints { distance(b, O, l) }",
        "expected `;` after the last statement of the block, found `}`",
    ),
    (
        "point O = [0, 0, 0]; body b { mass = m; position = [x, y, 0]; } spring s { between = b, O; stiffness = 1 }",
        "expected `;` after the last statement of the block, found `}`",
    ),
    // What a body's mass and inertia must satisfy (issue 14: once silently accepted).
    (
        "body b { position = [x, y, 0]; }",
        "needs `mass = m;` (kg; `mass = 0;` for a massless frame)",
    ),
    (
        "body b { mass = -m; position = [x, y, 0]; }",
        "the mass of body `b` is -1 at the declared values",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x); inertia = [[1, 0.1, 0], [0.2, 2, 0], [0, 0, 3]]; }",
        "not symmetric: entry (1, 2) is 0.1 but (2, 1) is 0.2",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x); inertia = diag(1, 1, 3); }",
        "not physically possible: its principal moments [1.0, 1.0, 3.0]",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x); inertia = diag(-0.1, 1, 1); }",
        "not physically possible",
    ),
    (
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x); inertia = diag(m*l^2, m*l^2, 3*m*l^2); }",
        "not physically possible",
    ),
    // Points, axes and bodies are among the known names, closest first.
    (
        "point O = [0, 0, 0]; body bob { mass = m; position = [x, y, 0]; } joints { distance(bob, Q, l); }",
        "; known: O, m, l, g, x, y, t, pi, ...",
    ),
];

#[test]
fn body_section_errors() {
    for (body, phrase) in ERRORS {
        let e = error_of(body);
        assert!(
            e.to_string().contains(phrase),
            "`{body}`: expected `{phrase}` in `{e}`"
        );
    }
}

/// The limiting bodies are possible: a thin rod (I1 = 0, I2 = I3), a flat plate
/// (I1 + I2 = I3), a massless frame (`mass = 0`), a full symmetric tensor.
#[test]
fn limiting_bodies_are_accepted() {
    for body in [
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x); inertia = diag(0, m*l^2/12, m*l^2/12); }",
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x); inertia = diag(m*l^2/12, m*l^2/12, m*l^2/6); }",
        "body b { mass = m; position = [x, y, 0]; } body f { mass = 0; position = [x, 0, 0]; }",
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x); inertia = [[1, 0.1, 0], [0.1, 2, 0], [0, 0, 3]]; }",
        // An explicit rotation, and one typed with 7 digits (orthogonal to about 1e-7).
        "body b { mass = m; position = [x, y, 0]; orientation = [[cos(x), -sin(x), 0], [sin(x), cos(x), 0], [0, 0, 1]]; inertia = diag(1, 1, 1); }",
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x) * [[0.7071068, -0.7071068, 0], [0.7071068, 0.7071068, 0], [0, 0, 1]]; inertia = diag(1, 1, 1); }",
    ] {
        let mut model =
            parse_model_str(&declaration(body)).unwrap_or_else(|e| panic!("`{body}` refused: {e}"));
        derive(&mut model).unwrap_or_else(|e| panic!("`{body}`: {e}"));
    }
}

/// Without bodies (or springs) the kinetic energy is still required.
#[test]
fn kinetic_is_required_without_bodies() {
    let e = error_of("point O = [0, 0, 0];");
    assert!(e.to_string().contains("no kinetic energy"), "{e}");
}

/// Errors point at the offending line of the file.
#[test]
fn errors_carry_the_line() {
    let text = "/// Test.\npub struct T;\nparameters { m = 1.0; }\ncoordinates { x = 0.5; }\nindependent { x = 0.5; }\nbody b {\n    mass = m;\n    position = [x, 0];\n}\n";
    let e = parse_model_str(text).unwrap_err();
    assert_eq!(e.location().map(|l| l.line), Some(8), "{e}");
}

fn env(model: &Model, state: &[(&str, f64)]) -> impl Fn(SymbolId) -> Option<f64> {
    let table: Vec<(SymbolId, f64)> = model
        .parameters
        .iter()
        .filter_map(|p| model.arena.as_symbol(p.symbol).map(|s| (s, p.default)))
        .chain(
            state
                .iter()
                .filter_map(|(n, v)| model.arena.lookup(n).map(|s| (s, *v))),
        )
        .collect();
    move |s| table.iter().find(|e| e.0 == s).map(|e| e.1)
}

/// Component rows, vector rows, explicit 3x3 orientations, full inertia tensors and the
/// vector functions lower to the expected values; the row count (2 rows from `[..] = [..]`,
/// 1 from `b.z = ..`) is what the degrees-of-freedom check counts (3 - 3 = 0: no independent
/// coordinate needed).
#[test]
fn vector_rows_and_explicit_matrices() {
    let text = "/// Test.
        pub struct T;
        parameters { m = 2.0; l = 0.5; }
        coordinates { x = 0.5; y = 0.0; z = 0.1; }
        body b {
            mass = m;
            position = [x, y, z];
            orientation = [[cos(x), -sin(x), 0], [sin(x), cos(x), 0], [0, 0, 1]];
            inertia = [[1, 0.1, 0], [0.1, 2, 0], [0, 0, 3]];
            point P = [l, 0, 0];
        }
        point O = [0, 0, 0];
        joints {
            [P.x, P.y] = [dot(P - O, [0, 1, 0]), norm(cross(P, [0, 0, 1])) - 1];
            b.z = l*2;
        }";
    let mut model = parse_model_str(text).unwrap();
    assert_eq!(model.constraints.len(), 3);
    let e = derive(&mut model).unwrap();
    let state = [
        ("x", 0.3),
        ("y", -0.2),
        ("z", 0.7),
        ("der(x)", 1.1),
        ("der(y)", 0.4),
        ("der(z)", -0.6),
    ];
    let env = env(&model, &state);
    let v = |id| eval(&model.arena, id, &env).unwrap();
    let (x, y, z, l) = (0.3_f64, -0.2_f64, 0.7_f64, 0.5_f64);
    let p = [x + l * x.cos(), y + l * x.sin(), z];
    // Row 1: P.x - dot(P, e_y); row 2: P.y - (|P x e_z| - 1); row 3: z - 2 l.
    let rows = [
        p[0] - p[1],
        p[1] - ((p[0] * p[0] + p[1] * p[1]).sqrt() - 1.0),
        z - 2.0 * l,
    ];
    for (k, (c, r)) in model.constraints.iter().zip(rows).enumerate() {
        assert!(
            (v(c.expr) - r).abs() < 1e-14,
            "row {k}: {} vs {r}",
            v(c.expr)
        );
    }
    // T = 1/2 m |v|^2 + 1/2 w^T I w with w = (0, 0, x') for the explicit rot_z(x): I_zz = 3.
    let t = 0.5 * 2.0 * (1.1_f64.powi(2) + 0.4_f64.powi(2) + 0.6_f64.powi(2))
        + 0.5 * 3.0 * 1.1_f64.powi(2);
    assert!(
        (v(e.kinetic) - t).abs() < 1e-14,
        "T = {}, expected {t}",
        v(e.kinetic)
    );
}

/// Hand-written energies add to the derived ones.
#[test]
fn hand_written_energies_are_added() {
    let text = declaration(
        "kinetic = 1/2*5*der(y)^2;
         potential = 7*y;
         gravity = [0, -g, 0];
         body b { mass = m; position = [x, y, 0]; }",
    );
    let model = parse_model_str(&text).unwrap();
    let env = env(
        &model,
        &[("x", 0.2), ("y", 0.3), ("der(x)", 2.0), ("der(y)", -1.0)],
    );
    let t = eval(&model.arena, model.kinetic, &env).unwrap();
    let pi = eval(&model.arena, model.potential, &env).unwrap();
    assert!(
        (t - (0.5 * 5.0 + 0.5 * (4.0 + 1.0))).abs() < 1e-14,
        "T = {t}"
    );
    assert!((pi - (7.0 * 0.3 + 9.81 * 0.3)).abs() < 1e-14, "Pi = {pi}");
}

/// Each row of `joints { .. }` is labelled with the joint as written and its component:
/// x, y, z for point rows, axis 1/2 for the parallel-axis rows, slide 1/2 and twist for the
/// rest of `prismatic`, nothing for a scalar statement.
#[test]
fn joint_rows_are_labelled() {
    let text = "/// Test.
        pub struct T;
        parameters { m = 2.0; l = 0.5; }
        coordinates { x = 0.5; y = 0.0; z = 0.1; a = 0.0; b = 0.0; c = 0.0; }
        body b1 {
            mass = m;
            position = [x, y, z];
            orientation = rot_x(a) * rot_y(b) * rot_z(c);
            inertia = diag(1, 2, 3);
            point P = [l, 0, 0];
            axis u = [0, 0, 1];
        }
        point O = [0, 0, 0];
        axis w = [0, 0, 1];
        joints {
            revolute(P, O, u, w);
            prismatic(P, O, u, w);
            spherical(P, O);
            distance(P, O, l/2);
            P = O + [l, -(l - 1), 0];
            P.z = 0;
            [P.x, P.y] = [2*l^2, 0];
        }
        constraints { x - l; }";
    let model = parse_model_str(text).unwrap();
    let labels: Vec<(&str, &str)> = model
        .constraints
        .iter()
        .map(|c| (c.joint.as_str(), c.component.as_str()))
        .collect();
    let revolute = "revolute(P, O, u, w)";
    let prismatic = "prismatic(P, O, u, w)";
    let equal = "P = O + [l, -(l - 1), 0]";
    let pair = "[P.x, P.y] = [2*l^2, 0]";
    assert_eq!(
        labels,
        [
            ("constraint 1", ""),
            (revolute, "x"),
            (revolute, "y"),
            (revolute, "z"),
            (revolute, "axis 1"),
            (revolute, "axis 2"),
            (prismatic, "axis 1"),
            (prismatic, "axis 2"),
            (prismatic, "slide 1"),
            (prismatic, "slide 2"),
            (prismatic, "twist"),
            ("spherical(P, O)", "x"),
            ("spherical(P, O)", "y"),
            ("spherical(P, O)", "z"),
            ("distance(P, O, l/2)", ""),
            (equal, "x"),
            (equal, "y"),
            (equal, "z"),
            ("P.z = 0", ""),
            (pair, "x"),
            (pair, "y"),
        ]
    );
    assert_eq!(model.constraints[4].label(), "revolute(P, O, u, w) axis 1");
    assert_eq!(model.constraints[14].label(), "distance(P, O, l/2)");
    assert_eq!(model.constraints[15].label(), "P = O + [l, -(l - 1), 0] x");
}

/// A rod turning in the xy plane, declared with planar coordinates (x, y, th) and spatial
/// joints: the joints' z rows and their axis rows (body z against ground z) vanish
/// identically and are left out, named in `vanished_rows` and in the equations text; the
/// rows that constrain remain, in order. A joint whose every row vanishes is refused.
#[test]
fn joint_rows_that_vanish_are_left_out() {
    let planar = |joints: &str| {
        format!(
            "/// Test.
            pub struct T;
            parameters {{ m = 2.0; l = 0.5; }}
            coordinates {{ x = 0.25; y = 0.0; th = 0.0; }}
            independent {{ th = 0.0; }}
            body rod {{
                mass = m;
                position = [x, y, 0];
                orientation = rot_z(th);
                inertia = diag(0, m*l^2/12, m*l^2/12);
                point A = [-l/2, 0, 0];
                axis n = [0, 0, 1];
            }}
            point O = [0, 0, 0];
            axis k = [0, 0, 1];
            joints {{ {joints} }}"
        )
    };
    let mut model = parse_model_str(&planar("revolute(A, O, n, k);")).unwrap();
    let labels: Vec<String> = model.constraints.iter().map(|c| c.label()).collect();
    assert_eq!(labels, ["revolute(A, O, n, k) x", "revolute(A, O, n, k) y"]);
    assert_eq!(
        model.vanished_rows,
        ["revolute(A, O, n, k) (z, axis 1, axis 2)"]
    );
    let eqs = derive(&mut model).unwrap();
    let text = mechanism_codegen::equations_text(&model, &eqs);
    assert!(
        text.contains("  (left out, identically zero: revolute(A, O, n, k) (z, axis 1, axis 2))\n"),
        "{text}"
    );
    let model = parse_model_str(&planar("A = O;")).unwrap();
    assert_eq!(model.constraints.len(), 2);
    assert_eq!(model.vanished_rows, ["A = O (z)"]);
    // `A.z = O.z` alone constrains nothing: refused, not left out.
    let refused = match parse_model_str(&planar("A.x = O.x; A.y = O.y; A.z = O.z;")) {
        Ok(_) => panic!("accepted a joint that constrains nothing"),
        Err(e) => e.to_string(),
    };
    assert!(
        refused.contains("constraint 3 does not depend on the coordinates or t"),
        "{refused}"
    );
}

/// The body checks run again on given parameter values (the run-time `--set`, issue 29,
/// item 7): a mass that the values make negative is refused there, at its line.
#[test]
fn given_parameter_values_are_checked_like_declared_ones() {
    let text = declaration(
        "body b { mass = m; position = [x, y, 0]; orientation = rot_z(x); inertia = diag(m, m, m); }",
    );
    assert!(mechanism_codegen::check_parameter_values(&text, &[("m", 2.0)]).is_ok());
    let e = mechanism_codegen::check_parameter_values(&text, &[("m", -1.0)]).unwrap_err();
    assert!(
        e.to_string()
            .contains("the mass of body `b` is -1 at the declared values"),
        "{e}"
    );
    assert!(e.location().is_some(), "{e}");
}
