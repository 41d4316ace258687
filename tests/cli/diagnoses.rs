//! Failures named for their real cause (issue 29, items 9 to 15): an over-specified
//! `independent`, a fixed step too large, a span too long, a drive out of reach, a drive's
//! kink, an unreachable start, a divergence under a huge parameter. Each message before
//! these changes blamed something else (the link lengths, a step-size collapse, conflicting
//! drives, a dead point, a NaN in gamma).

use super::{assert_one_line_error, mechanism, out_dir, stderr};

/// The planar four-bar's declaration with its `independent` line replaced by `line`.
fn four_bar_with(line: &str, name: &str) -> std::path::PathBuf {
    let src = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("mechanisms/planar_four_bar.mech"),
    )
    .expect("library mechanism");
    let old = "independent { th1 = pi/2; der(th1) = 10.0; }";
    assert!(src.contains(old));
    let dir = out_dir(&format!("diagnoses-{name}"));
    std::fs::create_dir_all(&dir).expect("scratch");
    let path = dir.join(format!("{name}.mech"));
    std::fs::write(&path, src.replace(old, line)).expect("written");
    path
}

#[test]
fn an_over_specified_independent_set_is_refused_naming_the_conflict() {
    // Every coordinate given, at the assembled values: consistent, still over-specified.
    let consistent = four_bar_with(
        "independent { th1 = pi/2; th2 = 0.523537196856287; th3 = 1.582721687434254; der(th1) = 10.0; }",
        "consistent",
    );
    let o = mechanism(&["simulate", consistent.to_str().unwrap(), "--t-end", "0.1"]);
    assert_one_line_error(
        &o,
        "`independent` gives 3 coordinates (th1, th2, th3), but the mechanism has 1 degree(s) of freedom: the constraints fix the other 2;",
    );
    assert!(!stderr(&o).contains("break"), "{}", stderr(&o));
    // th2 moved by 0.4 rad: the rows it breaks are named, not the link lengths.
    let conflicting = four_bar_with(
        "independent { th1 = pi/2; th2 = 0.923537196856287; th3 = 1.582721687434254; der(th1) = 10.0; }",
        "conflicting",
    );
    let o = mechanism(&["simulate", conflicting.to_str().unwrap(), "--t-end", "0.1"]);
    assert_one_line_error(&o, "and these values break constraint");
    assert!(!stderr(&o).contains("link lengths"), "{}", stderr(&o));
}

#[test]
fn a_fixed_step_too_large_is_named_not_the_link_lengths() {
    for method in ["rk4", "hht"] {
        let o = mechanism(&[
            "simulate",
            "planar_four_bar",
            "--integrator",
            method,
            "--step",
            "0.1",
            "--no-animation",
        ]);
        assert_one_line_error(
            &o,
            &format!("the fixed step h = 1e-1 s of {method} is too large for this motion"),
        );
        assert!(!stderr(&o).contains("link lengths"), "{}", stderr(&o));
    }
}

/// RK4 with h = 1 s on the seed (one crank turn per second): the first step throws the
/// state to angles of 1e5 rad and rates of 1e14 rad/s, and the projection fails at the
/// step's second sample. The samples inside the failed step go with it: only t = 0 is
/// kept, and no value in the file is absurd.
#[test]
fn the_samples_of_a_failed_step_are_not_kept() {
    let dir = out_dir("failed-step");
    let o = mechanism(&[
        "simulate",
        "spatial_crank_slider",
        "--integrator",
        "rk4",
        "--step",
        "1",
        "--no-animation",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_one_line_error(
        &o,
        "the fixed step h = 1e0 s of rk4 is too large for this motion",
    );
    assert_one_line_error(&o, "results up to t = 0 s are in");
    let csv = std::fs::read_to_string(dir.join("trajectory.csv")).unwrap();
    assert_eq!(csv.lines().count(), 2, "{csv}");
    let row: Vec<f64> = csv
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    assert!(row.iter().all(|v| v.abs() < 100.0), "{row:?}");
}

#[test]
fn a_span_too_long_for_the_step_is_named_not_a_collapse() {
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--t-end",
        "1e9",
        "--samples-per-second",
        "1e-6",
        "--no-animation",
    ]);
    assert_one_line_error(
        &o,
        "the time span is too long for this motion: its steps are a steady h = ",
    );
    assert!(!stderr(&o).contains("collapsed"), "{}", stderr(&o));
}

