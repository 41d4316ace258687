use mechanism::prelude::*;

mechanism! {
    pub struct Pendulum;
    parameters { m = 1.0 nonnegative; l = -1.0 positive; g = 9.81; }
    coordinates { x = 0.5; y = -0.8; }
    independent { x = 0.5; der(x) = 0.0; }
    kinetic = 1/2*m*(der(x)^2 + der(y)^2);
    potential = m*g*y;
    constraints { x^2 + y^2 - l^2; }
}

fn main() {}
