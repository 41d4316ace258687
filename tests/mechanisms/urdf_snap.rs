//! UR5 (`mechanisms/urdf/ur5_robot.urdf`, whose angles are rounded to 11 decimals:
//! `1.57079632679` is 4.9e-12 rad from pi/2) imported with and without an angle snapping
//! tolerance: every link frame moves by no more than the header's stated deviation, and
//! the snapped robot's `mass_and_bias` program is smaller (the sines and cosines of exact
//! quarter turns fold to 0 and +-1). The macro's `snap_angles` gives the same frames.

use mechanism::Mechanism;
use mechanism::nalgebra::SVector;
use mechanism_codegen::{
    Model, Role, SnappedAngles, SymbolId, UrdfOptions, compile, derive, eval_matrix,
    parse_model_str, residual_tangent, urdf_import,
};

const UR5: &str = include_str!("../../mechanisms/urdf/ur5_robot.urdf");

// The user's route to the same import: the macro's `snap_angles`.
mechanism::mechanism!(
    urdf = "mechanisms/urdf/ur5_robot.urdf",
    name = Ur5Snapped,
    snap_angles = 1e-9,
);

fn imported(snap_angles: Option<f64>) -> (String, Option<SnappedAngles>) {
    let options = UrdfOptions {
        file_name: "ur5_robot.urdf".into(),
        snap_angles,
        ..Default::default()
    };
    let import = urdf_import(UR5, &options).expect("imported");
    (import.text, import.snapped)
}

/// Each link frame's (R, p), by name, at coordinates `q` (in declaration order).
fn frames(text: &str, q: &[f64]) -> Vec<(String, Vec<f64>, Vec<f64>)> {
    let mut model = parse_model_str(text).expect("parses");
    let eqs = derive(&mut model).expect("derives");
    let env = |s: SymbolId| value(&model, q, s);
    eqs.frames
        .iter()
        .map(|f| {
            let r = eval_matrix(&model.arena, &f.rotation, &env).expect("R");
            let p = eval_matrix(&model.arena, &f.position, &env).expect("p");
            (f.name.clone(), r, p)
        })
        .collect()
}

/// A coordinate's value from `q`, a parameter's default.
fn value(model: &Model, q: &[f64], s: SymbolId) -> Option<f64> {
    let coordinate = model
        .coordinates
        .iter()
        .position(|c| model.arena.as_symbol(c.q) == Some(s));
    if let Some(i) = coordinate {
        return Some(q[i]);
    }
    model
        .parameters
        .iter()
        .find(|p| model.arena.as_symbol(p.symbol) == Some(s))
        .map(|p| p.default)
}

/// The `xyz = [x, y, z];` offsets of the declaration's joints.
fn offsets(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .filter_map(|l| {
            l.trim()
                .strip_prefix("xyz = [")?
                .strip_suffix("];")
                .map(str::to_string)
        })
        .map(|v| {
            v.split(", ")
                .map(|x| x.parse().expect("a number"))
                .collect()
        })
        .collect()
}

fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}

#[test]
fn snapped_frames_move_by_at_most_the_stated_deviation() {
    let (plain, none) = imported(None);
    let (snapped, report) = imported(Some(1e-9));
    assert_eq!(none, None);
    let report = report.expect("reported");
    // UR5 writes pi/2 as 1.57079632679 in five origins (and pi as 3.14159265359).
    assert!(report.count >= 5, "{report:?}");
    assert!(plain.contains("1.57079632679") && !snapped.contains("1.57079632679"));
    // Every joint offset |xyz| summed: a frame's origin moves by at most the total turn of
    // the rotations before it times the lever arms after them, so by total * this.
    let reach: f64 = offsets(&plain)
        .iter()
        .map(|v| v.iter().map(|x| x * x).sum::<f64>().sqrt())
        .sum();
    assert!(reach > 1.0, "UR5 reaches about 1.4 m: {reach}");
    // Round-off of two evaluations of products of six rotations (entries O(1), a few
    // dozen operations each): below 1e-14, three orders under the deviations tested.
    let round_off = 1e-14;
    let mut moved = 0.0_f64;
    for k in 0..4 {
        let q: Vec<f64> = (0..6)
            .map(|i| 0.3 * k as f64 - 0.7 + 0.45 * i as f64)
            .collect();
        for ((name, r0, p0), (name1, r1, p1)) in frames(&plain, &q).iter().zip(frames(&snapped, &q))
        {
            assert_eq!(name, &name1);
            // |R0 - R1|_F = 2 sqrt(2) sin(theta / 2): the angle turned, to first order.
            let turn = distance(r0, &r1) / 2f64.sqrt();
            assert!(
                turn <= report.total + round_off,
                "{name}: turned {turn:e} > {:e}",
                report.total
            );
            let shift = distance(p0, &p1);
            assert!(
                shift <= report.total * reach + round_off,
                "{name}: moved {shift:e}"
            );
            moved = moved.max(turn);
            // The macro's frames are the snapped import's.
            let frame = Ur5Snapped::frame_index(name).expect("the same frames");
            let (r, p) = Ur5Snapped::default()
                .frame_placement(frame, &SVector::<f64, 6>::from_column_slice(&q))
                .expect("a placement");
            // nalgebra stores R column-major, the equations row-major.
            let r: Vec<f64> = r.transpose().iter().copied().collect();
            assert!(distance(&r, &r1) <= round_off, "{name}: R of the macro");
            assert!(
                distance(p.as_slice(), &p1) <= round_off,
                "{name}: p of the macro"
            );
        }
    }
    // The snap moved something: the frames past the rounded origins turn by its size.
    assert!(moved > 1e-12, "largest turn {moved:e}");
}

#[test]
fn snapped_quarter_turns_shrink_the_mass_and_bias_program() {
    let count = |text: &str| {
        let mut model = parse_model_str(text).expect("parses");
        let eqs = derive(&mut model).expect("derives");
        let tangent = residual_tangent(&mut model, &eqs).expect("a tangent");
        let routines = compile(&mut model, &eqs, &tangent).expect("compiles");
        routines
            .program(Role::MassAndBias)
            .expect("the role")
            .op_counts()
            .total()
    };
    let plain = count(&imported(None).0);
    let snapped = count(&imported(Some(1e-9)).0);
    assert!(
        snapped < plain,
        "mass_and_bias: {snapped} operations snapped, {plain} not"
    );
}
