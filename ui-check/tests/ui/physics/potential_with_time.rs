use mechanism::prelude::*;

mechanism! {
    pub struct RisingFloor;
    parameters { m = 2.0; g = 9.81; v = 0.1; }
    coordinates { y = 1.0; }
    independent { y = 1.0; }
    kinetic = 1/2*m*der(y)^2;
    potential = m*g*(y - v*t);
}

fn main() {}
