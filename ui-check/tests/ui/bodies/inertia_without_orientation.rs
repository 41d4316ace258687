use mechanism::prelude::*;

mechanism! {
    pub struct Pendulum;
    parameters { m = 1.0; l = 1.0; g = 9.81; }
    coordinates { th = 0.3; }
    independent { th = 0.3; }
    gravity = [0, -g, 0];
    body bob { mass = m; position = [l*sin(th), -l*cos(th), 0]; inertia = diag(1, 1, 1); }
}

fn main() {}
