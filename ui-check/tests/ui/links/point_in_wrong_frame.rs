use mechanism::prelude::*;

mechanism! {
    pub struct Arm;
    parameters { g = 9.81; }
    gravity = [0, 0, -g];
    link upper { joint = revolute(q1, [0, 0, 1]); mass = 1.0; point elbow = [0.3, 0, 0]; }
    link lower { parent = upper; joint = revolute(q2, [0, 1, 0]); xyz = elbow; mass = 1.0; }
}

fn main() {}
