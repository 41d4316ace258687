use mechanism::prelude::*;

mechanism! {
    pub struct Sleigh;
    parameters { m = 1.0; a = 0.2; }
    coordinates { x = 0.0; y = 0.0; theta = 0.0; }
    independent { x = 0.0; theta = 0.0; der(x) = 0.1; der(theta) = 1.0; }
    kinetic = m/2*(der(x)^2 + der(y)^2 + der(theta)^2);
    // A product of two rates: not of the form A(q, t) q' + a(q, t).
    velocity_constraints { der(x)*der(theta) + der(y); }
}

fn main() {}
