//! Values that would run and be wrong (issue 29, items 6 to 8): an orientation that is not
//! a rotation, a `--set` that makes a mass negative, an `--init` so large that no step can
//! change it. Each is refused with one line that names the value and the rule.

use super::{assert_one_line_error, mechanism, out_dir, stderr};

/// `planar_four_bar_bodies.mech` with `from` replaced by `to`, written to a file.
fn bodies_with(name: &str, from: &str, to: &str) -> std::path::PathBuf {
    let text = include_str!("../../mechanisms/planar_four_bar_bodies.mech");
    assert!(text.contains(from), "{from}");
    let dir = out_dir(&format!("values-{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.mech"));
    std::fs::write(&path, text.replace(from, to)).unwrap();
    path
}

#[test]
fn an_orientation_that_is_not_a_rotation_is_refused_with_its_deviation() {
    let from = "orientation = rot_z(th2) * rot_y(b2) * rot_x(c2);";
    let cases = [
        (
            "zero",
            "orientation = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];",
            "max |(R^T R - I)_ij| = 1.000e0",
        ),
        (
            "scaled",
            "orientation = rot_z(th2) * [[2, 0, 0], [0, 1, 0], [0, 0, 1]];",
            "max |(R^T R - I)_ij| = 3.000e0",
        ),
        (
            "reflection",
            "orientation = [[cos(th2), -sin(th2), 0], [sin(th2), cos(th2), 0], [0, 0, -1]];",
            "det R = -1.000000",
        ),
    ];
    for (name, to, needle) in cases {
        let file = bodies_with(name, from, to);
        let out = out_dir(&format!("values-{name}-out"));
        let o = mechanism(&[
            "simulate",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_one_line_error(
            &o,
            "the orientation of body `coupler` is not a rotation at t = 0",
        );
        assert_one_line_error(&o, needle);
    }
    // Orthonormal at the guess th2 = 0.523537 (so the declaration is accepted), not at the
    // state assembled from th1 = 1.2: refused there, at that state.
    let to = "orientation = [[cos(th2), -sin(th2), 0], [sin(th2), cos(th2), 0], \
              [0, 0, th2/0.523537]] * rot_y(b2) * rot_x(c2);";
    let file = bodies_with("assembled", from, to);
    let out = out_dir("values-assembled-out");
    let f = file.to_str().unwrap();
    let o = mechanism(&["equations", f]);
    assert!(o.status.success(), "{}", stderr(&o));
    let o = mechanism(&[
        "simulate",
        f,
        "--init",
        "th1=1.2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_one_line_error(
        &o,
        "the orientation of body `coupler` is not a rotation at t = 0, th2 = 0.539088: max |(R^T R - I)_ij| = 6.029e-2",
    );
    // A rotation written out explicitly stays accepted.
    let to = "orientation = [[cos(th2), -sin(th2), 0], [sin(th2), cos(th2), 0], [0, 0, 1]] \
              * rot_y(b2) * rot_x(c2);";
    let file = bodies_with("explicit", from, to);
    let out = out_dir("values-explicit-out");
    let f = file.to_str().unwrap();
    let o = mechanism(&[
        "simulate",
        f,
        "--t-end",
        "0.1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

/// A library mechanism's text with its parameters' range annotations removed: what the
/// checks of the values themselves see when no range stops a value first.
fn without_ranges(name: &str) -> std::path::PathBuf {
    let path = format!("{}/mechanisms/{name}.mech", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).unwrap();
    let text = text
        .replace(" nonnegative;", ";")
        .replace(" positive;", ";");
    let dir = out_dir(&format!("values-unranged-{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.mech"));
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn set_values_are_checked_like_declared_ones() {
    // m2 in a declared T (planar_four_bar) and a body's mass (planar_four_bar_bodies),
    // where no declared range refuses it first.
    let four_bar = without_ranges("planar_four_bar");
    let four_bar = four_bar.to_str().unwrap();
    let o = mechanism(&["simulate", four_bar, "--set", "m2=-1"]);
    assert_one_line_error(&o, "--set m2=-1: the kinetic energy can be negative");
    let bodies = without_ranges("planar_four_bar_bodies");
    let o = mechanism(&[
        "simulate",
        bodies.to_str().unwrap(),
        "--set",
        "g=3",
        "--set",
        "m2=-1",
    ]);
    assert_one_line_error(&o, "--set m2=-1: ");
    assert_one_line_error(&o, "planar_four_bar_bodies.mech:");
    assert_one_line_error(&o, "the mass of body `coupler` is -1");
    let o = mechanism(&[
        "inverse",
        four_bar,
        "--set",
        "m3=-0.4",
        "--drive",
        "th1 = pi/2 + t",
    ]);
    assert_one_line_error(&o, "--set m3=-0.4: the kinetic energy can be negative");
    // The library's declarations say their masses are `nonnegative`: refused at once.
    let o = mechanism(&["simulate", "planar_four_bar", "--set", "m2=-1"]);
    assert_one_line_error(
        &o,
        "--set m2=-1: `m2` must be 0 or more (its declaration says `nonnegative`), got -1",
    );
    // Values that keep the model physical still run.
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--set",
        "m2=0",
        "--set",
        "m1=2",
        "--t-end",
        "0.1",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn init_values_beyond_1e9_are_refused_with_the_reason() {
    let cases = [
        (
            "th1=1e300",
            "got 1e300: f64 values there are 1.5e284 apart (at 1e9, 1.2e-7), so no integration \
             step could change it and the coordinate would stay frozen",
        ),
        (
            "der(th1)=-1e10",
            "got -1e10: a rate beyond 1e9 per second carries its coordinate past the 1e9",
        ),
    ];
    for (init, needle) in cases {
        let o = mechanism(&["simulate", "planar_four_bar", "--init", init]);
        assert_one_line_error(&o, "|value| must be at most 1e9, ");
        assert_one_line_error(&o, needle);
    }
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--init",
        "th1=1e9",
        "--t-end",
        "0.1",
    ]);
    // The limit itself is accepted (whatever the run then does).
    assert!(!stderr(&o).contains("at most 1e9"), "{}", stderr(&o));
}

/// A parameter or an initial value given twice is refused, naming both values, in every
/// command that takes them.
#[test]
fn a_name_given_twice_is_refused() {
    let dir = out_dir("given-twice");
    let d = dir.to_str().unwrap();
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--set",
        "l2=0.4",
        "--set",
        "l2=0.41",
        "--out",
        d,
    ]);
    assert_one_line_error(
        &o,
        "--set l2 is given twice (`l2=0.4` and `l2=0.41`); give it once",
    );
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--init",
        "th1=1",
        "--init",
        "th1=2",
        "--out",
        d,
    ]);
    assert_one_line_error(&o, "--init th1 is given twice (`th1=1` and `th1=2`)");
    let o = mechanism(&[
        "linearize",
        "planar_four_bar",
        "--set",
        "g=1",
        "--set",
        "g=2",
        "--out",
        d,
    ]);
    assert_one_line_error(&o, "--set g is given twice");
}
