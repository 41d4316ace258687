//! Standard output and standard error that cannot be written: a reader that stops early
//! (`mechanism list | true`) and a full device (`>/dev/full`). Never a panic: a closed
//! pipe is quiet with the command's own exit status, a full device one line and exit 1.

use std::path::Path;
use std::process::{Output, Stdio};

use assert_cmd::cargo::CommandCargoExt as _;

use super::{fresh_cwd, out_dir};

/// Runs the binary with `args`, its standard output set to `stdout`.
fn with_stdout(args: &[&str], stdout: Stdio) -> Output {
    let cwd = fresh_cwd();
    std::process::Command::cargo_bin("mechanism")
        .expect("binary built")
        .current_dir(&cwd)
        .args(args)
        .stdout(stdout)
        .stderr(Stdio::piped())
        .output()
        .expect("runs")
}

/// A pipe whose reading end is already closed, as in `mechanism list | true`.
fn closed_pipe() -> Stdio {
    let (reader, writer) = std::io::pipe().expect("pipe");
    drop(reader);
    writer.into()
}

/// `/dev/full`: every write fails with "no space left on device".
fn full_device() -> Stdio {
    std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/full")
        .expect("/dev/full")
        .into()
}

fn assert_no_panic(o: &Output) {
    let e = String::from_utf8_lossy(&o.stderr);
    assert!(
        !e.contains("panicked") && !e.contains("RUST_BACKTRACE"),
        "{e}"
    );
    assert_ne!(o.status.code(), Some(101), "{e}");
}

#[test]
fn a_closed_stdout_is_quiet_and_keeps_the_exit_status() {
    for args in [
        &["list"][..],
        &["equations", "planar_four_bar"],
        &["--version"],
    ] {
        let o = with_stdout(args, closed_pipe());
        assert_no_panic(&o);
        assert_eq!(o.status.code(), Some(0), "{args:?}");
        assert!(o.stderr.is_empty(), "{args:?}: {:?}", o.stderr);
    }
}

#[test]
fn a_full_stdout_is_one_line_and_exit_status_1() {
    if !Path::new("/dev/full").exists() {
        return;
    }
    for args in [&["list"][..], &["equations", "planar_four_bar"]] {
        let o = with_stdout(args, full_device());
        assert_no_panic(&o);
        super::assert_one_line_error(&o, "cannot write to standard output");
    }
}

#[test]
fn a_simulation_with_a_closed_stdout_still_writes_its_results() {
    let dir = out_dir("closed-stdout");
    let d = dir.to_str().unwrap();
    let args = ["simulate", "planar_four_bar", "--t-end", "0.2", "--out", d];
    let o = with_stdout(&args, closed_pipe());
    assert_no_panic(&o);
    assert_eq!(o.status.code(), Some(0));
    assert!(dir.join("trajectory.csv").is_file());
    let args = ["simulate", "planar_four_bar", "--t-end", "0.2", "--out", d];
    if Path::new("/dev/full").exists() {
        let o = with_stdout(&args, full_device());
        assert_no_panic(&o);
        super::assert_one_line_error(&o, "cannot write to standard output");
    }
}
