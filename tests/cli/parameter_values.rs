//! Parameters set on the command line (issue 53, items 1 and 3): every initial value written
//! with parameters follows `--set` in every command, and a value a declaration refuses (a
//! wheel of radius 0 or less, a parameter outside its declared range) is refused in one line
//! naming it.

use std::path::{Path, PathBuf};

use super::{assert_one_line_error, mechanism, out_dir, stderr};

/// The rows of a CSV file as (header, rows of numbers).
fn csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// Column `name` of the first row of `path`.
fn first(path: &Path, name: &str) -> f64 {
    let (header, rows) = csv(path);
    let k = header.iter().position(|h| h == name).expect(name);
    rows[0][k]
}

/// `text` written to `<scratch>/<name>/<name>.mech`.
fn declaration(name: &str, text: &str) -> PathBuf {
    let dir = out_dir(&format!("parameters-{name}"));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.mech"));
    std::fs::write(&path, text).unwrap();
    path
}

/// A slider on y = 2 x started at x = l/2 with x' = w: the closed form of its start is
/// (x, y) = (l/2, l), (x', y') = (w, 2 w).
const SLIDER: &str = "pub struct Slider;
parameters { l = 2.0 positive; w = 1.0; m = 1.0 nonnegative; }
coordinates { x = l/2; y = l; }
independent { x = l/2; der(x) = w; }
kinetic = m/2*(der(x)^2 + der(y)^2);
constraints { y - 2*x; }
";