#[test]
fn a_drive_leaving_the_reach_is_named_not_a_conflict() {
    // x = t on a unit pendulum: x = 1 is the edge of the reach, x = 1.01 beyond it.
    let o = mechanism(&["inverse", "cartesian_pendulum", "--drive", "x = t"]);
    assert_one_line_error(
        &o,
        "the prescribed motion leaves the positions the mechanism can reach at t = 1.01 s: no configuration satisfies the constraints with x = 1.01",
    );
    assert!(!stderr(&o).contains("conflicting"), "{}", stderr(&o));
}

/// The slider of the slider-crank (r = 0.05 m, l = 0.2 m) driven over its whole stroke,
/// x = 0.2 + 0.05 sin(2 pi t): at t = 0.25 s it reaches x = l + r, the dead centre, and
/// turns back. There the crank bearing takes any force along the rod, so the slider's
/// driving force is not determined: a singular position, named as one (with one drive on
/// one degree of freedom it is no conflict of drives). With a stroke of 0.04 m the run
/// passes.
#[test]
fn a_drive_through_a_dead_centre_is_named_a_singular_position() {
    let o = mechanism(&[
        "inverse",
        "planar_slider_crank",
        "--drive",
        "x = 0.2 + 0.05*sin(2*pi*t)",
    ]);
    assert_one_line_error(
        &o,
        "the drive of [\"x\"] is at a singular position at t = 0.25 s: there the constraints \
         fix its motion (a dead point of the mechanism)",
    );
    let o = mechanism(&[
        "inverse",
        "planar_slider_crank",
        "--drive",
        "x = 0.2 + 0.04*sin(2*pi*t)",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

/// Too few drives and a coordinate driven twice: each named in the terms of `inverse`.
#[test]
fn too_few_drives_and_a_repeated_drive_are_named() {
    let o = mechanism(&["inverse", "five_bar", "--drive", "th1 = 2*t"]);
    assert_one_line_error(
        &o,
        "the drives of [\"th1\"] leave 1 degree(s) of freedom free at t = 0 s: the motion is \
         not prescribed; add 1 drive(s)",
    );
    let o = mechanism(&[
        "inverse",
        "planar_slider_crank",
        "--drive",
        "th = 2*pi*t",
        "--drive",
        "th = t",
    ]);
    assert_one_line_error(&o, "coordinate `th` is given twice");
    // A parse error's column counts from the start of the drive as written: the end of
    // `th = 2*pi*t +` is column 14.
    let o = mechanism(&["inverse", "planar_slider_crank", "--drive", "th = 2*pi*t +"]);
    assert_one_line_error(
        &o,
        "in the drive `th = 2*pi*t +`: parse error at line 1, column 14: expected a number",
    );
}

#[test]
fn a_kink_of_a_drive_is_found_on_a_sample_and_between_samples() {
    for (at, needle) in [("0.5", "t = 0.5 s"), ("0.505", "t = 0.505")] {
        let drive = format!("x = 0.3 + 0.2*abs(t - {at})");
        let o = mechanism(&["inverse", "cartesian_pendulum", "--drive", &drive]);
        assert_one_line_error(&o, "the drive of x has a kink at ");
        assert_one_line_error(&o, needle);
        assert_one_line_error(&o, "its rate jumps from -0.2 to 0.2");
    }
    // A smooth drive at the same rate passes.
    let o = mechanism(&[
        "inverse",
        "cartesian_pendulum",
        "--drive",
        "x = 0.3 + 0.2*sin(3*t)",
    ]);
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
}

#[test]
fn an_unreachable_start_is_named_not_a_dead_point() {
    let o = mechanism(&["inverse", "planar_four_bar", "--drive", "th3 = 2*pi*t"]);
    assert_one_line_error(
        &o,
        "the prescribed motion leaves the positions the mechanism can reach at t = 0 s: no configuration satisfies the constraints with th3 = 0",
    );
    assert_one_line_error(&o, "at the start, from the declared guesses");
    assert!(!stderr(&o).contains("dead point"), "{}", stderr(&o));
}

#[test]
fn a_huge_gravity_is_not_blamed_on_a_nan_in_gamma() {
    // g = 1e10: the first trial steps diverged (q about 1e124 at a stage, where gamma
    // overflowed to NaN at t = 0.0014 s) and the run stopped, blaming gamma. A stage that
    // cannot be evaluated now rejects the step, and the run goes on with smaller ones.
    let o = mechanism(&[
        "simulate",
        "spatial_crank_slider",
        "--set",
        "g=1e10",
        "--t-end",
        "0.003",
        "--no-animation",
    ]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{e}");
    assert!(!e.contains("gamma row"), "{e}");
}

/// Issue 53, item 12: x = 1.5 is out of reach of a pendulum of length 1. Before: "start
/// from a closer guess or check the link lengths". A start from the guess y = 0 with
/// x = 0.5, where Newton cannot move (Phi_y = 0) but positions exist, keeps that advice.
#[test]
fn a_given_value_out_of_reach_is_named_not_the_guess() {
    let o = mechanism(&["simulate", "cartesian_pendulum", "--init", "x=1.5"]);
    assert_one_line_error(
        &o,
        "the given values admit no position at t = 0 s: with x = 1.5 the constraints cannot be closed",
    );
    assert_one_line_error(&o, "the nearest values that admit one are x = 1:");
    assert!(!stderr(&o).contains("closer guess"), "{}", stderr(&o));
    let o = mechanism(&[
        "simulate",
        "cartesian_pendulum",
        "--init",
        "x=0.5",
        "--init",
        "y=0",
    ]);
    assert_one_line_error(&o, "start from a closer guess");
    // A coupler too short for any crank angle near these: the lengths are to blame.
    let o = mechanism(&[
        "simulate",
        "planar_four_bar",
        "--set",
        "l2=0.01",
        "--set",
        "Dx=2",
    ]);
    assert_one_line_error(
        &o,
        "the constraints cannot be satisfied near the initial guess",
    );
}

/// The `phi = VALUE (` of a coordinate-singularity message.
fn lean_in(message: &str) -> f64 {
    let at = message.find(", phi = ").expect("the lean named") + ", phi = ".len();
    let rest = &message[at..];
    rest[..rest.find(' ').unwrap()].parse().expect("a number")
}

/// Issue 53, item 11: a disc or a bicycle that falls over stopped with "the mass matrix
/// gives no inertia to an allowed motion of psi, th": the body lies flat, where the axes of
/// the yaw and the spin (or pitch) of rot_z(psi) rot_x(phi) rot_y(..) line up, cos(phi) = 0.
#[test]
fn a_body_that_falls_flat_is_named_a_singularity_of_its_angles() {
    let dir = out_dir("diagnoses-flat-disc");
    let o = mechanism(&[
        "simulate",
        "rolling_disc",
        "--init",
        "der(th)=0",
        "--t-end",
        "2",
        "--figures",
        "none",
        "--no-animation",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_one_line_error(
        &o,
        "a coordinate singularity of the orientation angles at t = 0.64",
    );
    assert_one_line_error(
        &o,
        "in body `disc`'s rot_z(psi) rot_x(phi) rot_y(th) the axes of psi and th line up (its y axis lies along the world z axis)",
    );
    // The run stops where the step cannot go on, within 1e-3 rad of the singular lean.
    let lean = lean_in(&stderr(&o));
    assert!(
        (lean.abs() - std::f64::consts::FRAC_PI_2).abs() < 1e-3,
        "{lean}"
    );
    assert!(!stderr(&o).contains("gives no inertia to an allowed motion"));

    let dir = out_dir("diagnoses-flat-bicycle");
    let o = mechanism(&[
        "simulate",
        "whipple_bicycle",
        "--set",
        "v=0.5",
        "--init",
        "der(phi)=0.5",
        "--t-end",
        "5",
        "--figures",
        "none",
        "--no-animation",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_one_line_error(
        &o,
        "in body `rear_frame`'s rot_z(psi) rot_x(phi) rot_y(theta) the axes of psi and theta line up",
    );
    let lean = lean_in(&stderr(&o));
    assert!(
        (lean.abs() - std::f64::consts::FRAC_PI_2).abs() < 1e-3,
        "{lean}"
    );
}
