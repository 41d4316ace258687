//! The command-line tool as a user runs it: outputs, headers, summary keys, and one-line
//! errors with a non-zero exit status.

use std::path::{Path, PathBuf};
use std::process::Output;

use assert_cmd::Command;

#[path = "cli/a02_passages.rs"]
mod a02_passages;
#[path = "cli/conventions.rs"]
mod conventions;
#[path = "cli/declarations.rs"]
mod declarations;
#[path = "cli/diagnoses.rs"]
mod diagnoses;
#[path = "cli/energy_balance.rs"]
mod energy_balance;
#[path = "cli/fail_fast.rs"]
mod fail_fast;
#[path = "cli/floating.rs"]
mod floating;
#[path = "cli/implicit.rs"]
mod implicit;
#[path = "cli/import.rs"]
mod import;
#[path = "cli/input_limits.rs"]
mod input_limits;
#[path = "cli/inverse_branch.rs"]
mod inverse_branch;
#[path = "cli/joint_limits.rs"]
mod joint_limits;
#[path = "cli/kept_results.rs"]
mod kept_results;
#[path = "cli/linearize_scale.rs"]
mod linearize_scale;
#[path = "cli/outputs.rs"]
mod outputs;
#[path = "cli/ownership.rs"]
mod ownership;
#[path = "cli/parameter_values.rs"]
mod parameter_values;
#[path = "cli/passage_geometry.rs"]
mod passage_geometry;
#[path = "cli/run_values.rs"]
mod run_values;
#[path = "cli/scale.rs"]
mod scale;
#[path = "cli/singular_passages.rs"]
mod singular_passages;
#[path = "cli/streams.rs"]
mod streams;

/// Runs the binary with `args` in a fresh scratch working folder (so the default
/// `out/<key>` lands there, never among the repository's files, and never in a folder that
/// a test running at the same time writes: the second run would be refused).
fn mechanism(args: &[&str]) -> Output {
    mechanism_in(&fresh_cwd(), args)
}

/// A new, empty working folder for one run of the binary.
fn fresh_cwd() -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static RUNS: AtomicUsize = AtomicUsize::new(0);
    let cwd = out_dir(&format!("cwd/{}", RUNS.fetch_add(1, Ordering::Relaxed)));
    std::fs::create_dir_all(&cwd).expect("scratch folder");
    cwd
}

/// Runs the binary with `args` in the working folder `cwd`.
fn mechanism_in(cwd: &Path, args: &[&str]) -> Output {
    Command::cargo_bin("mechanism")
        .expect("binary built")
        .current_dir(cwd)
        .args(args)
        .output()
        .expect("runs")
}

