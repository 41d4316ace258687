//! More constraint rows than coordinates compiles (redundant rows: an overconstrained
//! mechanism; the runtime reports the rank of Phi_q). A point mass on a circle in the plane
//! z = 0, with both the plane and the circle written twice: n = 3, m = 4, rank 2, one degree
//! of freedom. The rows are labelled by statement and component.
use mechanism::prelude::*;

mechanism! {
    pub struct RedundantCircle;
    parameters { m = 1.0; l = 1.0; g = 9.81; }
    coordinates { x = 0.6; y = -0.8; z = 0.0; }
    independent { x = 0.6; der(x) = 0.0; }
    kinetic = 1/2*m*(der(x)^2 + der(y)^2 + der(z)^2);
    potential = m*g*y;
    constraints {
        x^2 + y^2 - l^2;
        [z, 2*(x^2 + y^2 - l^2)] = [0, 0];
        3*z;
    }
}

fn main() {
    assert_eq!((RedundantCircle::N, RedundantCircle::M), (3, 4));
    assert_eq!(
        <RedundantCircle as Mechanism<3, 4>>::CONSTRAINT_ROWS,
        &[
            ("constraint 1", ""),
            ("constraint 2", "x"),
            ("constraint 2", "y"),
            ("constraint 3", ""),
        ]
    );
    let p = RedundantCircle::default();
    let q = SVector::<f64, 3>::new(0.6, -0.8, 0.0);
    let jac = p.constraint_jacobian(0.0, &q);
    assert_eq!(jac.rank(1e-12), 2);
    let info = Compiled::new(p).info().clone();
    assert_eq!(info.constraint_label(2), "constraint 2 y");
}
