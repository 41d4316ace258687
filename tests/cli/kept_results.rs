//! Nothing lost (issue 53, items 4, 5 and 8): a run refused before it starts leaves its
//! output folder byte for byte as it was; a run whose files cannot all be written (a full
//! disk, a file beyond the size allowed) or cannot be put in (a folder where a file goes)
//! leaves the previous results, and says so in one line; an interrupted run leaves the
//! previous results or its own complete ones.

use std::collections::BTreeMap;
use std::path::Path;
use std::process::Output;

use super::{assert_one_line_error, fresh_cwd, mechanism, out_dir, stderr};

/// Every entry under `dir` by relative path: a file's bytes, or `None` for a folder (so
/// that a folder created, removed or put in a file's place shows).
fn tree(dir: &Path) -> BTreeMap<String, Option<Vec<u8>>> {
    let mut entries = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).expect("folder") {
            let path = e.unwrap().path();
            let name = path.strip_prefix(dir).unwrap().display().to_string();
            if path.is_dir() {
                stack.push(path);
                entries.insert(name, None);
            } else {
                entries.insert(name, Some(std::fs::read(&path).unwrap()));
            }
        }
    }
    entries
}

/// A completed run of the planar four-bar into `dir` (its figures, CSV, animation and
/// summary), with the user's notes beside it.
fn good_run(dir: &Path) {
    let d = dir.to_str().unwrap();
    let o = mechanism(&["simulate", "planar_four_bar", "--t-end", "0.3", "--out", d]);
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::write(dir.join("notes.txt"), "the user's own file").unwrap();
}

#[test]
fn every_refusal_before_the_start_leaves_the_folder_byte_for_byte() {
    let dir = out_dir("refusals");
    good_run(&dir);
    let before = tree(&dir);
    let d = dir.to_str().unwrap();
    let missing = fresh_cwd().join("missing.mech");
    let missing = missing.to_str().unwrap();
    // (arguments, part of the one-line error); each gets `--out d`. Before issue 53 all
    // but the option-range refusals replaced the results with a failed summary.
    let refusals: &[(&[&str], &str)] = &[
        (
            &["simulate", "planar_four_bar", "--set", "G=9.81"],
            "did you mean `g`",
        ),
        (
            &["simulate", "planar_four_bar", "--set", "g=abc"],
            "--set g",
        ),
        (
            &["simulate", "planar_four_bar", "--set", "m2=-1"],
            "--set m2=-1",
        ),
        (&["simulate", "planar_fourbar"], "unknown mechanism"),
        (&["simulate", missing], "cannot read"),
        (
            &["simulate", "planar_four_bar", "--t-end", "1e5"],
            "would hold",
        ),
        (
            &[
                "simulate",
                "planar_four_bar",
                "--integrator",
                "rk4",
                "--step",
                "1e-9",
            ],
            "fixed step",
        ),
        (
            &["simulate", "planar_four_bar", "--samples-per-second", "1e9"],
            "samples",
        ),
        (&["simulate", "planar_four_bar", "--rtol", "2"], "--rtol"),
        (&["simulate", "planar_four_bar", "--t-end", "0"], "--t-end"),
        (
            &["simulate", "planar_four_bar", "--init", "nope=1"],
            "`nope`",
        ),
        (
            &["simulate", "planar_four_bar", "--init", "th1=1e300"],
            "at most 1e9",
        ),
        (
            &["inverse", "planar_four_bar", "--drive", "nope = t"],
            "--drive",
        ),
        (
            &[
                "inverse",
                "planar_four_bar",
                "--drive",
                "th1 = t",
                "--drive",
                "th1 = 2*t",
            ],
            "twice",
        ),
        (
            &[
                "inverse",
                "planar_four_bar",
                "--drive",
                "th1 = t",
                "--init",
                "th1=1",
            ],
            "driven",
        ),
        (
            &[
                "inverse",
                "planar_four_bar",
                "--drive",
                "th1 = t",
                "--t-end",
                "1e5",
            ],
            "would hold",
        ),
        (&["linearize", "planar_fourbar"], "unknown mechanism"),
        (
            &["linearize", "planar_four_bar", "--set", "G=1"],
            "unknown parameter",
        ),
    ];
    for (args, needle) in refusals {
        let mut args = args.to_vec();
        args.extend(["--out", d]);
        let o = mechanism(&args);
        assert_one_line_error(&o, needle);
        assert!(tree(&dir) == before, "{args:?} changed the folder");
    }
    // A usage error (exit status 2) touches nothing either.
    let o = mechanism(&["simulate", "planar_four_bar", "--bogus", "--out", d]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(tree(&dir) == before);
    // A refused run into a folder that does not exist does not create it.
    let none = out_dir("refusals-none");
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--set",
        "g=abc",
        "--out",
        none.to_str().unwrap(),
    ]);
    assert_one_line_error(&o, "--set g");
    assert!(!none.exists());
}

