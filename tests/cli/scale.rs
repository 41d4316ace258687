//! Output that scales with the mechanism: the A02 chain of 40 four-bar loops (82
//! coordinates, 81 constraint rows) run with the defaults writes a few files and a short
//! summary, where one figure per coordinate and a table row per coordinate would be 171
//! files and 92 lines; `--figures` chooses the figures for any mechanism.

use std::path::Path;

use super::{fresh_cwd, mechanism, mechanism_in, out_dir, stderr};

/// Every entry of `dir` (files and folders alike, the lock file included).
fn entries(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("output folder")
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn the_a02_chain_with_defaults_writes_at_most_20_files_and_40_lines() {
    let cwd = fresh_cwd();
    let o = mechanism_in(&cwd, &["simulate", "n_four_bar"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let dir = cwd.join("out").join("n_four_bar");
    let files = entries(&dir);
    assert!(files.len() <= 20, "{} entries: {files:?}", files.len());
    let stdout = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = stdout.lines().collect();
    assert!(lines.len() <= 40, "{} lines:\n{stdout}", lines.len());
    // The overview and the constraint error instead of 82 coordinate figures; the drawing.
    for f in [
        "trajectory.csv",
        "summary.json",
        "coordinates.png",
        "coordinates.svg",
        "constraint_error.png",
        "animation.html",
        "mechanism.png",
    ] {
        assert!(files.iter().any(|n| n == f), "{f} in {files:?}");
    }
    assert!(!files.iter().any(|n| n == "x1.png"), "{files:?}");
    // The last line names the folder and the count of what summary.json lists.
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let listed = summary["files"].as_array().expect("files").len();
    let last = lines.last().copied().unwrap_or("");
    let folder = Path::new("out").join("n_four_bar");
    let expected = format!(
        "wrote {listed} files to {} (listed in summary.json)",
        folder.display()
    );
    assert_eq!(last, expected);
    // The table of 82 initial values is in the summary file, not on the terminal.
    let q0 = summary["consistent_initial_state"]["q"]
        .as_object()
        .expect("q(0)");
    assert_eq!(q0.len(), 82);
    assert!(stdout.contains("in summary.json"), "{stdout}");
    // The page stays under the documented 1.5 MB.
    let page = std::fs::metadata(dir.join("animation.html")).unwrap().len();
    assert!(page < 1_500_000, "animation.html is {page} bytes");
}

#[test]
fn figures_picks_every_coordinate_one_overview_or_none() {
    let run = |figures: &str| {
        let dir = out_dir(&format!("figures-{figures}"));
        let d = dir.to_str().unwrap();
        let args = [
            "simulate",
            "planar_four_bar",
            "--t-end",
            "0.3",
            "--figures",
            figures,
        ];
        let o = mechanism(&[&args[..], &["--no-animation", "--out", d]].concat());
        assert!(o.status.success(), "{}", stderr(&o));
        entries(&dir)
            .into_iter()
            .filter(|n| n.ends_with(".png"))
            .collect::<Vec<_>>()
    };
    // The four-bar's coordinates: th1, th2, th3 (3 <= 12: auto is all).
    let all = ["constraint_error.png", "th1.png", "th2.png", "th3.png"];
    assert_eq!(run("all"), all);
    assert_eq!(run("auto"), all);
    assert_eq!(run("overview"), ["constraint_error.png", "coordinates.png"]);
    assert!(run("none").is_empty());
}

/// A run that cannot get past a singular position says so, and what passes it: A02 without
/// stabilisation drifts off the constraints, and the drift, amplified there, collapses the
/// step at the first flat configuration (t = 0.7216 s); one line, exit 1, the partial
/// results kept.
#[test]
fn a_run_stuck_at_a_singular_position_names_it_and_what_passes_it() {
    let dir = out_dir("stuck-singular");
    let d = dir.to_str().unwrap();
    let o = mechanism(&[
        "simulate",
        "n_four_bar",
        "--t-end",
        "2",
        "--stabilization",
        "none",
        "--no-animation",
        "--out",
        d,
    ]);
    assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
    let err = stderr(&o);
    let line = err.lines().find(|l| l.starts_with("error:")).expect(&err);
    assert!(line.contains("next to a singular position"), "{line}");
    assert!(line.contains("--stabilization projection"), "{line}");
    assert!(line.contains("t = 0.72"), "{line}");
}

/// A serial chain of 45 revolute links (no constraint rows, n past the dense LU routes'
/// 40): `simulate` solves every integration stage by the mechanism's generated forward
/// dynamics and says so in summary.json; only the start and the output samples (which
/// record T and Pi from the evaluation) take the dense route, one solve each.
#[test]
fn a_long_chain_is_integrated_by_its_generated_forward_dynamics() {
    let cwd = fresh_cwd();
    let axes = ["[0, 0, 1]", "[0, 1, 0]", "[1, 0, 0]"];
    let mut text =
        String::from("pub struct Chain45;\nparameters { g = 9.81; }\ngravity = [0, 0, -g];\n");
    for i in 1..=45 {
        let parent = match i {
            1 => String::new(),
            _ => format!("parent = l{}; xyz = [0, 0, 0.1]; ", i - 1),
        };
        text += &format!(
            "link l{i} {{ {parent}joint = revolute(q{i}, {}); mass = 1; com = [0.01, 0, 0.05]; \
             inertia = [[0.0042, 0.0001, -0.0002], [0.0001, 0.0041, 0.0003], [-0.0002, 0.0003, 0.0008]]; }}\n",
            axes[(i - 1) % 3]
        );
    }
    std::fs::write(cwd.join("chain45.mech"), text).unwrap();
    let o = mechanism_in(
        &cwd,
        &[
            "simulate",
            "chain45.mech",
            "--t-end",
            "0.05",
            "--figures",
            "none",
            "--no-animation",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(cwd.join("out").join("chain45").join("summary.json")).unwrap(),
    )
    .unwrap();
    let count = |k: &str| summary[k].as_u64().unwrap_or_else(|| panic!("{k}"));
    // 0.05 s at 100 samples a second: 6 samples, t = 0 included.
    assert!(count("generated_solves") > 0);
    assert_eq!(count("generated_solves") + 6 + 1, count("rhs_evaluations"));
}
