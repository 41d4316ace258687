//! Command-line conventions: every error is one line on stderr; usage mistakes exit 2 and
//! point at `--help`; invalid values exit 1 and state the allowed range; `--help` documents
//! the exit statuses.

use super::{assert_one_line_error, mechanism, stderr};

/// A usage error: exit status 2, one line naming the mistake and where help is.
fn assert_usage_error(args: &[&str], needle: &str, help: &str) {
    let o = mechanism(args);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {e}");
    assert_eq!(e.trim_end().lines().count(), 1, "one line: {e}");
    assert!(
        e.starts_with("error: ") && e.contains(needle),
        "`{needle}` in {e}"
    );
    assert!(
        e.trim_end().ends_with(&format!("(see {help} --help)")),
        "{e}"
    );
    assert!(!e.contains("tip:") && !e.contains("Usage:"), "{e}");
}

#[test]
fn usage_errors_are_one_line_with_exit_status_2() {
    let cases: [(&[&str], &str, &str); 8] = [
        (
            &["simulate", "planar_four_bar", "--bogus"],
            "unexpected argument '--bogus'",
            "mechanism simulate",
        ),
        (
            &["simulate"],
            "required arguments were not provided: <MECHANISM>",
            "mechanism simulate",
        ),
        (
            &["inverse", "planar_four_bar"],
            "not provided: --drive",
            "mechanism inverse",
        ),
        (
            &["simulate", "planar_four_bar", "--integrator", "euler"],
            "[possible values: rk4, dopri5, dop853, hht]",
            "mechanism simulate",
        ),
        (
            &["simulate", "planar_four_bar", "--t-end", "ten"],
            "invalid value 'ten' for '--t-end <S>'",
            "mechanism simulate",
        ),
        (
            // A negative count is a value out of range, not an unknown flag `-1`.
            &["simulate", "planar_four_bar", "--strobe", "-1"],
            "invalid value '-1' for '--strobe <K>': -1 is not in 1..=100",
            "mechanism simulate",
        ),
        (
            &["simulat"],
            "unrecognized subcommand 'simulat'",
            "mechanism",
        ),
        (
            &["list", "extra"],
            "unexpected argument 'extra'",
            "mechanism list",
        ),
    ];
    for (args, needle, help) in cases {
        assert_usage_error(args, needle, help);
    }
}

#[test]
fn help_documents_the_exit_statuses() {
    for args in [
        &["--help"][..],
        &["simulate", "--help"],
        &["inverse", "--help"],
    ] {
        let o = mechanism(args);
        assert_eq!(o.status.code(), Some(0));
        let text = String::from_utf8_lossy(&o.stdout);
        assert!(
            text.contains("Exit status: 0 success; 1 invalid input or a failed run")
                && text.contains("2 a usage error"),
            "{text}"
        );
    }
}

#[test]
fn numeric_options_state_their_allowed_range() {
    let cases: [(&[&str], &str); 15] = [
        (
            &["--t-end", "-1"],
            "--t-end must be > 0 s and at most 1e9 s, got -1",
        ),
        (&["--t-end", "0"], "--t-end must be > 0 s"),
        (
            &["--t-end", "inf"],
            "--t-end must be > 0 s and at most 1e9 s, got inf",
        ),
        (&["--t-end", "2e9"], "at most 1e9 s, got 2000000000"),
        (
            &["--samples-per-second", "-5"],
            "--samples-per-second must be > 0 and finite, got -5",
        ),
        (
            &["--samples-per-second", "NaN"],
            "--samples-per-second must be > 0 and finite, got NaN",
        ),
        (
            &["--rtol", "inf"],
            "--rtol must be finite, at least 1e-15 and below 1, got inf",
        ),
        (
            &["--rtol", "1e-16"],
            "--rtol must be finite, at least 1e-15 and below 1",
        ),
        (
            &["--rtol", "1"],
            "--rtol must be finite, at least 1e-15 and below 1, got 1",
        ),
        (&["--atol", "0"], "--atol must be > 0 and finite, got 0"),
        (
            &["--atol", "-inf"],
            "--atol must be > 0 and finite, got -inf",
        ),
        (
            &["--step", "-1e-3"],
            "--step must be > 0 s and at most --t-end (10 s), got -0.001",
        ),
        (
            &["--step", "20"],
            "--step must be > 0 s and at most --t-end (10 s), got 20",
        ),
        (&["--set", "g=inf"], "--set g: the value must be finite"),
        (
            &["--init", "th1=1e400"],
            "--init th1: the value must be finite",
        ),
    ];
    for (extra, needle) in cases {
        let mut args = vec!["simulate", "planar_four_bar"];
        args.extend(extra);
        let o = mechanism(&args);
        assert_one_line_error(&o, needle);
        assert!(!stderr(&o).contains("-- -"), "no clap hint: {}", stderr(&o));
    }
    // The same ranges for inverse.
    let o = mechanism(&[
        "inverse",
        "planar_four_bar",
        "--drive",
        "th1 = t",
        "--t-end",
        "-1",
    ]);
    assert_one_line_error(&o, "--t-end must be > 0 s");
}
