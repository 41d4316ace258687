//! `summary.json`: every key, with values computed from the trajectory and the run settings.

use crate::support::{DRIFT, MAX_PHI, MAX_VEL, PARAMETERS, info, temp_dir, trajectory};
use mechanism::output::summary::NamedValues;
use mechanism::output::{
    InverseSummary, InverseTable, OutputError, RunSettings, Summary, TrajectoryMaxima,
    write_summary,
};
use mechanism::{SolverStats, Trajectory};
use serde_json::Value;

fn settings() -> RunSettings {
    RunSettings {
        integrator: "dopri5".into(),
        rtol: Some(1e-10),
        atol: Some(1e-12),
        stabilization: "projection".into(),
    }
}

/// The number written after `"key":` in `text`, parsed with Rust's correctly rounded parser
/// (serde_json's default float parser may be off by one ulp).
fn raw_number(text: &str, key: &str) -> f64 {
    let pattern = format!("\"{key}\":");
    let start = text
        .find(&pattern)
        .unwrap_or_else(|| panic!("no key {key}"))
        + pattern.len();
    let rest = text[start..].trim_start();
    let end = rest.find([',', '\n', '}']).unwrap_or(rest.len());
    rest[..end]
        .trim()
        .parse()
        .unwrap_or_else(|e| panic!("{key}: {:?}: {e}", &rest[..end]))
}

fn parameter_values() -> Vec<f64> {
    PARAMETERS.iter().map(|p| p.1).collect()
}

#[test]
fn maxima_are_the_injected_ones() {
    let max = TrajectoryMaxima::of(&trajectory("spatial_crank_slider"));
    assert_eq!(max.constraint_error, MAX_PHI);
    assert_eq!(
        max.velocity_constraint_error, MAX_VEL,
        "absolute value of a negative residual"
    );
    // T + Pi = 1 (up to rounding) and W = DRIFT t^2, so max |E - E0| = DRIFT * 10^2.
    let expected = DRIFT * 100.0;
    assert!(
        (max.energy_balance_error - expected).abs() < 1e-12 * expected + 4.0 * f64::EPSILON,
        "{}",
        max.energy_balance_error
    );
}

#[test]
fn energy_balance_is_relative_to_the_first_sample() {
    // E = T + Pi - W = 5, 5, 5 + 3e-6, 5 - 1e-6: the error is 3e-6 whatever E0 is.
    let mut tr = Trajectory::with_capacity(info("energy"), 4);
    let z = [0.0; 4];
    for (t, e) in [
        (0.0, [4.0, 2.0, 1.0]),
        (1.0, [3.0, 4.0, 2.0]),
        (2.0, [1.0, 4.0 + 3e-6, 0.0]),
        (3.0, [0.0, 6.0, 1.0 + 1e-6]),
    ] {
        tr.push(t, &z, &z, &z, &[0.0; 3], 0.0, 0.0, e);
    }
    let err = TrajectoryMaxima::of(&tr).energy_balance_error;
    assert!((err - 3e-6).abs() < 1e-15, "{err}");
}

#[test]
fn nan_is_reported_not_hidden() {
    let mut tr = trajectory("nan");
    let z = [0.0; 4];
    tr.push(
        10.01,
        &z,
        &z,
        &z,
        &[0.0; 3],
        f64::NAN,
        0.0,
        [f64::NAN, 0.0, 0.0],
    );
    let max = TrajectoryMaxima::of(&tr);
    assert!(
        max.constraint_error.is_nan() && max.energy_balance_error.is_nan(),
        "{max:?}"
    );
    assert_eq!(max.velocity_constraint_error, MAX_VEL);
}

