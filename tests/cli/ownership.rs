//! The output folder belongs to one run at a time (issue 29, items 1 to 4): a second run
//! into a folder in use is refused; a run killed at any moment leaves the previous results
//! whole; a `summary.json` we did not write never decides what is removed.

use std::collections::BTreeSet;
use std::path::Path;
use std::time::{Duration, Instant};

use assert_cmd::cargo::CommandCargoExt as _;

use super::{assert_one_line_error, fresh_cwd, mechanism, out_dir, stderr};

fn files_in(dir: &Path) -> BTreeSet<String> {
    std::fs::read_dir(dir)
        .expect("folder")
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

/// A completed run of the planar four-bar into `dir`; returns the files and the CSV.
fn completed_run(dir: &Path) -> (BTreeSet<String>, String) {
    let d = dir.to_str().unwrap();
    let o = mechanism(&["simulate", "planar_four_bar", "--t-end", "0.3", "--out", d]);
    assert!(o.status.success(), "{}", stderr(&o));
    let csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    (files_in(dir), csv)
}

/// Starts a long run into `dir` and waits until it holds the folder's lock.
fn long_run(dir: &Path) -> std::process::Child {
    let cwd = fresh_cwd();
    let child = std::process::Command::cargo_bin("mechanism")
        .unwrap()
        .current_dir(cwd)
        .args(["simulate", "planar_four_bar", "--t-end", "1000000"])
        .args(["--samples-per-second", "1", "--out", dir.to_str().unwrap()])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let lock = dir.join(".mechanism.lock");
    let start = Instant::now();
    while std::fs::read_to_string(&lock).map_or(true, |s| s.is_empty()) {
        assert!(start.elapsed() < Duration::from_secs(60), "no lock taken");
        std::thread::sleep(Duration::from_millis(10));
    }
    child
}

#[test]
fn a_second_run_into_a_folder_in_use_is_refused_and_a_killed_run_loses_nothing() {
    let dir = out_dir("in-use");
    let (before, csv) = completed_run(&dir);
    let mut first = long_run(&dir);
    let d = dir.to_str().unwrap();
    let o = mechanism(&["simulate", "planar_four_bar", "--set", "g=3", "--out", d]);
    assert_one_line_error(
        &o,
        &format!("is in use by another run (process {})", first.id()),
    );
    // kill -9 mid-run: the previous results are whole, nothing of the killed run shows.
    first.kill().unwrap();
    first.wait().unwrap();
    let mut now = files_in(&dir);
    now.remove(".mechanism-staging");
    now.remove(".mechanism.lock");
    assert_eq!(now, before);
    assert_eq!(
        std::fs::read_to_string(dir.join("trajectory.csv")).unwrap(),
        csv
    );
    // The next run takes the stale lock over and clears what the killed run left.
    let (after, _) = completed_run(&dir);
    assert_eq!(after, before);
}

#[test]
fn a_foreign_summary_decides_nothing() {
    let cases = [r#"{"files":["thesis.tex"]}"#, "{}"];
    for summary in cases {
        let dir = out_dir("foreign-summary");
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("thesis.tex"), "the user's").unwrap();
        std::fs::write(dir.join("inverse.csv"), "the user's").unwrap();
        std::fs::write(dir.join("summary.json"), summary).unwrap();
        let d = dir.to_str().unwrap();
        let o = mechanism(&["simulate", "planar_four_bar", "--set", "g=abc", "--out", d]);
        assert_one_line_error(&o, "--set g");
        let o = mechanism(&["simulate", "planar_four_bar", "--t-end", "0.2", "--out", d]);
        assert!(o.status.success(), "{}", stderr(&o));
        for f in ["thesis.tex", "inverse.csv"] {
            assert_eq!(
                std::fs::read_to_string(dir.join(f)).unwrap(),
                "the user's",
                "{summary}"
            );
        }
    }
}

#[test]
fn a_mistyped_set_keeps_the_previous_results() {
    // Refused before the run starts: the folder keeps the previous results as they were.
    let dir = out_dir("typo");
    let (before, csv) = completed_run(&dir);
    assert!(before.contains("th1.png"));
    let d = dir.to_str().unwrap();
    let o = mechanism(&["simulate", "planar_four_bar", "--set", "L2=0.5", "--out", d]);
    assert_one_line_error(&o, "unknown parameter `L2` (did you mean `l2`?)");
    assert_eq!(files_in(&dir), before);
    assert_eq!(
        std::fs::read_to_string(dir.join("trajectory.csv")).unwrap(),
        csv
    );
}

#[cfg(unix)]
#[test]
fn a_lock_file_that_links_elsewhere_is_refused_and_its_target_kept() {
    let dir = out_dir("lock-link");
    let (before, _) = completed_run(&dir);
    let victim = out_dir("lock-link-victim");
    std::fs::create_dir_all(&victim).unwrap();
    let victim = victim.join("thesis.tex");
    std::fs::write(&victim, "the user's").unwrap();
    std::os::unix::fs::symlink(&victim, dir.join(".mechanism.lock")).unwrap();
    let d = dir.to_str().unwrap();
    let runs: [&[&str]; 2] = [
        &["simulate", "planar_four_bar", "--t-end", "0.3", "--out", d],
        &["linearize", "whipple_bicycle", "--out", d],
    ];
    for args in runs {
        let o = mechanism(args);
        assert_one_line_error(
            &o,
            &format!("the lock file {d}/.mechanism.lock is a symbolic link, not a regular file"),
        );
        assert_eq!(std::fs::read_to_string(&victim).unwrap(), "the user's");
        let mut now = files_in(&dir);
        assert!(now.remove(".mechanism.lock"));
        assert_eq!(now, before);
    }
}

#[test]
fn linearize_is_refused_while_another_run_holds_the_folder() {
    let dir = out_dir("linearize-lock");
    std::fs::create_dir_all(&dir).unwrap();
    let held = mechanism::output::FolderLock::acquire(&dir).unwrap();
    let d = dir.to_str().unwrap();
    let o = mechanism(&["linearize", "whipple_bicycle", "--out", d]);
    assert_one_line_error(
        &o,
        &format!("is in use by another run (process {})", std::process::id()),
    );
    assert!(!dir.join("linearization.json").exists());
    drop(held);
    let o = mechanism(&["linearize", "whipple_bicycle", "--out", d]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(files_in(&dir), ["linearization.json".to_string()].into());
}

#[test]
fn mistyped_names_get_a_suggestion() {
    let o = mechanism(&["simulate", "planar_four_bar", "--init", "TH1=1"]);
    assert_one_line_error(&o, "unknown coordinate `TH1` (did you mean `th1`?)");
    let o = mechanism(&["inverse", "planar_four_bar", "--drive", "th4 = t"]);
    assert_one_line_error(
        &o,
        "--drive `th4 = t`: unknown coordinate `th4` (did you mean `th1`?); coordinates: th1, \
         th2, th3 (independent: th1)",
    );
    // A name that is no likely typo gets the list and the independent coordinate only.
    let o = mechanism(&["inverse", "planar_four_bar", "--drive", "phi = 2*pi*t"]);
    assert_one_line_error(
        &o,
        "unknown coordinate `phi`; coordinates: th1, th2, th3 (independent: th1)",
    );
}
