use mechanism::prelude::*;

mechanism! {
    pub struct Rover;
    parameters { g = 9.81; }
    gravity = [0, 0, -g];
    link base { joint = revolute(q1, [0, 0, 1]); mass = 1.0; }
    link body { parent = base; joint = floating(free); mass = 1.0; }
}

fn main() {}