#[test]
fn summary_json_has_every_key_with_its_value() {
    let tr = trajectory("spatial_crank_slider");
    let summary = Summary::new(&tr, &parameter_values(), &settings()).expect("summary");
    let path = temp_dir("summary").join("out/summary.json");
    write_summary(&path, &summary).expect("write");
    let text = std::fs::read_to_string(&path).expect("read");
    let json: Value = serde_json::from_str(&text).expect("valid JSON");
    let keys = [
        "format",
        "format_version",
        "mechanism",
        "parameters",
        "consistent_initial_state",
        "max_constraint_error",
        "max_velocity_constraint_error",
        "max_energy_balance_error",
        "energy_depends_on_time",
        "steps",
        "rejected_steps",
        "rhs_evaluations",
        "wall_time_s",
        "integrator",
        "rtol",
        "atol",
        "stabilization",
        "augmented_solves",
        "banded_solves",
        "generated_solves",
        "mobility",
        "singular_passages",
        "joint_limit_excursions",
        "status",
        "t_last",
        "error",
        "stage",
        "files",
    ];
    let object = json.as_object().expect("an object");
    assert_eq!(
        object.len(),
        keys.len(),
        "exactly the documented keys: {:?}",
        object.keys().collect::<Vec<_>>()
    );
    // Keys are written in the documented order.
    let positions: Vec<usize> = keys
        .iter()
        .map(|k| text.find(&format!("\"{k}\"")).expect(k))
        .collect();
    assert!(
        positions.windows(2).all(|w| w[0] < w[1]),
        "key order {positions:?}"
    );

    assert_eq!(json["mechanism"], "spatial_crank_slider");
    for (name, value) in PARAMETERS {
        assert_eq!(json["parameters"][name].as_f64(), Some(value), "{name}");
    }
    let a1 = text.find("\"a1\"").expect("a1");
    assert!(
        a1 < text.find("\"l2\"").expect("l2") && text.find("\"l2\"") < text.find("\"g\""),
        "parameter order"
    );

    let first = tr.sample(0);
    for (i, name) in ["phi", "beta", "gamma", "x_c"].iter().enumerate() {
        assert_eq!(
            json["consistent_initial_state"]["q"][name].as_f64(),
            Some(first.q[i]),
            "q {name}"
        );
        assert_eq!(
            json["consistent_initial_state"]["q_dot"][name].as_f64(),
            Some(first.qd[i]),
            "q_dot {name}"
        );
    }
    assert_eq!(
        json["consistent_initial_state"]["q_dot"]["phi"].as_f64(),
        Some(2.0 * std::f64::consts::PI)
    );

    assert_eq!(json["max_constraint_error"].as_f64(), Some(MAX_PHI));
    assert_eq!(
        json["max_velocity_constraint_error"].as_f64(),
        Some(MAX_VEL)
    );
    let energy = TrajectoryMaxima::of(&tr).energy_balance_error;
    assert_eq!(
        raw_number(&text, "max_energy_balance_error").to_bits(),
        energy.to_bits(),
        "written exactly"
    );
    assert_eq!(raw_number(&text, "wall_time_s"), 0.125);
    assert_eq!(json["steps"], 2000);
    assert_eq!(json["rejected_steps"], 7);
    assert_eq!(json["rhs_evaluations"], 12_034);
    assert_eq!(json["wall_time_s"].as_f64(), Some(0.125));
    assert_eq!(json["integrator"], "dopri5");
    assert_eq!(json["rtol"].as_f64(), Some(1e-10));
    assert_eq!(json["atol"].as_f64(), Some(1e-12));
    assert_eq!(json["stabilization"], "projection");
    // A completed run of a trajectory without mobility data: status, last time, no error.
    assert_eq!(json["status"], "completed");
    assert!(json["error"].is_null());
    assert_eq!(json["t_last"].as_f64(), Some(tr.last().unwrap().t));
    assert_eq!(json["singular_passages"].as_array().map(Vec::len), Some(0));
    // The stage of a failure, and the files the CLI fills in.
    assert!(json["stage"].is_null());
    assert_eq!(json["files"], serde_json::json!([]));
}

#[test]
fn a_run_without_samples_says_where_and_why_it_stopped() {
    let parameters = NamedValues(vec![("g".into(), 9.81)]);
    let summary = Summary::not_started(
        "Seed",
        parameters,
        &settings(),
        "assembly",
        &"the constraints cannot be satisfied",
    );
    let json = serde_json::to_value(&summary).expect("serialise");
    assert_eq!(json["status"], "failed");
    assert_eq!(json["stage"], "assembly");
    assert_eq!(json["error"], "the constraints cannot be satisfied");
    assert_eq!(json["parameters"]["g"].as_f64(), Some(9.81));
    // Nothing was computed: no time, no maxima (null, not a reassuring 0).
    for key in ["t_last", "max_constraint_error", "max_energy_balance_error"] {
        assert!(json[key].is_null(), "{key}: {}", json[key]);
    }
    assert_eq!(json["steps"], 0);
}

#[test]
fn the_inverse_summary_holds_the_peak_driving_forces() {
    let table = InverseTable {
        coordinates: vec!["phi".into()],
        driven: vec!["phi".into()],
        constraints: 0,
        rows: vec![
            vec![0.0, 0.0, 1.0, 0.0, -3.0],
            vec![0.5, 0.5, 1.0, 0.0, 2.0],
        ],
    };
    let drives = ["phi = t".to_string()];
    let summary = InverseSummary::new("Crank", NamedValues::default(), &drives, &table);
    let json = serde_json::to_value(&summary).expect("serialise");
    assert_eq!(json["command"], "inverse");
    assert_eq!(json["drives"], serde_json::json!(["phi = t"]));
    assert_eq!(json["samples"], 2);
    assert_eq!(json["max_abs_driving_force"]["tau_phi"].as_f64(), Some(3.0));
    assert_eq!(
        (json["status"].as_str(), json["t_last"].as_f64()),
        (Some("completed"), Some(0.5))
    );
    let mut failed = summary.clone();
    failed.outcome.failed_in("output", &"disk full");
    let json = serde_json::to_value(&failed).expect("serialise");
    assert_eq!(
        (json["status"].as_str(), json["stage"].as_str()),
        (Some("failed"), Some("output"))
    );
}

