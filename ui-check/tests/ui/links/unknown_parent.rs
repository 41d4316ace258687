use mechanism::prelude::*;

mechanism! {
    pub struct Arm;
    parameters { g = 9.81; }
    gravity = [0, 0, -g];
    link upper { joint = revolute(q1, [0, 0, 1]); mass = 1.0; }
    link lower { parent = uper; joint = revolute(q2, [0, 1, 0]); mass = 1.0; }
}

fn main() {}
