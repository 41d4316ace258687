//! Input files with limits (issue 29, items 20 and 21): only a regular file is read as a
//! `.mech` declaration (a FIFO or a device is refused at once, never read), and at most
//! 16 MiB of it unless `MECHANISM_MAX_INPUT_BYTES` says otherwise.

use std::process::Output;
use std::time::Duration;

use assert_cmd::Command;

use super::{assert_one_line_error, fresh_cwd, out_dir};

/// Runs the binary with `args` and the environment `env`, killed after 30 s.
fn run(args: &[&str], env: &[(&str, &str)]) -> Output {
    let cwd = fresh_cwd();
    let mut cmd = Command::cargo_bin("mechanism").unwrap();
    cmd.current_dir(cwd)
        .args(args)
        .timeout(Duration::from_secs(30));
    for (k, v) in env {
        cmd.env(k, v);
    }
    cmd.output().unwrap()
}

#[cfg(unix)]
#[test]
fn a_pipe_or_a_device_is_refused_without_reading_it() {
    let dir = out_dir("special-files");
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("fifo.mech");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let zero = dir.join("zero.mech");
    std::os::unix::fs::symlink("/dev/zero", &zero).unwrap();
    for (file, kind) in [(&fifo, "a pipe"), (&zero, "a device")] {
        let f = file.to_str().unwrap();
        for args in [&["equations", f][..], &["simulate", f]] {
            let o = run(args, &[]);
            assert_one_line_error(&o, &format!("not a regular file ({kind})"));
        }
    }
}

#[test]
fn a_file_beyond_the_input_budget_is_refused_and_the_budget_can_be_raised() {
    let dir = out_dir("large-input");
    std::fs::create_dir_all(&dir).unwrap();
    let big = dir.join("big.mech");
    // 17 MiB of comment: refused before it is read.
    let line = format!("// {}\n", "x".repeat(1020));
    std::fs::write(&big, line.repeat(17 * 1024)).unwrap();
    let o = run(&["equations", big.to_str().unwrap()], &[]);
    assert_one_line_error(
        &o,
        "17825792 bytes, more than the 16777216 allowed for an input file; raise the limit \
         with the environment variable MECHANISM_MAX_INPUT_BYTES=17825792",
    );
    // The budget applies to every input file, and the variable moves it both ways.
    let pendulum = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/mechanisms/cartesian_pendulum.mech"
    );
    let o = run(
        &["equations", pendulum],
        &[("MECHANISM_MAX_INPUT_BYTES", "100")],
    );
    assert_one_line_error(&o, "more than the 100 allowed for an input file");
    let o = run(
        &["equations", pendulum],
        &[("MECHANISM_MAX_INPUT_BYTES", "1000000")],
    );
    assert!(o.status.success());
    // A value that is not a positive whole number is refused, not ignored.
    for bad in ["12k", "0", "-5", ""] {
        let o = run(
            &["equations", pendulum],
            &[("MECHANISM_MAX_INPUT_BYTES", bad)],
        );
        assert_one_line_error(
            &o,
            &format!(
                "MECHANISM_MAX_INPUT_BYTES must be a positive whole number of bytes, got `{bad}`"
            ),
        );
    }
}
