//! A private struct, no constraints, no forces, no independent block: an angle pendulum.
use mechanism::prelude::*;

mechanism! {
    struct AnglePendulum;
    parameters { m = 1.0; l = 2.0; g = 9.81; }
    coordinates { th = 0.1; }
    independent { th = 0.1; der(th) = 0.0; }
    kinetic = 1/2*m*l^2*der(th)^2;
    potential = -m*g*l*cos(th);
}

fn main() {
    let p = AnglePendulum::default();
    let q = SVector::<f64, 1>::new(0.3);
    let qd = SVector::<f64, 1>::new(0.0);
    assert_eq!(p.mass_matrix(&q)[(0, 0)], 4.0);
    assert!((p.gravity(&q)[0] - 9.81 * 2.0 * 0.3f64.sin()).abs() < 1e-14);
    let e = p.evaluate(0.0, &q, &qd);
    assert_eq!(e.phi.len(), 0);
}
