//! Generated command lines run through the `mechanism` binary: every run ends with status
//! 0 (success), 1 (a failed run or invalid input) or 2 (a usage error), never by a signal,
//! never with a panic, within a time budget, and a failure says so in one line on stderr.

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use proptest::prelude::*;
use proptest::test_runner::{Config, TestRunner};

const COMMANDS: &[&str] = &["simulate", "inverse", "equations", "list", "bogus", ""];
const MECHANISMS: &[&str] = &[
    "planar_four_bar",
    "cartesian_pendulum",
    "spatial_crank_slider",
    "no_such_mechanism",
    "/nonexistent/file.mech",
    "..mech",
    "",
];
const FLAGS: &[&str] = &[
    "--t-end",
    "--samples-per-second",
    "--rtol",
    "--atol",
    "--step",
    "--set",
    "--init",
    "--drive",
    "--integrator",
    "--stabilization",
    "--view",
    "--strobe",
    "--no-animation",
    "--latex",
    "--bogus",
    "-x",
];
const VALUES: &[&str] = &[
    "-1",
    "0",
    "1e-300",
    "0.05",
    "0.2",
    "1",
    "2",
    "nan",
    "inf",
    "-inf",
    "1e300",
    "abc",
    "",
    "l1=0.2",
    "g=nan",
    "g=-9.81",
    "nosuch=1",
    "l2=",
    "th1=0.3",
    "der(th1)=3",
    "der(th2)=1",
    "x=0.1",
    "th1 = 2*pi*t",
    "th1 = sin(",
    "phi = 2*pi*t",
    "rk4",
    "dopri5",
    "dop853",
    "hht",
    "baumgarte",
    "none",
    "projection",
    "xy",
    "oblique",
    "7",
    "1000",
];

/// Half the cases: any mix of the vocabulary ([`any_line`]); half: a short `simulate` or
/// `inverse` of a real mechanism with numeric options drawn from edge values, which gets
/// past the argument parser and into the solvers.
fn command_line() -> impl Strategy<Value = Vec<String>> {
    prop_oneof![any_line(), plausible_line()]
}

const NUMERIC: &[&str] = &["--samples-per-second", "--rtol", "--atol", "--step"];
const NUMBERS: &[&str] = &[
    "-1", "0", "1e-300", "1e-12", "1e-3", "0.01", "1", "50", "nan", "inf", "1e300",
];

fn plausible_line() -> impl Strategy<Value = Vec<String>> {
    (
        prop::bool::ANY,
        prop::sample::select(
            &[
                "planar_four_bar",
                "cartesian_pendulum",
                "spatial_crank_slider",
            ][..],
        ),
        prop::sample::select(&["0.05", "0.2"][..]),
        prop::collection::vec(
            (prop::sample::select(NUMERIC), prop::sample::select(NUMBERS)),
            0..3,
        ),
        prop::sample::select(&["", "rk4", "dopri5", "hht"][..]),
    )
        .prop_map(|(inverse, mechanism, t_end, options, integrator)| {
            let mut args: Vec<String> = if inverse {
                let drive = match mechanism {
                    "planar_four_bar" => "th1 = pi/2 + 2*pi*t",
                    "cartesian_pendulum" => "x = 0.3*sin(t)",
                    _ => "phi = 2*pi*t",
                };
                vec![
                    "inverse".into(),
                    mechanism.into(),
                    "--drive".into(),
                    drive.into(),
                ]
            } else {
                vec!["simulate".into(), mechanism.into()]
            };
            args.extend(["--t-end".into(), t_end.into(), "--no-animation".into()]);
            for (flag, value) in options {
                if !inverse {
                    args.extend([flag.to_string(), value.to_string()]);
                }
            }
            if !inverse && !integrator.is_empty() {
                args.extend(["--integrator".into(), integrator.into()]);
            }
            args
        })
}

