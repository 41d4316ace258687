//! Declared joint limits in the runs' reports: the Panda (imported from its URDF, limits
//! kept) falls under gravity through its stops, and driven fast it needs more torque than
//! its motors give; the summary says so on the terminal and in `summary.json`.

use super::{mechanism, out_dir};

fn summary(dir: &std::path::Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// The Panda's declared start, q = 0, already has joint 4 outside its range
/// [-3.0718, -0.0698] rad (the URDF's), so the first sample is reported; the line on the
/// terminal and the entry in `summary.json` agree. A mechanism without links reports none.
#[test]
fn a_simulation_reports_the_limits_its_motion_passes() {
    let dir = out_dir("limits-simulate");
    let args = [
        "--t-end",
        "0.2",
        "--figures",
        "none",
        "--no-animation",
        "--out",
    ];
    let o = mechanism(&[&["simulate", "panda"][..], &args, &[dir.to_str().unwrap()]].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("which the simulation does not enforce"),
        "{stdout}"
    );
    assert!(
        stdout.contains("panda_joint4 position outside [-3.0718, -0.0698] rad from t = 0 s;"),
        "{stdout}"
    );
    let s = summary(&dir);
    let passed = s["joint_limit_excursions"].as_array().unwrap();
    let joint4 = passed
        .iter()
        .find(|e| e["coordinate"] == "panda_joint4" && e["quantity"] == "position")
        .unwrap();
    assert_eq!(joint4["lower"], -3.0718);
    assert_eq!(joint4["upper"], -0.0698);
    assert_eq!(joint4["first_t"], 0.0);
    assert!(joint4["extreme"].as_f64().unwrap() > -0.0698);

    let dir = out_dir("limits-simulate-seed");
    let seed = ["simulate", "spatial_crank_slider"];
    let o = mechanism(&[&seed[..], &args, &[dir.to_str().unwrap()]].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        summary(&dir)["joint_limit_excursions"],
        serde_json::json!([])
    );
}

/// Joint 2 swung by 1.5 rad at 1 Hz needs about 200 N m at the ends of its swing, beyond
/// the 87 N m of its motor, and turns at 3 pi rad/s, beyond its 2.175 rad/s.
#[test]
fn an_inverse_run_reports_the_torque_beyond_a_motor() {
    let dir = out_dir("limits-inverse");
    let drives = [
        "panda_joint1 = 0",
        "panda_joint2 = 1.5*sin(2*pi*t)",
        "panda_joint3 = 0",
        "panda_joint4 = -1.5",
        "panda_joint5 = 0",
        "panda_joint6 = 1.5",
        "panda_joint7 = 0",
    ];
    let mut args = vec!["inverse", "panda", "--t-end", "1", "--figures", "none"];
    args.extend(["--no-animation", "--out", dir.to_str().unwrap()]);
    for d in &drives {
        args.extend(["--drive", d]);
    }
    let o = mechanism(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("panda_joint2 effort outside [-87, 87] N m from t = 0.05 s;"),
        "{stdout}"
    );
    let s = summary(&dir);
    let passed = s["joint_limit_excursions"].as_array().unwrap();
    let effort = passed
        .iter()
        .find(|e| e["coordinate"] == "panda_joint2" && e["quantity"] == "effort")
        .unwrap();
    let peak = s["max_abs_driving_force"]["tau_panda_joint2"]
        .as_f64()
        .unwrap();
    assert_eq!(effort["extreme"].as_f64().unwrap().abs(), peak);
    assert!(peak > 87.0);
    let rate = passed
        .iter()
        .find(|e| e["coordinate"] == "panda_joint2" && e["quantity"] == "rate")
        .unwrap();
    let fastest = 1.5 * 2.0 * std::f64::consts::PI;
    assert!((rate["extreme"].as_f64().unwrap().abs() - fastest).abs() < 1e-9);
}
