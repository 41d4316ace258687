//! The implicit integrator through the command-line tool: a `.mech` file runs through the
//! interpreter with the residual's exact tangent, as the built-in (compiled) copy of the
//! same declaration does, not with the finite-difference fallback.

use super::{mechanism, out_dir, stderr};

/// The right-hand-side evaluations a run reports in its summary.
fn evaluations(out: &std::path::Path) -> u64 {
    let text = std::fs::read_to_string(out.join("summary.json")).expect("summary.json");
    let json: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    json["rhs_evaluations"].as_u64().expect("rhs_evaluations")
}

/// HHT on `mechanisms/planar_four_bar.mech` and on the built-in `planar_four_bar` counts
/// the same evaluations: the interpreter's routines are the compiled ones, so the two runs
/// take the same Newton iterations. Finite differences would add 2 n = 8 evaluations per
/// Jacobian, one Jacobian per step at least.
#[test]
fn hht_on_a_file_takes_the_exact_tangent() {
    let file = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/mechanisms/planar_four_bar.mech"
    );
    let mut counts = Vec::new();
    for (key, spec) in [("file", file), ("builtin", "planar_four_bar")] {
        let out = out_dir(&format!("implicit-{key}"));
        let o = mechanism(&[
            "simulate",
            spec,
            "--integrator",
            "hht",
            "--t-end",
            "0.5",
            "--no-animation",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", stderr(&o));
        counts.push(evaluations(&out));
    }
    assert!(counts[0] > 0);
    assert_eq!(counts[0], counts[1], "file, built-in");
}