/// A command line: a command, a mechanism, then flags and values in any order.
fn any_line() -> impl Strategy<Value = Vec<String>> {
    (
        // Mostly the commands that run something; the others and nonsense now and then.
        prop_oneof![
            5 => Just("simulate"),
            3 => Just("inverse"),
            2 => prop::sample::select(COMMANDS),
        ],
        prop::sample::select(MECHANISMS),
        prop::collection::vec(
            (
                prop::sample::select(FLAGS),
                prop::option::of(prop::sample::select(VALUES)),
            ),
            0..5,
        ),
    )
        .prop_map(|(command, mechanism, flags)| {
            let mut args: Vec<String> = [command, mechanism]
                .into_iter()
                .filter(|s| !s.is_empty())
                .map(String::from)
                .collect();
            for (flag, value) in flags {
                args.push(flag.into());
                args.extend(value.map(String::from));
            }
            args
        })
}

/// Budget per run: the generated runs are at most a few seconds of a small mechanism; a
/// run that is still going after this is a hang (a doomed run that does not fail fast).
const BUDGET: Duration = Duration::from_secs(30);

/// Runs the binary on `args` (with `--out` into a scratch folder); Err on a violation.
fn run(args: &[String], scratch: &PathBuf) -> Result<i32, String> {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_mechanism"));
    cmd.args(args);
    if matches!(
        args.first().map(String::as_str),
        Some("simulate" | "inverse")
    ) && !args.iter().any(|a| a == "--out")
    {
        cmd.arg("--out").arg(scratch);
    }
    let mut child = cmd
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| e.to_string())?;
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(|e| e.to_string())? {
            break status;
        }
        if start.elapsed() > BUDGET {
            let _ = child.kill();
            return Err(format!("still running after {BUDGET:?}"));
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let mut stderr = String::new();
    use std::io::Read;
    if let Some(mut e) = child.stderr.take() {
        let _ = e.read_to_string(&mut stderr);
    }
    let code = status.code().ok_or("ended by a signal")?;
    if stderr.contains("panicked") || stderr.contains("RUST_BACKTRACE") {
        return Err(format!("panicked: {stderr}"));
    }
    let one_line = stderr.trim_end().lines().count() == 1 && stderr.starts_with("error: ");
    match code {
        0 => Ok(0),
        1 | 2 if one_line => Ok(code),
        1 | 2 => Err(format!("exit {code} without a one-line error: {stderr:?}")),
        other => Err(format!("exit status {other}: {stderr}")),
    }
}

/// Runs `cases` generated command lines; the counts of exit statuses 0, 1 and 2.
pub fn campaign(cases: u32) -> [usize; 3] {
    let scratch = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("fuzz-cli");
    let mut runner = TestRunner::new(Config {
        cases,
        failure_persistence: None,
        ..Config::default()
    });
    let counts = std::cell::RefCell::new([0; 3]);
    let result = runner.run(&command_line(), |args| {
        let code = run(&args, &scratch)
            .map_err(|why| TestCaseError::fail(format!("{why}: mechanism {}", args.join(" "))))?;
        counts.borrow_mut()[code as usize] += 1;
        Ok(())
    });
    let _ = std::fs::remove_dir_all(&scratch);
    if let Err(e) = result {
        panic!("{e}");
    }
    counts.into_inner()
}

#[test]
fn generated_command_lines_exit_cleanly() {
    let n = crate::cases(40);
    let [ok, failed, usage] = campaign(n);
    assert_eq!(ok + failed + usage, n as usize);
}

#[test]
#[ignore = "the full campaign (10^4 command lines): cargo test --release --test fuzz -- --ignored --nocapture"]
fn campaign_of_command_lines() {
    let t = Instant::now();
    let [ok, failed, usage] = campaign(10_000);
    println!(
        "command lines: 10000 in {:.1?}: exit 0: {ok}, exit 1: {failed}, exit 2: {usage}",
        t.elapsed()
    );
}
