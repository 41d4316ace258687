//! The output folder as a user finds it: summary.json lists what the run wrote; a new run
//! replaces the previous run's files (only those: the user's own stay); a run that fails
//! once started (assembly onwards) leaves a summary with status failed and never older
//! results that look current, while a run refused before it starts touches nothing
//! (`kept_results`); no temporary file survives; the default folder stays inside `out/`.

use std::collections::BTreeSet;
use std::path::Path;

use super::{assert_one_line_error, mechanism, mechanism_in, out_dir, stderr};

fn summary(dir: &Path) -> serde_json::Value {
    let text = std::fs::read_to_string(dir.join("summary.json")).expect("summary.json");
    serde_json::from_str(&text).expect("valid JSON")
}

/// The names of the files in `dir`.
fn files_in(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .expect("folder")
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

/// `summary.json`'s `files`, which must be exactly the result files in `dir` (besides
/// `others`), with no temporary left.
fn listed(dir: &Path, others: &[&str]) -> BTreeSet<String> {
    let json = summary(dir);
    let listed: BTreeSet<String> = json["files"]
        .as_array()
        .expect("files")
        .iter()
        .map(|f| f.as_str().unwrap().to_string())
        .collect();
    let mut present = files_in(dir);
    for o in others {
        assert!(present.remove(*o), "{o} is still in {dir:?}");
    }
    assert_eq!(present, listed, "the folder holds exactly the listed files");
    assert!(
        !present.iter().any(|f| f.contains(".partial.")),
        "{present:?}"
    );
    listed
}

/// A successful run of the planar four-bar into `dir`, with the user's notes beside it.
fn successful_run(dir: &Path) -> BTreeSet<String> {
    let d = dir.to_str().unwrap();
    let o = mechanism(&["simulate", "planar_four_bar", "--t-end", "0.5", "--out", d]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::write(dir.join("notes.txt"), "the user's own file").unwrap();
    let files = listed(dir, &["notes.txt"]);
    for f in [
        "trajectory.csv",
        "summary.json",
        "th1.png",
        "constraint_error.svg",
    ] {
        assert!(files.contains(f), "{f} in {files:?}");
    }
    files
}

/// After a failing run: status failed in `stage`, the error containing `needle`, no file
/// of the run before left unless this run wrote it again, the user's notes kept.
fn assert_failed_cleanly(dir: &Path, before: &BTreeSet<String>, stage: &str, needle: &str) {
    let json = summary(dir);
    assert_eq!(json["status"], "failed", "{json}");
    assert_eq!(json["stage"], stage, "{json}");
    assert!(json["error"].as_str().unwrap().contains(needle), "{json}");
    let now = listed(dir, &["notes.txt"]);
    for old in before.difference(&now) {
        assert!(!dir.join(old).exists(), "stale {old}");
    }
    assert_eq!(
        std::fs::read_to_string(dir.join("notes.txt")).unwrap(),
        "the user's own file"
    );
}

#[test]
fn a_failure_at_the_assembly_leaves_no_stale_results() {
    // A coupler too short to close the loop: the run started (a refusal before the start
    // touches nothing: `kept_results`).
    let dir = out_dir("stale-setup");
    let before = successful_run(&dir);
    let d = dir.to_str().unwrap();
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--set",
        "l2=0.01",
        "--out",
        d,
    ]);
    assert_one_line_error(&o, "the given values admit no position");
    assert_failed_cleanly(
        &dir,
        &before,
        "assembly",
        "the given values admit no position",
    );
    let json = summary(&dir);
    assert!(json["t_last"].is_null() && json["max_constraint_error"].is_null());
    assert_eq!(json["files"], serde_json::json!(["summary.json"]));
}

#[test]
fn a_nan_in_a_constraint_is_named_and_recorded() {
    let dir = out_dir("nan-row");
    let before = successful_run(&dir);
    let source = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/mechanisms/planar_four_bar.mech"
    ))
    .unwrap()
    .replace(
        "l1*sin(th1) + l2*sin(th2) - l3*sin(th3);",
        "l1*sin(th1) + l2*sin(th2) - l3*sin(th3) + ln(th1 - 5);",
    );
    let file = dir.join("nan.mech");
    std::fs::write(&file, source).unwrap();
    let o = mechanism(&[
        "simulate",
        file.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_one_line_error(&o, "Phi row 2 (constraint 2) is NaN at t = 0 s, q = [");
    std::fs::remove_file(&file).unwrap();
    assert_failed_cleanly(&dir, &before, "assembly", "Phi row 2 (constraint 2)");
}

#[test]
fn a_run_that_stops_midway_replaces_the_previous_results_with_its_own() {
    let dir = out_dir("stale-midway");
    let before = successful_run(&dir);
    // g = 1e23: the step is far too small for the span; the run stops after the first sample.
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--set",
        "g=1e23",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_one_line_error(&o, "results up to t = 0 s");
    assert_failed_cleanly(&dir, &before, "integration", "time span is too long");
    // Its own trajectory (the one sample at t = 0) replaces the old one; one sample draws
    // no figure, so the old figures are gone.
    let csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    assert_eq!(csv.lines().count(), 2, "header and the sample at t = 0");
    assert!(!dir.join("th1.png").exists());
}

#[test]
fn an_unknown_mechanism_with_out_touches_nothing() {
    let dir = out_dir("stale-unknown");
    let before = successful_run(&dir);
    let o = mechanism(&["simulate", "nonesuch", "--out", dir.to_str().unwrap()]);
    assert_one_line_error(&o, "unknown mechanism `nonesuch`");
    assert_eq!(listed(&dir, &["notes.txt"]), before);
    assert_eq!(summary(&dir)["status"], "completed");
}

#[test]
fn inverse_lists_its_files_and_a_failure_removes_them() {
    let dir = out_dir("stale-inverse");
    let d = dir.to_str().unwrap();
    let inverse = |drive: &str| {
        mechanism(&[
            "inverse",
            "planar_four_bar",
            "--drive",
            drive,
            "--t-end",
            "0.5",
            "--out",
            d,
        ])
    };
    let o = inverse("th1 = pi/2 + 2*t");
    assert!(o.status.success(), "{}", stderr(&o));
    let before = listed(&dir, &[]);
    for f in [
        "inverse.csv",
        "summary.json",
        "driving_torque.png",
        "th2.svg",
    ] {
        assert!(before.contains(f), "{f} in {before:?}");
    }
    let json = summary(&dir);
    assert_eq!(
        (json["command"].as_str(), json["status"].as_str()),
        (Some("inverse"), Some("completed"))
    );
    assert!(json["max_abs_driving_force"]["tau_th1"].as_f64().unwrap() > 0.0);
    std::fs::write(dir.join("notes.txt"), "the user's own file").unwrap();
    // A drive the mechanism cannot follow (the rocker cannot turn round): the run starts
    // and fails.
    let o = inverse("th3 = 2*pi*t");
    assert_one_line_error(&o, "leaves the positions the mechanism can reach");
    assert_failed_cleanly(&dir, &before, "inverse dynamics", "leaves the positions");
    // A forward run that fails at its assembly owns the folder in turn.
    let before = listed(&dir, &["notes.txt"]);
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--set",
        "l2=0.01",
        "--out",
        d,
    ]);
    assert_eq!(o.status.code(), Some(1));
    assert_failed_cleanly(
        &dir,
        &before,
        "assembly",
        "the given values admit no position",
    );
}

