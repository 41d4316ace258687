//! The energy line of `simulate`: a pendulum whose pivot is shaken, declared twice. With the
//! moving pivot as a moving anchor (a joint row that depends on t), W holds the row's work
//! and T + Pi - W stays constant, so the line measures the integration error. With the
//! pivot's motion written into T, T depends on t explicitly, W cannot hold that work, and
//! the line says it is no error measure (`energy_depends_on_time` in summary.json).

use super::{mechanism, out_dir};

/// A rod (m = 2 kg, l = 1 m) hinged at one end to a pivot at x = A sin(w t).
const ANCHOR: &str = "
/// Shaken pendulum, the pivot a moving anchor.
pub struct ShakenAnchor;
parameters { l = 1.0; m = 2.0; g = 9.81; A = 0.1; w = 7.0; }
coordinates { th = 0.3; x = 0.0; y = 0.0; }
independent { th = 0.3; }
gravity = [0, -g, 0];
point O = [A*sin(w*t), 0, 0];
body rod {
    mass = m; position = [x, y, 0]; orientation = rot_z(th);
    inertia = diag(0, m*l^2/12, m*l^2/12);
    point P = [l/2, 0, 0];
}
joints { P = O; }
";

/// The same rod in its angle alone, the pivot's motion inside T.
const IN_T: &str = "
/// Shaken pendulum, the pivot's motion written into T.
pub struct ShakenInT;
parameters { l = 1.0; m = 2.0; g = 9.81; A = 0.1; w = 7.0; }
coordinates { th = 0.3; }
independent { th = 0.3; }
kinetic = 1/2*m*((A*w*cos(w*t) + l/2*sin(th)*der(th))^2 + (l/2*cos(th)*der(th))^2)
    + 1/2*(m*l^2/12)*der(th)^2;
potential = -m*g*l/2*sin(th);
";

/// Runs `source` for 2 s at 1e-11 and returns stdout and summary.json.
fn run(name: &str, source: &str) -> (String, serde_json::Value) {
    let dir = out_dir(&format!("energy-{name}"));
    std::fs::create_dir_all(&dir).expect("scratch");
    let file = dir.join(format!("{name}.mech"));
    std::fs::write(&file, source).expect("written");
    let out = dir.join("out");
    let o = mechanism(&[
        "simulate",
        file.to_str().unwrap(),
        "--t-end",
        "2",
        "--rtol",
        "1e-11",
        "--atol",
        "1e-11",
        "--figures",
        "none",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let summary = std::fs::read_to_string(out.join("summary.json")).expect("summary");
    let stdout = String::from_utf8_lossy(&o.stdout).into_owned();
    (stdout, serde_json::from_str(&summary).expect("JSON"))
}

/// The anchor's balance closes to 1e-8 J (measured 5.3e-11 J over 2 s at 1e-11, while the
/// anchor's work reaches 1.69 J) and carries no note; the declaration with t in T drifts by
/// 1.69 J (the same motion: the work W leaves out), with the note on stdout and in
/// summary.json.
#[test]
fn the_energy_line_says_when_it_is_no_error_measure() {
    let note = "not an error measure: T or Pi depends on t explicitly";
    let (stdout, summary) = run("anchor", ANCHOR);
    let balance = summary["max_energy_balance_error"].as_f64().unwrap();
    assert!(balance < 1e-8, "{balance:e}");
    assert_eq!(summary["energy_depends_on_time"], false);
    assert!(!stdout.contains(note), "{stdout}");
    let (stdout, summary) = run("in-t", IN_T);
    let drift = summary["max_energy_balance_error"].as_f64().unwrap();
    assert!(drift > 0.1, "{drift:e}");
    assert_eq!(summary["energy_depends_on_time"], true);
    assert!(stdout.contains(note), "{stdout}");
}
