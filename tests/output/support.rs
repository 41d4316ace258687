//! A synthetic seed-like trajectory with known maxima, shared by the `output_*` tests.
#![allow(dead_code)]

use std::f64::consts::PI;
use std::path::PathBuf;

use mechanism::{ConstraintRow, Independent, SolverStats, SystemInfo, Trajectory};

/// Samples: t = 0, 0.01, ..., 10 s.
pub const SAMPLES: usize = 1001;
/// Injected max |Phi|_inf, at sample 500.
pub const MAX_PHI: f64 = 3.5e-13;
/// Injected max |Phi_q q'|_inf, at sample 700.
pub const MAX_VEL: f64 = 7.25e-12;
/// Energy drift: W = DRIFT * t^2 while T + Pi = 1, so max |E - E0| = DRIFT * 100.
pub const DRIFT: f64 = 1e-9;
/// Parameter names and values.
pub const PARAMETERS: [(&str, f64); 3] = [("a1", 0.1), ("l2", 0.25), ("g", -9.81)];

pub fn info(name: &str) -> SystemInfo {
    SystemInfo {
        name: name.to_string(),
        coordinates: ["phi", "beta", "gamma", "x_c"]
            .iter()
            .map(|s| s.to_string())
            .collect(),
        parameters: PARAMETERS.iter().map(|p| p.0.to_string()).collect(),
        parameter_ranges: vec![Default::default(); PARAMETERS.len()],
        initial_guess: vec![0.0, 0.1, 0.2, 0.3],
        independent: vec![Independent {
            coordinate: 0,
            position: 0.0,
            velocity: 2.0 * PI,
        }],
        constraints: 3,
        constraint_rows: (0..3).map(ConstraintRow::unnamed).collect(),
        velocity_rows: 0,
        energy_depends_on_time: false,
        drawing: Default::default(),
        orientations: Vec::new(),
        joint_limits: Vec::new(),
        frames: Vec::new(),
    }
}

/// Time of sample `i`.
pub fn time(i: usize) -> f64 {
    i as f64 / 100.0
}

/// phi = 2 pi t; beta, gamma, x_c periodic; known constraint and energy errors.
pub fn trajectory(name: &str) -> Trajectory {
    let mut tr = Trajectory::with_capacity(info(name), SAMPLES);
    let w = 2.0 * PI;
    for i in 0..SAMPLES {
        let t = time(i);
        let (s, c) = (w * t).sin_cos();
        let q = [w * t, 0.4 * s, 0.3 + 0.2 * c, 0.15 + 0.05 * c];
        let qd = [w, 0.4 * w * c, -0.2 * w * s, -0.05 * w * s];
        let qdd = [0.0, -0.4 * w * w * s, -0.2 * w * w * c, -0.05 * w * w * c];
        let lambda = [10.0 * s, -3.0 * c, 0.5];
        let phi = match i {
            500 => MAX_PHI,
            0 => 0.0,
            _ => 1e-16 * (1.0 + s.abs()),
        };
        let vel = if i == 700 { -MAX_VEL } else { 1e-14 * c };
        let kinetic = 1.0 + 0.5 * s * s;
        let potential = 1.0 - kinetic;
        let work = DRIFT * t * t;
        tr.push(
            t,
            &q,
            &qd,
            &qdd,
            &lambda,
            phi,
            vel,
            [kinetic, potential, work],
        );
    }
    tr.stats = SolverStats {
        steps: 2000,
        rejected_steps: 7,
        rhs_evaluations: 12_034,
        wall_time_s: 0.125,
        augmented_solves: 0,
        banded_solves: 0,
        generated_solves: 0,
        factor_work: 0,
    };
    tr
}

/// Per-row residual series f_1..f_3; f_1 and f_3 contain exact zeros.
pub fn residuals() -> Vec<Vec<f64>> {
    let f1 = (0..SAMPLES)
        .map(|i| {
            if i % 50 == 0 {
                0.0
            } else {
                2e-16 * (1.0 + (time(i)).sin().abs())
            }
        })
        .collect();
    let f2 = (0..SAMPLES)
        .map(|i| 1e-13 * (1.0 + 0.5 * (3.0 * time(i)).sin()) * (time(i) / 10.0))
        .collect();
    let f3 = (0..SAMPLES)
        .map(|i| {
            if i < 300 {
                0.0
            } else {
                4e-15 * (1.0 + (2.0 * time(i)).cos().abs())
            }
        })
        .collect();
    vec![f1, f2, f3]
}

/// A fresh, empty directory `target/tmp/output/<tag>-<n>` (cargo's scratch folder for
/// integration tests; n counts the calls of this run): a run replaces the last run's
/// folders instead of adding to the system's temporary folder.
pub fn temp_dir(tag: &str) -> PathBuf {
    use std::sync::atomic::{AtomicUsize, Ordering};
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("output")
        .join(format!("{tag}-{n}"));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("create temp dir");
    dir
}

/// The names of the files in `dir`.
pub fn files_in(dir: &std::path::Path) -> std::collections::BTreeSet<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

/// `names` as a set, to compare with [`files_in`].
pub fn set(names: &[&str]) -> std::collections::BTreeSet<String> {
    names.iter().map(|s| s.to_string()).collect()
}