#[test]
fn a_temporary_left_by_a_killed_run_is_removed() {
    let dir = out_dir("partial-left");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(".th1.partial.png"), "half a figure").unwrap();
    std::fs::write(dir.join(".trajectory.partial.csv"), "t,th1\n0,").unwrap();
    std::fs::write(dir.join("mine.partial.csv"), "the user's").unwrap();
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--t-end",
        "0.2",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    listed(&dir, &["mine.partial.csv"]);
}

#[test]
fn an_unknown_name_without_out_touches_no_folder() {
    let cwd = out_dir("no-folder");
    std::fs::create_dir_all(&cwd).unwrap();
    let o = mechanism_in(&cwd, &["simulate", "nonesuch"]);
    assert_one_line_error(&o, "unknown mechanism");
    assert!(files_in(&cwd).is_empty(), "{:?}", files_in(&cwd));
}

/// A `.mech` file that is not there (a typo, or a folder given instead) without `--out`:
/// one line naming it, and the results of its earlier run in out/<stem> untouched.
#[test]
fn a_missing_file_without_out_leaves_its_folder_alone() {
    let cwd = out_dir("missing-file");
    std::fs::create_dir_all(&cwd).unwrap();
    let pendulum = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/mechanisms/cartesian_pendulum.mech"
    );
    std::fs::copy(pendulum, cwd.join("p.mech")).unwrap();
    let o = mechanism_in(&cwd, &["simulate", "p.mech", "--t-end", "0.1"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let before = files_in(&cwd.join("out/p"));
    assert!(before.contains("trajectory.csv"), "{before:?}");
    std::fs::remove_file(cwd.join("p.mech")).unwrap();
    let o = mechanism_in(&cwd, &["simulate", "p.mech", "--t-end", "0.1"]);
    assert_one_line_error(&o, "cannot read p.mech");
    assert_eq!(files_in(&cwd.join("out/p")), before);
    assert_eq!(summary(&cwd.join("out/p"))["status"], "completed");
    std::fs::create_dir_all(cwd.join("d")).unwrap();
    let o = mechanism_in(&cwd, &["simulate", "./d"]);
    assert_one_line_error(&o, "cannot read ./d: not a regular file (a folder)");
    assert_eq!(files_in(&cwd.join("out")), ["p".to_string()].into());
}

/// `--out` naming an existing file: one line saying it is not a folder, the file kept.
#[test]
fn out_naming_a_file_is_refused_and_the_file_kept() {
    let dir = out_dir("out-is-a-file");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("results.csv");
    std::fs::write(&file, "the user's table").unwrap();
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--out",
        file.to_str().unwrap(),
    ]);
    assert_one_line_error(&o, "it exists and is not a folder; give --out a folder");
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "the user's table");
}

#[test]
fn the_default_folder_stays_inside_out() {
    // Files whose stems are `..`, `.` and `a b` would otherwise name out/.., out/. and a
    // folder with a space.
    let cwd = out_dir("keys");
    let work = cwd.join("work");
    std::fs::create_dir_all(&work).unwrap();
    let pendulum = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/mechanisms/cartesian_pendulum.mech"
    ))
    .unwrap();
    for (file, key) in [("...mech", "__"), ("..mech", "_"), ("a b.mech", "a_b")] {
        std::fs::write(work.join(file), &pendulum).unwrap();
        let o = mechanism_in(&work, &["simulate", file, "--t-end", "0.1"]);
        assert!(o.status.success(), "{file}: {}", stderr(&o));
        assert!(
            work.join("out").join(key).join("summary.json").is_file(),
            "{file}"
        );
    }
    assert_eq!(
        files_in(&work.join("out")),
        ["_", "__", "a_b"].map(String::from).into()
    );
    // Nothing was written beside `out/` or above the working folder.
    let beside: BTreeSet<String> = files_in(&work)
        .into_iter()
        .filter(|f| !f.ends_with("mech"))
        .collect();
    assert_eq!(beside, ["out".to_string()].into());
    assert_eq!(files_in(&cwd), ["work".to_string()].into());
}