/// Before: `--set v=3` ran at 5 m/s and `--set rR=0.5` at 8.33 m/s while summary.json said
/// otherwise. Truth: upright and straight ahead, the rear wheel rolls without slipping, so
/// the rear wheel centre moves forward at x' = rR thR', and the declared `der(thR) = v/rR`
/// makes that v.
#[test]
fn the_bicycle_runs_at_the_speed_set() {
    for (set, rr, speed) in [("v=3", 0.3, 3.0), ("rR=0.5", 0.5, 5.0)] {
        let dir = out_dir(&format!("parameters-bicycle-{set}"));
        let o = mechanism(&[
            "simulate",
            "whipple_bicycle",
            "--set",
            set,
            "--t-end",
            "0.05",
            "--figures",
            "none",
            "--no-animation",
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        let trajectory = dir.join("trajectory.csv");
        let (x_dot, th_dot) = (first(&trajectory, "x_dot"), first(&trajectory, "thR_dot"));
        // One solve of the rolling rows at the start: a few ulp.
        assert!(
            (th_dot * rr - speed).abs() < 1e-12,
            "{set}: thR' = {th_dot}"
        );
        assert!((x_dot - speed).abs() < 1e-12, "{set}: x' = {x_dot}");
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap())
                .unwrap();
        let (name, value) = set.split_once('=').unwrap();
        assert_eq!(
            summary["parameters"][name].as_f64(),
            value.parse::<f64>().ok()
        );
    }
}

/// `independent { x = l/2; der(x) = w; }` with `--set`: simulate, linearize and the guesses
/// of inverse follow.
#[test]
fn declared_initial_values_follow_set_in_every_command() {
    let slider = declaration("slider", SLIDER);
    let slider = slider.to_str().unwrap();
    let dir = out_dir("parameters-slider-simulate");
    let o = mechanism(&[
        "simulate",
        slider,
        "--set",
        "w=2",
        "--set",
        "l=4",
        "--t-end",
        "0.1",
        "--figures",
        "none",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let trajectory = dir.join("trajectory.csv");
    assert_eq!(first(&trajectory, "x"), 2.0);
    assert_eq!(first(&trajectory, "x_dot"), 2.0);
    // y = 2 x is linear: one Newton step, exact to a few ulp.
    assert!((first(&trajectory, "y") - 4.0).abs() < 1e-14);
    assert!((first(&trajectory, "y_dot") - 4.0).abs() < 1e-14);

    // linearize: at rest (w = 0) where l puts it, and the bicycle's steady motion at v.
    let dir = out_dir("parameters-slider-linearize");
    let o = mechanism(&[
        "linearize",
        slider,
        "--set",
        "w=0",
        "--set",
        "l=4",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let read = |dir: &Path| -> serde_json::Value {
        let text = std::fs::read_to_string(dir.join("linearization.json")).unwrap();
        serde_json::from_str(&text).unwrap()
    };
    assert_eq!(read(&dir)["state"]["q"]["x"].as_f64(), Some(2.0));
    let dir = out_dir("parameters-bicycle-linearize");
    let o = mechanism(&[
        "linearize",
        "whipple_bicycle",
        "--set",
        "v=3",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let qd = &read(&dir)["state"]["qd"];
    assert!((qd["x"].as_f64().unwrap() - 3.0).abs() < 1e-12, "{qd}");
    assert!((qd["thR"].as_f64().unwrap() - 10.0).abs() < 1e-12, "{qd}");

    // The guess y = s*l picks the branch of the circle: s = 1, the upper one.
    let branch = declaration(
        "branch",
        "pub struct Branch;
         parameters { m = 1.0 nonnegative; l = 1.0 positive; s = -1.0; g = 9.81; }
         coordinates { x = 0.0; y = s*l; }
         independent { x = 0.0; }
         kinetic = m/2*(der(x)^2 + der(y)^2);
         potential = m*g*y;
         constraints { x^2 + y^2 - l^2; }",
    );
    for (s, y0) in [("s=-1", -1.0), ("s=1", 1.0)] {
        let dir = out_dir(&format!("parameters-branch-{s}"));
        let o = mechanism(&[
            "inverse",
            branch.to_str().unwrap(),
            "--drive",
            "x = 0.5*sin(t)",
            "--set",
            s,
            "--t-end",
            "0.1",
            "--figures",
            "none",
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        assert_eq!(first(&dir.join("inverse.csv"), "y"), y0, "{s}");
    }
}

/// Before: all three ran, the wheel under the ground rolling backwards.
#[test]
fn a_wheel_of_radius_zero_or_less_is_refused() {
    for (set, needle) in [
        ("r=-0.1", "the radius of the wheel `disc` is -0.1"),
        ("r=0", "the radius of the wheel `disc` is 0"),
    ] {
        // Through a file without the `positive` of the library's declaration, so the
        // wheel's own check is the one that speaks.
        let text = include_str!("../../mechanisms/rolling_disc.mech").replace(" positive", "");
        let disc = declaration("disc-unranged", &text);
        let o = mechanism(&["simulate", disc.to_str().unwrap(), "--set", set]);
        assert_one_line_error(&o, &format!("--set {set}: "));
        assert_one_line_error(&o, needle);
        assert_one_line_error(&o, "a wheel's radius must be greater than 0");
        // The library's disc declares r `positive`: refused by its range.
        let o = mechanism(&["simulate", "rolling_disc", "--set", set]);
        assert_one_line_error(
            &o,
            &format!("--set {set}: `r` must be greater than 0 (its declaration says `positive`)"),
        );
    }
    let o = mechanism(&["simulate", "whipple_bicycle", "--set", "rR=-0.3"]);
    assert_one_line_error(&o, "--set rR=-0.3: `rR` must be greater than 0");
    let o = mechanism(&["linearize", "whipple_bicycle", "--set", "rF=0"]);
    assert_one_line_error(&o, "--set rF=0: `rF` must be greater than 0");
    // Written into the statement: refused at its line and column.
    let text = include_str!("../../mechanisms/rolling_disc.mech")
        .replace("rolling(disc, a, r);", "rolling(disc, a, 0);");
    let disc = declaration("disc-zero", &text);
    let o = mechanism(&["simulate", disc.to_str().unwrap()]);
    assert_one_line_error(&o, "disc-zero.mech:");
    assert_one_line_error(
        &o,
        "the radius of the wheel `disc` is 0 at the declared values: a wheel's radius must be greater than 0",
    );
}

#[test]
fn a_parameter_outside_its_declared_range_is_refused() {
    let o = mechanism(&["simulate", "planar_four_bar", "--set", "l2=-0.1"]);
    assert_one_line_error(
        &o,
        "--set l2=-0.1: `l2` must be greater than 0 (its declaration says `positive`), got -0.1",
    );
    let o = mechanism(&[
        "inverse",
        "planar_four_bar",
        "--set",
        "l1=0",
        "--drive",
        "th1 = t",
    ]);
    assert_one_line_error(&o, "--set l1=0: `l1` must be greater than 0");
    // A default outside its own range is a mistake of the declaration, at its value.
    let slider = declaration("bad-default", &SLIDER.replace("l = 2.0", "l = -2.0"));
    let o = mechanism(&["simulate", slider.to_str().unwrap()]);
    assert_one_line_error(&o, "bad-default.mech:2:18: ");
    assert_one_line_error(
        &o,
        "parameter `l` is -2 at the declared values, but its declaration says `positive` (greater than 0)",
    );
    // A word after a default that is no range says what may stand there.
    let slider = declaration("bad-word", &SLIDER.replace("w = 1.0;", "w = 1.0 m;"));
    let o = mechanism(&["simulate", slider.to_str().unwrap()]);
    assert_one_line_error(
        &o,
        "`m` after the default of `w` is not a range: a parameter's value may be followed by `positive` or `nonnegative`, then `;`",
    );
}
