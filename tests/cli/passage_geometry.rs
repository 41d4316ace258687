//! The geometry of the singular positions a run passes, as the user meets it: a passage
//! through an apex (a point the motion can miss, `src/simulation/apex.rs`) carries a
//! warning and `"geometry": "apex"` in summary.json; a crossing of branches, which every
//! nearby motion passes through, carries neither, whatever the mobility.

use std::path::Path;

use mechanism_test_support::a02::angles_declaration;

use super::{out_dir, simulate_to, stderr};

/// Runs `target` (a built-in name or a file) to `t_end` into `dir` with `extra` settings;
/// returns the process output and the parsed summary.json.
fn run(
    target: &str,
    dir: &Path,
    t_end: &str,
    extra: &[&str],
) -> (std::process::Output, serde_json::Value) {
    let o = simulate_to(target, dir, t_end, extra);
    assert!(o.status.success(), "{target}: {}", stderr(&o));
    let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    (o, serde_json::from_str(&text).unwrap())
}

fn geometries(summary: &serde_json::Value) -> Vec<String> {
    summary["singular_passages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["geometry"].as_str().unwrap().to_string())
        .collect()
}

/// The five-bar started 5.4e-8 rad off its symmetric pose (th2 = 1.1415926 instead of
/// pi - 2) misses the apex of its flat configuration and turns around it onto the other
/// assembly mode: th1(0.5 s) = 4.294590 rad by the 50-digit reference
/// (`tests/fixtures/five_bar_near_miss.py`), where the run at the default tolerance goes
/// straight through as the symmetric motion does (5.909 rad, measured). The miss is below
/// what the steps resolve, so the run cannot be right; it must say so: the passage is an
/// apex a step went over (w at its ends about 1e5 times the minimum inside), with the
/// warning. The symmetric start passes the same apex exactly and is flagged the same way
/// (its continuation is one an asymmetry below the tolerance would change). Started
/// 2.7e-6 rad off (th2 = 1.14159) the steps follow the turn (w below 1e-3 first at a step's
/// end, 9.4e-4: the ratio is 1): an apex not stepped over, with a note, not the warning.
#[test]
fn a_passage_through_the_five_bars_apex_is_flagged() {
    for (name, extra, over) in [
        ("near-miss", &["--init", "th2=1.1415926"][..], true),
        ("symmetric", &[][..], true),
        ("turned", &["--init", "th2=1.14159"][..], false),
    ] {
        let dir = out_dir(&format!("passage_geometry/five-bar-{name}"));
        let (o, summary) = run("five_bar", &dir, "0.5", extra);
        assert_eq!(geometries(&summary), ["apex"], "{name}");
        assert_eq!(
            summary["singular_passages"][0]["stepped_over"], over,
            "{name}"
        );
        let report = String::from_utf8_lossy(&o.stdout);
        let flagged: Vec<&str> = report
            .lines()
            .filter(|l| l.starts_with("warning:") || l.starts_with("note:"))
            .collect();
        assert_eq!(flagged.len(), 1, "{name}: {report}");
        let needles = if over {
            [
                "warning: a step went straight over an apex at 0.294",
                "not determined",
            ]
        } else {
            [
                "note: the motion turned around an apex within its steps at 0.294",
                "compare two",
            ]
        };
        for needle in needles {
            assert!(
                flagged[0].contains(needle),
                "{name}: `{needle}` in {report}"
            );
        }
    }
}

/// A02 with three rhombus windows and a free slider beside them (x, 1 kg, no force):
/// mobility 2, so the forms are taken, but the windows fold along x as well (the singular
/// set is a line of the two-dimensional configuration set), so every passage is a
/// crossing, unflagged. Without the slider (mobility 1) the same passages are crossings
/// with no form taken.
#[test]
fn crossings_beside_a_free_coordinate_are_not_flagged() {
    for slider in [true, false] {
        let mut text = angles_declaration(3, false);
        if slider {
            text = text
                .replace("coordinates {\n", "coordinates {\n    x = 0.0;\n")
                .replace("independent { ", "independent { x = 0.0; ")
                .replace("kinetic = ", "kinetic = der(x)^2/2 + ");
        }
        let dir = out_dir(&format!("passage_geometry/a02-3-slider-{slider}"));
        std::fs::create_dir_all(&dir).unwrap();
        let file = dir.join("a02.mech");
        std::fs::write(&file, text).unwrap();
        let out = dir.join("run");
        let (o, summary) = run(file.to_str().unwrap(), &out, "1.5", &["--rtol", "1e-7"]);
        let found = geometries(&summary);
        assert!(found.len() >= 2, "slider {slider}: {found:?}");
        assert!(
            found.iter().all(|g| g == "crossing"),
            "slider {slider}: {found:?}"
        );
        let report = String::from_utf8_lossy(&o.stdout);
        assert!(
            !report.contains("warning:") && !report.contains("note:"),
            "slider {slider}: {report}"
        );
    }
}
