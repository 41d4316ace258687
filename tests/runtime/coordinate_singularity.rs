//! An undetermined motion that the coordinates cause is named for it (issue 53, item 11),
//! one that a missing inertia causes is not: a point mass in polar coordinates at r = 0,
//! where M = diag(m, m r^2) has no inertia for th but a step of r gives it back, against a
//! coordinate that carries no mass anywhere.

use mechanism::{Error, InitialState, Interpreted, SimulationOptions, simulate};

/// A run of `source` from the consistent state (q, q').
fn run(source: &str, q: [f64; 2], qd: [f64; 2]) -> Error {
    let system = Interpreted::from_source(source).expect("declaration");
    let options = SimulationOptions {
        t_end: 0.1,
        initial: InitialState::Consistent {
            q: q.to_vec(),
            qd: qd.to_vec(),
        },
        ..Default::default()
    };
    simulate(&system, &options).expect_err("the motion is undetermined at the start")
}

#[test]
fn polar_coordinates_at_the_origin_are_a_coordinate_singularity() {
    let polar = "pub struct Polar;
        parameters { m = 1.0 positive; }
        coordinates { r = 1.0; th = 0.0; }
        kinetic = m/2*(der(r)^2 + r^2*der(th)^2);";
    match run(polar, [0.0, 0.3], [1.0, 0.0]) {
        Error::CoordinateSingularity {
            coordinate,
            value,
            moving,
            orientation,
            ..
        } => {
            // r is the coordinate at its singular value, th the one it leaves free; no body
            // declares these as orientation angles.
            assert_eq!((coordinate.as_str(), value), ("r", 0.0));
            assert_eq!(moving, ["th"]);
            assert!(orientation.is_none());
        }
        other => panic!("expected a coordinate singularity, got {other}"),
    }
}

#[test]
fn a_coordinate_without_mass_stays_an_undetermined_motion() {
    // y carries no inertia anywhere: no step of a coordinate gives it any.
    let massless = "pub struct Massless;
        parameters { m = 1.0 positive; }
        coordinates { x = 0.0; y = 0.0; }
        kinetic = m/2*der(x)^2;";
    match run(massless, [0.0, 0.0], [1.0, 0.0]) {
        Error::UndeterminedMotion { coordinates, .. } => assert_eq!(coordinates, ["y"]),
        other => panic!("expected an undetermined motion, got {other}"),
    }
}
