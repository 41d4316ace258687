//! The file form, and a parameter changed at run time without rebuilding.
use mechanism::prelude::*;

mechanism!(file = "../../../../mechanisms/cartesian_pendulum.mech");

fn main() {
    let mut p = CartesianPendulum::default();
    assert!(p.set_parameter(0, 3.0));
    assert_eq!(p.m, 3.0);
    assert!(!p.set_parameter(99, 1.0));
    let q = SVector::<f64, 2>::new(0.6, -0.8);
    assert_eq!(p.mass_matrix(&q)[(1, 1)], 3.0);
    assert_eq!(CartesianPendulum::INDEPENDENT[0].coordinate, 0);
}
