//! The Whipple bicycle benchmark (Meijaard, Papadopoulos, Ruina, Schwab, Proc. R. Soc. A 463,
//! 2007): `mechanisms/whipple_bicycle.mech` (four bodies, two rolling wheels), linearised
//! about the upright steady motion through `linearize_steady`, against the paper's Table 2
//! eigenvalues and its weave and capsize speeds.

use mechanism::nalgebra::Complex;
use mechanism::{Interpreted, SteadyLinearization, SteadyOptions, linearize_steady};

use crate::common::{assemble_with, load};

/// The rear wheel radius rR of the declaration (m).
const REAR_RADIUS: f64 = 0.3;

/// Table 2 of the paper: the four eigenvalues (1/s) at v = 0, 1, .., 10 m/s, [re, im].
const TABLE_2: [[[f64; 2]; 4]; 11] = [
    [
        [-5.53094371765393, 0.0],
        [-3.13164324790656, 0.0],
        [3.13164324790656, 0.0],
        [5.53094371765393, 0.0],
    ],
    [
        [-7.11008014637442, 0.0],
        [-3.13423125066578, 0.0],
        [3.52696170990070, -0.8077402751993],
        [3.52696170990070, 0.8077402751993],
    ],
    [
        [-8.67387984831735, 0.0],
        [-3.07158645641514, 0.0],
        [2.68234517512745, -1.68066296590675],
        [2.68234517512745, 1.68066296590675],
    ],
    [
        [-10.3510146724592, 0.0],
        [-2.63366137253667, 0.0],
        [1.70675605663975, -2.31582447384325],
        [1.70675605663975, 2.31582447384325],
    ],
    [
        [-12.1586142657645, 0.0],
        [-1.42944427361326, 0.0],
        [0.41325331521125, -3.07910818603206],
        [0.41325331521125, 3.07910818603206],
    ],
    [
        [-14.0783896927982, 0.0],
        [-0.77534188219585, -4.46486771378823],
        [-0.77534188219585, 4.46486771378823],
        [-0.32286642900409, 0.0],
    ],
    [
        [-16.0853712309803, 0.0],
        [-1.52644486584142, -5.87673060598709],
        [-1.52644486584142, 5.87673060598709],
        [-0.00406690076970, 0.0],
    ],
    [
        [-18.15788466125262, 0.0],
        [-2.13875644258362, -7.19525913329805],
        [-2.13875644258362, 7.19525913329805],
        [0.10268170574766, 0.0],
    ],
    [
        [-20.27940894394569, 0.0],
        [-2.69348683581097, -8.46037971396931],
        [-2.69348683581097, 8.46037971396931],
        [0.14327879765713, 0.0],
    ],
    [
        [-22.43788559040858, 0.0],
        [-3.21675402252485, -9.69377351531791],
        [-3.21675402252485, 9.69377351531791],
        [0.15790184030917, 0.0],
    ],
    [
        [-24.62459635017404, 0.0],
        [-3.72016840437287, -10.90681139476287],
        [-3.72016840437287, 10.90681139476287],
        [0.16105338653172, 0.0],
    ],
];

/// The weave and capsize speeds of the paper (m/s), where the weave pair and the capsize
/// eigenvalue cross the imaginary axis.
const WEAVE_SPEED: f64 = 4.29238253634111;
const CAPSIZE_SPEED: f64 = 6.02426201538837;

/// The linearisation at forward speed v (rear wheel rate v / rR).
fn at_speed(system: &Interpreted, v: f64) -> SteadyLinearization {
    let s = assemble_with(system, &[("thR", v / REAR_RADIUS)]);
    linearize_steady(system, 0.0, &s.q, &s.qd, &SteadyOptions::default()).expect("steady")
}

/// [re, im] sorted by real part, then imaginary part.
fn sorted(values: &[Complex<f64>]) -> Vec<[f64; 2]> {
    let mut v: Vec<[f64; 2]> = values.iter().map(|c| [c.re, c.im]).collect();
    v.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    v
}

#[test]
fn eigenvalues_match_table_2_to_1e_10() {
    let system = load("whipple_bicycle", &[]);
    let mut worst = 0.0_f64;
    for (v, table) in TABLE_2.iter().enumerate() {
        let lin = at_speed(&system, v as f64);
        // Six variables are structural: x, y, psi, thR, thF (cyclic) and der(thR) (the
        // forward speed is conserved to first order); lean and steer with their rates remain.
        let structural: Vec<&str> = lin
            .structural
            .iter()
            .map(|&k| lin.variables[k].as_str())
            .collect();
        assert_eq!(
            structural,
            ["x", "y", "psi", "thR", "thF", "der(thR)"],
            "v = {v}"
        );
        let ours = sorted(&lin.reduced);
        let mut want = table.to_vec();
        want.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
        assert_eq!(ours.len(), 4, "v = {v}: {ours:?}");
        for (o, w) in ours.iter().zip(&want) {
            let err = (o[0] - w[0]).abs().max((o[1] - w[1]).abs());
            worst = worst.max(err);
            // The table gives 14 decimals; 1e-10 leaves room for the round-off of a 10 x 10
            // eigenproblem and nothing for a modelling error.
            assert!(err < 1e-10, "v = {v}: {o:?} vs {w:?} (error {err:e})");
        }
    }
    println!("largest eigenvalue error over v = 0..10: {worst:e}");
}

/// The largest real part of the eigenvalues at speed v (the spectral abscissa).
fn abscissa(system: &Interpreted, v: f64) -> f64 {
    at_speed(system, v)
        .reduced
        .iter()
        .map(|c| c.re)
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The root of `f` in [a, b] by bisection (f(a) and f(b) of opposite signs), to 1e-12.
fn bisect(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let mut fa = f(a);
    assert!(fa * f(b) < 0.0, "no sign change on [{a}, {b}]");
    while b - a > 1e-12 {
        let m = 0.5 * (a + b);
        let fm = f(m);
        if fm * fa > 0.0 {
            (a, fa) = (m, fm);
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

#[test]
fn weave_and_capsize_speeds_to_1e_9() {
    let system = load("whipple_bicycle", &[]);
    // Unstable below the weave speed (the weave pair), stable up to the capsize speed, then
    // unstable again (the capsize eigenvalue): the spectral abscissa changes sign at each.
    let weave = bisect(|v| abscissa(&system, v), 4.0, 5.0);
    let capsize = bisect(|v| abscissa(&system, v), 5.5, 7.0);
    println!("weave {weave:.12} m/s, capsize {capsize:.12} m/s");
    assert!((weave - WEAVE_SPEED).abs() < 1e-9, "weave speed {weave}");
    assert!(
        (capsize - CAPSIZE_SPEED).abs() < 1e-9,
        "capsize speed {capsize}"
    );
}

#[test]
fn mobility_counts_positions_and_velocities_apart() {
    let system = load("whipple_bicycle", &[]);
    let s = assemble_with(&system, &[("thR", 5.0 / REAR_RADIUS)]);
    let mob = mechanism::mobility(&system, 0.0, &s.q).unwrap();
    // 9 coordinates, 2 contact heights, 4 sliding rows (the paper: a 7-dimensional
    // configuration space and 3 velocity degrees of freedom).
    assert_eq!((mob.n, mob.m, mob.rank), (9, 6, 6));
    assert_eq!(mob.position_degrees_of_freedom, 7);
    assert_eq!(mob.degrees_of_freedom, 3);
}
