//! `mechanism simulate` of a floating-base declaration as a user runs it: a tumbling,
//! falling brick against its closed form (the centre of mass on a parabola, the angular
//! momentum about it constant, T + Pi constant), Solo12 imported with `--floating` and
//! dropped, and the bad inputs as one line each with the output folder left as it was.

use super::{assert_one_line_error, csv_header, mechanism, out_dir, stderr};

/// A brick whose centre of mass is the root's origin, so that the root's origin is the
/// centre of mass and moves on the parabola x0 + u0 t + 1/2 g t^2.
const BRICK: &str = "
pub struct Brick;
parameters { g = 9.81; m = 3.0 positive; }
gravity = [0, 0, -g];
link body {
    joint = floating(base);
    mass = m;
    inertia = [[0.2, 0.01, -0.02], [0.01, 0.35, 0.03], [-0.02, 0.03, 0.5]];
}
";

const INERTIA: [[f64; 3]; 3] = [[0.2, 0.01, -0.02], [0.01, 0.35, 0.03], [-0.02, 0.03, 0.5]];

/// R of the unit quaternion (x, y, z, w).
fn rotation([x, y, z, w]: [f64; 4]) -> [[f64; 3]; 3] {
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - z * w),
            2.0 * (x * z + y * w),
        ],
        [
            2.0 * (x * y + z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - x * w),
        ],
        [
            2.0 * (x * z - y * w),
            2.0 * (y * z + x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

fn apply(r: &[[f64; 3]; 3], x: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|i| r[i][0] * x[0] + r[i][1] * x[1] + r[i][2] * x[2])
}

fn rows(path: &std::path::Path) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(path).unwrap();
    (text.lines().skip(1))
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

fn summary(dir: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap()
}

/// The brick thrown tumbling from a turned start for 3 s at the default step (1e-3):
/// the root's origin on the closed-form parabola and the world's angular momentum about it,
/// R I w, constant, both to 1e-9 of their size (RK4's global error on this motion is about
/// 1e-11: the run's T + Pi moves by that much); summary.json's E(0) the closed form
/// 1/2 m |u|^2 + 1/2 w^T I w + m g z0 to 1e-12, and its checks under 1e-9 of their scales.
#[test]
fn a_tumbling_brick_follows_its_closed_form() {
    let dir = out_dir("floating-brick");
    std::fs::create_dir_all(&dir).unwrap();
    let mech = dir.join("brick.mech");
    std::fs::write(&mech, BRICK).unwrap();
    let out = dir.join("run");
    // A quarter turn about (1, 1, 1)/sqrt(3): (sin(pi/8) n, cos(pi/8)).
    let s = (std::f64::consts::PI / 8.0).sin() / 3f64.sqrt();
    let quat = [s, s, s, (std::f64::consts::PI / 8.0).cos()];
    let (x0, v, w) = ([0.5, -0.2, 1.0], [0.4, -0.3, 2.0], [1.2, -0.7, 2.5]);
    let init = |name: &str, value: f64| format!("--init=base_{name}={value:.17e}");
    let mut args = vec!["simulate".to_string(), mech.to_str().unwrap().into()];
    args.extend(["--t-end", "3", "--out", out.to_str().unwrap()].map(String::from));
    for (k, name) in ["x", "y", "z"].iter().enumerate() {
        args.push(init(name, x0[k]));
    }
    for (k, name) in ["qx", "qy", "qz", "qw"].iter().enumerate() {
        args.push(init(name, quat[k]));
    }
    for (k, name) in ["vx", "vy", "vz", "wx", "wy", "wz"].iter().enumerate() {
        args.push(init(name, if k < 3 { v[k] } else { w[k - 3] }));
    }
    let args: Vec<&str> = args.iter().map(String::as_str).collect();
    let o = mechanism(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let header = csv_header(&out.join("trajectory.csv"));
    let names = "t base_x base_y base_z base_qx base_qy base_qz base_qw base_vx base_vy base_vz \
                 base_wx base_wy base_wz";
    assert_eq!(header.join(" "), names);
    for figure in ["configuration.png", "configuration.svg", "velocities.png"] {
        assert!(out.join(figure).is_file(), "{figure}");
    }
    let r0 = rotation(quat);
    let u0 = apply(&r0, v);
    let (m, g) = (3.0, 9.81);
    let l0 = apply(&r0, apply(&INERTIA, w));
    let samples = rows(&out.join("trajectory.csv"));
    assert_eq!(samples.len(), 301);
    let (mut worst_x, mut worst_l) = (0.0_f64, 0.0_f64);
    for row in &samples {
        let t = row[0];
        let fall = [0.0, 0.0, -0.5 * g * t * t];
        for i in 0..3 {
            worst_x = worst_x.max((row[1 + i] - (x0[i] + u0[i] * t + fall[i])).abs());
        }
        let r = rotation([row[4], row[5], row[6], row[7]]);
        let l = apply(&r, apply(&INERTIA, [row[11], row[12], row[13]]));
        for i in 0..3 {
            worst_l = worst_l.max((l[i] - l0[i]).abs());
        }
    }
    let l_scale = l0.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
    // The parabola's size: the fall over 3 s, 1/2 g t^2 = 44 m.
    let x_scale = 0.5 * g * 9.0;
    assert!(worst_x < 1e-9 * x_scale, "parabola: {worst_x:e}");
    assert!(worst_l < 1e-9 * l_scale, "R I w: {worst_l:e}");
    let c = &summary(&out)["conservation"];
    let wiw: f64 = (0..3).map(|i| w[i] * apply(&INERTIA, w)[i]).sum();
    let e0 = 0.5 * m * v.iter().map(|x| x * x).sum::<f64>() + 0.5 * wiw + m * g * x0[2];
    let read = |key: &str| c[key].as_f64().unwrap();
    assert!((read("energy_initial") - e0).abs() < 1e-12 * e0, "{c}");
    assert!(read("max_energy_error") < 1e-9 * e0, "{c}");
    assert!(
        read("max_linear_momentum_error") < 1e-9 * m * g * 3.0,
        "{c}"
    );
    assert!(read("max_angular_momentum_error") < 1e-9 * l_scale, "{c}");
    assert!(read("max_quaternion_norm_error") < 1e-15, "{c}");
    assert_eq!(c["efforts_declared"], false);
}

/// Solo12 imported with `--floating`, its legs swinging and its base spinning as it falls
/// for 1 s: summary.json's T + Pi, p - m g t and L about the centre of mass kept to 1e-9 of
/// their scales (E(0), m g t_end, |L| at the start from the macro route's run of the same
/// state: floating_motion.rs measures about 1e-12 there), the quaternion unit.
#[test]
fn a_falling_solo12_through_the_cli() {
    let dir = out_dir("floating-solo12");
    std::fs::create_dir_all(&dir).unwrap();
    let mech = dir.join("solo12.mech");
    let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/mechanisms/urdf/solo12.urdf");
    let o = mechanism(&[
        "import",
        urdf,
        "--floating",
        "--out",
        mech.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = dir.join("run");
    let o = mechanism(&[
        "simulate",
        mech.to_str().unwrap(),
        "--t-end",
        "1",
        "--out",
        out.to_str().unwrap(),
        "--init",
        "root_joint_z=0.4",
        "--init",
        "root_joint_wx=1.5",
        "--init",
        "root_joint_wz=-2",
        "--init",
        "root_joint_vy=0.7",
        "--init",
        "FL_HFE=0.6",
        "--init",
        "der(FL_HFE)=3",
        "--init",
        "der(HR_KFE)=-2",
        "--figures",
        "none",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.starts_with("Solo: floating base, rk4"), "{text}");
    let s = summary(&out);
    assert_eq!(s["status"], "completed");
    assert_eq!(s["initial_state"]["v"]["FL_HFE"], 3.0);
    assert_eq!(s["initial_state"]["q"]["root_joint_qw"], 1.0);
    let c = &s["conservation"];
    let read = |key: &str| c[key].as_f64().unwrap();
    let samples = rows(&out.join("trajectory.csv"));
    assert_eq!(samples[0].len(), 1 + 19 + 18);
    let mass = 2.5; // Solo12's total mass is about 2.5 kg: a scale, not a check.
    assert!(
        read("max_energy_error") < 1e-9 * read("energy_initial").abs(),
        "{c}"
    );
    assert!(
        read("max_linear_momentum_error") < 1e-9 * mass * 9.81,
        "{c}"
    );
    assert!(read("max_angular_momentum_error") < 1e-9, "{c}");
    assert!(read("max_quaternion_norm_error") < 1e-15, "{c}");
}

/// The bad inputs of a floating run, one line and exit status 1 each, with a previous run's
/// folder left as it was: a quaternion off unit after `--init`, a parameter outside its
/// range, an unknown entry, an integrator the floating step is not; `linearize` and
/// `inverse` refuse a floating base; `equations` prints it.
#[test]
fn floating_bad_inputs_are_one_line() {
    let dir = out_dir("floating-bad");
    std::fs::create_dir_all(&dir).unwrap();
    let mech = dir.join("brick.mech");
    std::fs::write(&mech, BRICK).unwrap();
    let (mech, out) = (mech.to_str().unwrap(), dir.join("run"));
    let out_s = out.to_str().unwrap();
    let o = mechanism(&["simulate", mech, "--t-end", "0.1", "--out", out_s]);
    assert!(o.status.success(), "{}", stderr(&o));
    // 0.1 / 1e-3 is 100.00000000000001 in f64: still 100 steps, ending at t = 0.1.
    let s = summary(&out);
    assert_eq!(
        (s["steps"].as_u64(), s["t_last"].as_f64()),
        (Some(100), Some(0.1))
    );
    let before = std::fs::read(out.join("summary.json")).unwrap();
    let cases: [(&[&str], &str); 4] = [
        (
            &["--init", "base_qw=2"],
            "--init: the root's quaternion (x, y, z, w) = [0.0, 0.0, 0.0, 2.0] has norm 2, not 1",
        ),
        (&["--set", "m=-1"], "`m` must be greater than 0"),
        (
            &["--init", "base_vq=1"],
            "unknown entry `base_vq` (did you mean",
        ),
        (
            &["--integrator", "hht"],
            "has a floating base, which steps by fixed RK4",
        ),
    ];
    for (extra, needle) in cases {
        let mut args = vec!["simulate", mech, "--t-end", "0.1", "--out", out_s];
        args.extend(extra);
        assert_one_line_error(&mechanism(&args), needle);
        assert_eq!(
            std::fs::read(out.join("summary.json")).unwrap(),
            before,
            "{extra:?}"
        );
    }
    // Within 1e-9 of unit (norm 1 + 5e-13): normalised and run.
    let o = mechanism(&[
        "simulate",
        mech,
        "--t-end",
        "0.1",
        "--out",
        out_s,
        "--init",
        "base_qx=1e-6",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_one_line_error(
        &mechanism(&["linearize", mech]),
        "has a floating base (q has 7 entries, v 6), which `mechanism linearize` does not take",
    );
    assert_one_line_error(
        &mechanism(&["inverse", mech, "--drive", "base_vx = t"]),
        "which `mechanism inverse` does not take",
    );
    let o = mechanism(&["equations", mech]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.starts_with("Floating base: the coordinates below are the velocities v"));
    assert!(text.contains("Mobility: a floating base, no constraint rows: 6 + 0 degrees"));
}