/// The mobility, the multipliers note, the singular passages and a failure, as a run of the
/// redundant four-bar (rows named by their joints) would write them.
#[test]
fn summary_names_redundant_rows_passages_and_failures() {
    use mechanism::{PassageGeometry, SingularPassage, mobility};
    let system = mechanism::builtin::builtin("planar_four_bar_bodies").unwrap();
    let start =
        mechanism::assemble(system.as_ref(), 0.0, &mechanism::AssemblyOptions::default()).unwrap();
    let mut tr = Trajectory::with_capacity(system.info().clone(), 2);
    let (n, m) = (system.info().n(), system.info().m());
    for t in [0.0, 0.5] {
        tr.push(
            t,
            &start.q,
            &start.qd,
            &vec![0.0; n],
            &vec![0.0; m],
            0.0,
            0.0,
            [1.0, 2.0, 0.0],
        );
    }
    tr.mobility = Some(mobility(system.as_ref(), 0.0, &start.q).unwrap());
    tr.singular_passages.push(SingularPassage {
        t: 0.25,
        rank_drop: 2,
        rows: vec![0, 5],
        independence: 1e-7,
        geometry: PassageGeometry::Apex,
        stepped_over: true,
    });
    let params = vec![0.0; system.info().parameters.len()];
    let mut summary = Summary::new(&tr, &params, &settings()).expect("summary");
    summary.failed(&"step size underflow at t = 0.5 s");
    let json = serde_json::to_value(&summary).expect("serialise");
    let mob = &json["mobility"];
    assert_eq!(
        (mob["n"].as_u64(), mob["m"].as_u64(), mob["rank"].as_u64()),
        (Some(18), Some(20), Some(17))
    );
    assert_eq!(mob["degrees_of_freedom"], 1);
    assert_eq!(mob["grubler"], -2);
    let redundant: Vec<&str> = mob["redundant_rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert_eq!(redundant.len(), 3);
    assert!(
        redundant.iter().all(|r| r.starts_with("revolute(")),
        "{redundant:?}"
    );
    let note = mob["multipliers"].as_str().unwrap();
    assert!(
        note.starts_with("not unique") && note.contains("minimum-norm"),
        "{note}"
    );
    let p = &json["singular_passages"][0];
    assert_eq!(
        (p["t"].as_f64(), p["rank_drop"].as_u64()),
        (Some(0.25), Some(2))
    );
    assert_eq!(p["joints"].as_array().unwrap().len(), 2, "{p}");
    assert_eq!(p["geometry"], "apex", "{p}");
    assert_eq!(p["stepped_over"], true, "{p}");
    assert_eq!(json["status"], "failed");
    assert_eq!(json["t_last"].as_f64(), Some(0.5));
    assert_eq!(json["error"], "step size underflow at t = 0.5 s");
}

#[test]
fn fixed_step_runs_write_null_tolerances() {
    let mut tr = trajectory("rk4");
    tr.stats = SolverStats::default();
    let settings = RunSettings {
        integrator: "rk4".into(),
        rtol: None,
        atol: None,
        stabilization: "none".into(),
    };
    let summary = Summary::new(&tr, &parameter_values(), &settings).expect("summary");
    let json = serde_json::to_value(&summary).expect("serialise");
    assert!(json["rtol"].is_null() && json["atol"].is_null(), "{json}");
    assert_eq!(json["steps"], 0);
}

#[test]
fn bad_inputs_are_errors() {
    let tr = trajectory("x");
    let err = Summary::new(&tr, &[1.0], &settings()).expect_err("wrong parameter count");
    assert!(
        matches!(err, OutputError::InvalidData { .. })
            && err.to_string().contains("1 parameter values for 3"),
        "{err}"
    );
    let empty = Trajectory::with_capacity(info("empty"), 0);
    assert!(
        Summary::new(&empty, &parameter_values(), &settings()).is_err(),
        "empty trajectory"
    );
    assert_eq!(TrajectoryMaxima::of(&empty), TrajectoryMaxima::default());
}