/// Runs the binary under `ulimit -f` (in 512-byte blocks for `sh`, 1024 for `bash`: about
/// 32 to 64 KB per file) with SIGXFSZ ignored, so that a larger write fails with EFBIG as
/// on a full disk, without needing a mount.
#[cfg(unix)]
fn with_file_size_limit(args: &[&str]) -> Output {
    let bin = assert_cmd::cargo::cargo_bin("mechanism");
    std::process::Command::new("sh")
        .current_dir(fresh_cwd())
        .arg("-c")
        .arg("ulimit -f 64 && trap '' XFSZ && exec \"$0\" \"$@\"")
        .arg(bin)
        .args(args)
        .output()
        .expect("runs")
}

#[cfg(unix)]
#[test]
fn a_run_whose_files_cannot_be_written_keeps_the_previous_results() {
    let dir = out_dir("file-too-large");
    good_run(&dir);
    let before = tree(&dir);
    let d = dir.to_str().unwrap();
    // trajectory.csv of 10 s at 1000 samples per second is about 3 MB.
    let args = [
        "simulate",
        "planar_four_bar",
        "--set",
        "g=3",
        "--samples-per-second",
        "1000",
    ];
    let o = with_file_size_limit(&[&args[..], &["--out", d]].concat());
    assert_one_line_error(
        &o,
        &format!("File too large (os error 27); {d} is left as it was"),
    );
    assert!(tree(&dir) == before, "the previous results are whole");
    // A run that fails midway (a force undefined from t = 0.5 s on) and cannot write its
    // partial results either: the previous results stay, not a failed summary.
    let failing = fresh_cwd().join("failing.mech");
    std::fs::write(
        &failing,
        "struct Failing;\ncoordinates { x = 0.0; }\nindependent { x = 0.0; }\n\
         kinetic = 1/2*der(x)^2;\nforces { x: sqrt(0.5 - t); }\n",
    )
    .unwrap();
    let o = with_file_size_limit(&[
        "simulate",
        failing.to_str().unwrap(),
        "--t-end",
        "1",
        "--samples-per-second",
        "1e4",
        "--out",
        d,
    ]);
    assert_one_line_error(&o, "tau of x is NaN");
    assert!(
        stderr(&o).contains("is left as it was (cannot write"),
        "{}",
        stderr(&o)
    );
    assert!(tree(&dir) == before);
    // Into a new folder: nothing is left, not even the folder.
    let new = out_dir("file-too-large-new");
    let o = with_file_size_limit(&[&args[..], &["--out", new.to_str().unwrap()]].concat());
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    assert!(!new.exists());
}

