//! A hand-built scene with a closed form: the crank-rocker four-bar (ground pivots O and D,
//! crank O-A, coupler A-B, rocker B-D) with the crank turning at 1 rev/s.

use std::f64::consts::PI;

use mechanism::output::{Scene, SceneCoordinate, ScenePoint};

/// Crank, coupler, rocker and ground lengths (m).
pub const L: [f64; 4] = [0.1, 0.4, 0.3, 0.35];

/// O, A, B, D at crank angle th (B on the upper circle intersection).
pub fn four_bar(th: f64) -> [[f64; 3]; 4] {
    let [l1, l2, l3, dx] = L;
    let a = [l1 * th.cos(), l1 * th.sin()];
    let (ux, uy) = (dx - a[0], -a[1]);
    let d = (ux * ux + uy * uy).sqrt();
    // Distance from A along A->D to the chord through the two intersections.
    let along = (l2 * l2 - l3 * l3 + d * d) / (2.0 * d);
    let h = (l2 * l2 - along * along).sqrt();
    let (ex, ey) = (ux / d, uy / d);
    let b = [a[0] + along * ex - h * ey, a[1] + along * ey + h * ex];
    [
        [0.0, 0.0, 0.0],
        [a[0], a[1], 0.0],
        [b[0], b[1], 0.0],
        [dx, 0.0, 0.0],
    ]
}

/// `frames` frames over 1 s.
pub fn four_bar_scene(frames: usize) -> Scene {
    let times: Vec<f64> = (0..frames)
        .map(|k| k as f64 / (frames - 1) as f64)
        .collect();
    let th: Vec<f64> = times.iter().map(|t| PI / 2.0 + 2.0 * PI * t).collect();
    let positions = th
        .iter()
        .flat_map(|&a| four_bar(a).into_iter().flatten())
        .collect();
    let point = |name: &str, ground| ScenePoint {
        name: name.into(),
        ground,
    };
    Scene {
        name: "four_bar".into(),
        note: "closed form".into(),
        points: vec![
            point("O", true),
            point("A", false),
            point("B", false),
            point("D", true),
        ],
        lines: vec![vec![0, 1], vec![1, 2], vec![2, 3]],
        traces: vec![2],
        times,
        positions,
        coordinates: vec![SceneCoordinate {
            name: "th1".into(),
            unit: "rad".into(),
            values: th,
        }],
        decimation: 1,
        driver: None,
    }
}
