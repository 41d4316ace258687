use mechanism::prelude::*;

mechanism! {
    pub struct Pendulum;
    parameters { m = 1.0; l = 1.0; g = 9.81; }
    coordinates { x = 0.3; y = -0.9; }
    independent { x = 0.3; }
    gravity = [0, -g, 0];
    point O = [0, 0, 0];
    body bob { mass = m; position = [x, y, 0] }
    joints { distance(bob, O, l); }
}

fn main() {}