/// The same on a real full disk: a 1 MiB tmpfs. Needs the privilege to mount (root), so
/// it is not run by default: `cargo test --test cli -- --ignored a_full_disk`.
#[cfg(target_os = "linux")]
#[test]
#[ignore = "mounts a tmpfs: needs root"]
fn a_full_disk_keeps_the_previous_results() {
    let mount = out_dir("tmpfs");
    std::fs::create_dir_all(&mount).unwrap();
    let m = mount.to_str().unwrap();
    let status = std::process::Command::new("mount")
        .args(["-t", "tmpfs", "-o", "size=1m", "tmpfs", m])
        .status()
        .expect("mount runs");
    assert!(status.success(), "mount -t tmpfs needs root");
    let dir = mount.join("run");
    good_run(&dir);
    let before = tree(&dir);
    let d = dir.to_str().unwrap();
    for _ in 0..3 {
        let o = mechanism(&[
            "simulate",
            "planar_four_bar",
            "--t-end",
            "10",
            "--samples-per-second",
            "1000",
            "--out",
            d,
        ]);
        assert_one_line_error(&o, "No space left on device");
        assert!(stderr(&o).contains("is left as it was: free space"));
        assert!(tree(&dir) == before);
    }
    let _ = std::process::Command::new("umount").arg(m).status();
}

#[test]
fn a_folder_in_the_place_of_a_result_file_stops_the_swap_whole() {
    for (name, needle) in [
        // Known before the run: refused before it starts.
        (
            "trajectory.csv",
            "trajectory.csv: it exists and is a directory",
        ),
        ("summary.json", "summary.json: it exists and is a directory"),
        // Known when the figures are drawn: the swap is refused before anything moves.
        (
            "th2.png",
            "th2.png: it exists and is a directory, not a regular file; write elsewhere; ",
        ),
    ] {
        let dir = out_dir("folder-as-file");
        good_run(&dir);
        std::fs::remove_file(dir.join(name)).unwrap();
        std::fs::create_dir(dir.join(name)).unwrap();
        std::fs::write(dir.join(name).join("inside.txt"), "the user's").unwrap();
        let before = tree(&dir);
        let d = dir.to_str().unwrap();
        let o = mechanism(&[
            "simulate",
            "planar_four_bar",
            "--t-end",
            "0.3",
            "--set",
            "g=3",
            "--out",
            d,
        ]);
        assert_one_line_error(&o, needle);
        assert!(tree(&dir) == before, "{name}: the folder as it was");
    }
}

/// Sends `signal` to a run of the four-bar with g = 3 into `dir` (holding a run with
/// g = 9.81) `after` it starts, and checks what is left: the previous results byte for
/// byte, or the new run complete (its summary, every file it lists and no other).
#[cfg(unix)]
fn interrupt(dir: &Path, signal: &str, after: std::time::Duration) {
    use assert_cmd::cargo::CommandCargoExt as _;
    let before = tree(dir);
    let mut child = std::process::Command::cargo_bin("mechanism")
        .unwrap()
        .current_dir(fresh_cwd())
        .args([
            "simulate",
            "planar_four_bar",
            "--t-end",
            "4",
            "--set",
            "g=3",
        ])
        .args([
            "--samples-per-second",
            "200",
            "--out",
            dir.to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(after);
    let _ = std::process::Command::new("kill")
        .args([signal, &child.id().to_string()])
        .status();
    child.wait().unwrap();
    let mut now = tree(dir);
    // What a killed run may leave: its lock file and staging folder, hidden, which the
    // next run there removes.
    now.retain(|name, _| !name.starts_with(".mechanism"));
    if now == before {
        return;
    }
    let summary: serde_json::Value =
        serde_json::from_slice(now["summary.json"].as_ref().unwrap()).unwrap();
    assert_eq!(summary["status"], "completed", "{signal} at {after:?}");
    assert_eq!(summary["parameters"]["g"], 3.0);
    let mut listed: Vec<String> = summary["files"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| f.as_str().unwrap().to_string())
        .collect();
    listed.push("notes.txt".into());
    listed.sort();
    assert_eq!(
        now.keys().cloned().collect::<Vec<_>>(),
        listed,
        "{signal} at {after:?}"
    );
}

#[cfg(unix)]
#[test]
fn an_interrupted_run_leaves_the_previous_results_or_its_complete_ones() {
    for (signal, ms) in [("-INT", 50), ("-TERM", 300), ("-INT", 700), ("-TERM", 1500)] {
        let dir = out_dir("interrupted");
        good_run(&dir);
        interrupt(&dir, signal, std::time::Duration::from_millis(ms));
    }
}