/// A folder for one test's outputs, removed first (it does not exist on return).
fn out_dir(name: &str) -> PathBuf {
    let d = scratch(name);
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// `name` under cargo's scratch folder for integration tests (`target/tmp/cli`): a fixed
/// name per test, so a run replaces the last run's files instead of adding to the system's
/// temporary folder, and a failed test's outputs stay there to be read.
fn scratch(name: &str) -> PathBuf {
    Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cli")
        .join(name)
}

/// `mechanism simulate TARGET --t-end T --figures none --no-animation --out DIR EXTRA...`:
/// a run that writes only trajectory.csv and summary.json.
fn simulate_to(target: &str, dir: &Path, t_end: &str, extra: &[&str]) -> Output {
    let d = dir.to_str().unwrap();
    let mut args = vec![
        "simulate",
        target,
        "--t-end",
        t_end,
        "--figures",
        "none",
        "--no-animation",
        "--out",
        d,
    ];
    args.extend_from_slice(extra);
    mechanism(&args)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn csv_header(path: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).expect("csv written");
    text.lines()
        .next()
        .unwrap_or("")
        .split(',')
        .map(str::to_string)
        .collect()
}

/// A user error: exit status 1, exactly one line on stderr, no panic or backtrace.
fn assert_one_line_error(o: &Output, needle: &str) {
    let e = stderr(o);
    assert_eq!(o.status.code(), Some(1), "exit status for: {e}");
    assert_eq!(e.trim_end().lines().count(), 1, "one line: {e}");
    assert!(e.starts_with("error: "), "{e}");
    assert!(e.contains(needle), "`{needle}` in: {e}");
    assert!(
        !e.contains("panicked") && !e.contains("RUST_BACKTRACE"),
        "{e}"
    );
}

#[test]
fn simulate_writes_the_seed_outputs() {
    let dir = out_dir("seed");
    let o = mechanism(&[
        "simulate",
        "spatial_crank_slider",
        "--t-end",
        "1",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let header = csv_header(&dir.join("trajectory.csv"));
    let mut expected: Vec<String> = vec!["t".into()];
    let q = ["phi", "beta", "gamma", "x_c"];
    expected.extend(q.iter().map(|s| s.to_string()));
    expected.extend(q.iter().map(|s| format!("{s}_dot")));
    expected.extend(q.iter().map(|s| format!("{s}_ddot")));
    expected.extend(["lambda_1", "lambda_2", "lambda_3"].map(String::from));
    expected.extend(
        [
            "constraint_error",
            "velocity_constraint_error",
            "kinetic",
            "potential",
            "work",
        ]
        .map(String::from),
    );
    assert_eq!(header, expected);
    // 1 s at 100 samples per second: t = 0, 0.01, ..., 1.
    let rows = std::fs::read_to_string(dir.join("trajectory.csv"))
        .unwrap()
        .lines()
        .count()
        - 1;
    assert_eq!(rows, 101);

    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    for key in [
        "mechanism",
        "parameters",
        "consistent_initial_state",
        "max_constraint_error",
        "max_velocity_constraint_error",
        "max_energy_balance_error",
        "steps",
        "rejected_steps",
        "rhs_evaluations",
        "wall_time_s",
        "integrator",
        "rtol",
        "atol",
        "stabilization",
    ] {
        assert!(summary.get(key).is_some(), "summary.json lacks `{key}`");
    }
    // The issue's bar: loop closure below 1e-12 with the default projection.
    assert!(summary["max_constraint_error"].as_f64().unwrap() < 1e-12);
    // ERRATA item 2: gamma0 = acos((h + l1)/l2), beta0 = asin(d/(l2 sin gamma0)).
    let gamma0 = ((0.12_f64 + 0.08) / 0.3).acos();
    let beta0 = (0.1 / (0.3 * gamma0.sin())).asin();
    let q0 = &summary["consistent_initial_state"]["q"];
    assert!((q0["gamma"].as_f64().unwrap() - gamma0).abs() < 1e-14);
    assert!((q0["beta"].as_f64().unwrap() - beta0).abs() < 1e-14);
    assert!((q0["x_c"].as_f64().unwrap() - 0.2).abs() < 1e-14);
    for fig in [
        "fig_3_1_phi",
        "fig_3_2_beta",
        "fig_3_3_gamma",
        "fig_3_4_x_c",
        "fig_3_5_constraint_error",
    ] {
        for ext in ["png", "svg"] {
            assert!(dir.join(format!("{fig}.{ext}")).is_file(), "{fig}.{ext}");
        }
    }
}

#[test]
fn inverse_writes_the_driving_torque() {
    let dir = out_dir("inverse");
    let o = mechanism(&[
        "inverse",
        "spatial_crank_slider",
        "--drive",
        "phi = 2*pi*t",
        "--t-end",
        "1",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let header = csv_header(&dir.join("inverse.csv"));
    assert_eq!(&header[..2], ["t", "phi"]);
    assert!(header.contains(&"tau_phi".to_string()));
    assert_eq!(header.last().map(String::as_str), Some("lambda_3"));
    assert!(dir.join("driving_torque.png").is_file());
    // phi follows the drive exactly: phi(t) = 2 pi t in every row.
    let text = std::fs::read_to_string(dir.join("inverse.csv")).unwrap();
    for line in text.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
        assert!((v[1] - 2.0 * std::f64::consts::PI * v[0]).abs() < 1e-12);
    }
}

#[test]
fn a_mech_file_runs_through_the_interpreter() {
    let dir = out_dir("file");
    let file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/mechanisms/cartesian_pendulum.mech"
    );
    let o = mechanism(&[
        "simulate",
        file,
        "--t-end",
        "0.5",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("trajectory.csv").is_file());
    assert!(dir.join("constraint_error.png").is_file());
}

#[test]
fn list_and_equations() {
    let o = mechanism(&["list"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("spatial_crank_slider") && text.contains("planar_four_bar"),
        "{text}"
    );
    let o = mechanism(&["equations", "spatial_crank_slider"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("Phi_q"), "{text}");
    let o = mechanism(&["equations", "spatial_crank_slider", "--latex"]);
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stdout).contains("\\sin"));
}

#[test]
fn unknown_mechanism_lists_the_names() {
    let o = mechanism(&["simulate", "nonesuch"]);
    assert_one_line_error(&o, "available: spatial_crank_slider");
}

#[test]
fn bad_set_and_init_name_the_culprit() {
    assert_one_line_error(
        &mechanism(&["simulate", "spatial_crank_slider", "--set", "l9=1"]),
        "`l9`",
    );
    assert_one_line_error(
        &mechanism(&["simulate", "spatial_crank_slider", "--init", "theta=1"]),
        "`theta`",
    );
    assert_one_line_error(
        &mechanism(&["simulate", "spatial_crank_slider", "--set", "l2=abc"]),
        "l2",
    );
}

#[test]
fn syntax_error_in_a_file_gives_line_and_column() {
    let dir = out_dir("syntax");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("broken.mech");
    std::fs::write(
        &file,
        "pub struct Broken;\ncoordinates { x = 0.0; }\nkinetic = 1/2*der(x)^2 +* 3;\n",
    )
    .unwrap();
    let o = mechanism(&["simulate", file.to_str().unwrap()]);
    assert_one_line_error(&o, "broken.mech:3:");
}

#[test]
fn solver_failure_is_a_typed_message() {
    // A crank longer than the geometry allows cannot assemble: Newton fails with a message.
    let o = mechanism(&[
        "simulate",
        "spatial_crank_slider",
        "--set",
        "l2=0.05",
        "--t-end",
        "0.1",
    ]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(1), "{e}");
    assert_eq!(e.trim_end().lines().count(), 1, "{e}");
}

#[test]
fn absurd_sample_counts_are_refused_not_a_crash() {
    // 1e300 s is beyond the longest run; 1e6 s at 100 samples per second cannot be
    // stored: a one-line error, before any buffer is reserved, for both commands.
    let o = mechanism(&["simulate", "cartesian_pendulum", "--t-end", "1e300"]);
    assert_one_line_error(&o, "at most 1e9 s");
    let o = mechanism(&["simulate", "cartesian_pendulum", "--t-end", "1e6"]);
    assert_one_line_error(&o, "samples");
    let o = mechanism(&[
        "inverse",
        "cartesian_pendulum",
        "--drive",
        "x = 0.1*sin(t)",
        "--t-end",
        "1e6",
    ]);
    assert_one_line_error(&o, "samples");
    let o = mechanism(&[
        "simulate",
        "cartesian_pendulum",
        "--t-end",
        "1",
        "--samples-per-second",
        "1e15",
    ]);
    assert_one_line_error(&o, "samples");
}

#[test]
fn the_library_refuses_them_too() {
    // The same limit in `Simulator::new`, for callers that do not go through the CLI.
    let system = mechanism::builtin::builtin("cartesian_pendulum").expect("built in");
    let options = mechanism::SimulationOptions {
        t_end: 1e300,
        ..Default::default()
    };
    let err = mechanism::simulate(system.as_ref(), &options).expect_err("refused");
    assert!(err.to_string().contains("samples"), "{err}");
}

#[test]
fn list_and_equations_report_rank_and_redundant_rows() {
    let o = mechanism(&["list"]);
    let text = String::from_utf8_lossy(&o.stdout);
    // name, n, m, rank, dof, grubler, redundant
    let row = |name: &str| -> Vec<String> {
        text.lines()
            .find(|l| l.split_whitespace().next() == Some(name))
            .unwrap_or_else(|| panic!("{name} in {text}"))
            .split_whitespace()
            .map(str::to_string)
            .collect()
    };
    assert_eq!(row("bricard")[1..], ["30", "30", "29", "1", "0", "1"]);
    assert_eq!(
        row("planar_four_bar_bodies")[1..],
        ["18", "20", "17", "1", "-2", "3"]
    );
    assert_eq!(row("n_four_bar")[1..], ["82", "81", "81", "1", "1", "0"]);
    let o = mechanism(&["equations", "planar_four_bar_bodies"]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("rank Phi_q = 17"), "{text}");
    assert!(text.contains("Redundant rows: row "), "{text}");
    assert!(text.contains("are not unique"), "{text}");
    // The same declaration as a file takes the interpreter (its constraint rows alone,
    // `InterpretedConstraints`) instead of the compiled built-in: the same paragraph.
    let file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/mechanisms/planar_four_bar_bodies.mech"
    );
    let o = mechanism(&["equations", file]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let from_file = String::from_utf8_lossy(&o.stdout);
    let paragraph = |t: &str| t[t.find("Mobility at").expect("a mobility paragraph")..].to_string();
    assert_eq!(paragraph(&from_file), paragraph(&text));
}

/// A run that stops midway writes what it computed, says where and why in summary.json,
/// and exits 1 with one line.
#[test]
fn a_failed_run_writes_its_partial_results() {
    let dir = out_dir("partial");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("failing.mech");
    std::fs::write(
        &file,
        "struct Failing;\ncoordinates { x = 0.0; }\nindependent { x = 0.0; }\n\
         kinetic = 1/2*der(x)^2;\nforces { x: sqrt(0.5 - t); }\n",
    )
    .unwrap();
    let out = dir.join("out");
    let o = mechanism(&[
        "simulate",
        file.to_str().unwrap(),
        "--t-end",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_one_line_error(&o, "results up to t = ");
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["status"], "failed");
    let t_last = summary["t_last"].as_f64().unwrap();
    assert!(t_last > 0.4 && t_last <= 0.5, "{t_last}");
    assert!(
        summary["error"]
            .as_str()
            .unwrap()
            .contains("tau of x is NaN")
    );
    let rows = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    assert_eq!(
        rows.lines().count() - 1,
        (t_last * 100.0).round() as usize + 1
    );
}

/// The JSON data block of an animation page.
fn animation_data(page: &Path) -> serde_json::Value {
    let html = std::fs::read_to_string(page).expect("animation.html written");
    let open = r#"<script type="application/json" id="scene-data">"#;
    let start = html.find(open).expect("data block") + open.len();
    let end = start
        + html[start..]
            .find("</script>")
            .expect("end of the data block");
    serde_json::from_str(&html[start..end].replace("<\\/", "</")).expect("valid JSON")
}

#[test]
fn simulate_writes_an_animation_that_holds_the_run() {
    let dir = out_dir("animation");
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--t-end",
        "0.5",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    for f in ["animation.html", "mechanism.png", "mechanism.svg"] {
        assert!(dir.join(f).is_file(), "{f} written");
    }
    let data = animation_data(&dir.join("animation.html"));
    let times: Vec<f64> = serde_json::from_value(data["times"].clone()).unwrap();
    let th1: Vec<f64> = serde_json::from_value(data["coordinates"][0]["values"].clone()).unwrap();
    let positions: Vec<f64> = serde_json::from_value(data["positions"].clone()).unwrap();
    // The page's frames are the CSV's samples (51 of them: no decimation at this length),
    // bit for bit.
    let csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(times.len(), rows.len());
    for (k, row) in rows.iter().enumerate() {
        assert_eq!((times[k], th1[k]), (row[0], row[1]), "frame {k}");
        // Point B (index 1) is the crank tip l1 (cos th1, sin th1) at that frame.
        let b = &positions[3 * (4 * k + 1)..3 * (4 * k + 1) + 2];
        assert!(
            (b[0] - 0.1 * row[1].cos()).abs() < 1e-16 && (b[1] - 0.1 * row[1].sin()).abs() < 1e-16
        );
    }
    assert_eq!(data["points"][0]["name"], "A");
    assert_eq!(data["points"][0]["ground"], true);
}

#[test]
fn no_animation_writes_neither_page_nor_strobe() {
    let dir = out_dir("no-animation");
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--t-end",
        "0.2",
        "--no-animation",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("trajectory.csv").is_file());
    assert!(!dir.join("animation.html").exists() && !dir.join("mechanism.png").exists());
}

#[test]
fn inverse_writes_the_animation_of_the_prescribed_motion() {
    let dir = out_dir("inverse-animation");
    let o = mechanism(&[
        "inverse",
        "spatial_crank_slider",
        "--drive",
        "phi = 2*pi*t",
        "--t-end",
        "1",
        "--view",
        "yz",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let data = animation_data(&dir.join("animation.html"));
    let phi: Vec<f64> = serde_json::from_value(data["coordinates"][0]["values"].clone()).unwrap();
    let times: Vec<f64> = serde_json::from_value(data["times"].clone()).unwrap();
    for (t, p) in times.iter().zip(&phi) {
        assert!(
            (p - 2.0 * std::f64::consts::PI * t).abs() < 1e-12,
            "the drive at t = {t}"
        );
    }
    let svg = std::fs::read_to_string(dir.join("mechanism.svg")).unwrap();
    assert!(
        svg.contains("y (m)") && svg.contains("z (m)"),
        "the chosen view plane"
    );
}
