//! An inline declaration: the struct, its defaults, the constants and every method.
use mechanism::prelude::*;

mechanism! {
    /// A point mass on a rod, in Cartesian coordinates.
    pub struct Pendulum;
    parameters { m = 2.0; l = 1.5; g = 9.81; }
    coordinates { x = 0.5; y = -1.4; }
    independent { x = 0.5; der(x) = 0.0; }
    kinetic = 1/2*m*(der(x)^2 + der(y)^2);
    potential = m*g*y;
    constraints { x^2 + y^2 - l^2; }
    forces { x: -0.1*der(x); }
}

fn main() {
    let mut p = Pendulum::default();
    assert_eq!(*p.parameters(), PendulumParameters { m: 2.0, l: 1.5, g: 9.81 });
    assert_eq!(p, Pendulum::from(PendulumParameters { m: 2.0, l: 1.5, g: 9.81 }));
    assert!(p.is_cached());
    // Through the fields: the cache is stale (the methods compute the values themselves)
    // until `refresh`, and the new value is what the methods use either way.
    p.l = 1.0;
    assert!(!p.is_cached());
    assert_eq!(p.l, 1.0);
    assert_eq!(p.constraints(0.0, &SVector::<f64, 2>::new(1.0, 0.0))[0], 0.0);
    p.refresh();
    assert!(p.is_cached());
    assert_eq!(p.constraints(0.0, &SVector::<f64, 2>::new(1.0, 0.0))[0], 0.0);
    p.l = 1.5;
    p.refresh();
    assert_eq!(format!("{p:?}"), "Pendulum { m: 2.0, l: 1.5, g: 9.81 }");
    assert_eq!(Pendulum::COORDINATES, ["x", "y"]);
    assert_eq!(<Pendulum as Mechanism<2, 1>>::PARAMETERS, &["m", "l", "g"]);
    assert_eq!((Pendulum::N, Pendulum::M), (2, 1));
    let q = SVector::<f64, 2>::new(0.3, -0.4);
    let qd = SVector::<f64, 2>::new(1.0, 2.0);
    // M = diag(m, m), g = [0, m g], Phi = x^2 + y^2 - l^2, Phi_q = [2x, 2y].
    assert_eq!(p.mass_matrix(&q), SMatrix::<f64, 2, 2>::new(2.0, 0.0, 0.0, 2.0));
    assert_eq!(p.gravity(&q), SVector::<f64, 2>::new(0.0, 2.0 * 9.81));
    assert!((p.constraints(0.0, &q)[0] - (0.25 - 2.25)).abs() < 1e-15);
    assert_eq!(p.constraint_jacobian(0.0, &q), SMatrix::<f64, 1, 2>::new(0.6, -0.8));
    // gamma = -2 (x'^2 + y'^2).
    assert!((p.constraint_gamma(0.0, &q, &qd)[0] + 10.0).abs() < 1e-14);
    assert_eq!(p.generalized_forces(0.0, &q, &qd), SVector::<f64, 2>::new(-0.1, 0.0));
    let e = p.evaluate(0.0, &q, &qd);
    assert_eq!(e.mass, p.mass_matrix(&q));
    assert!((e.kinetic - 5.0).abs() < 1e-14);
    assert!(Pendulum::equations().contains("Phi"));
}
