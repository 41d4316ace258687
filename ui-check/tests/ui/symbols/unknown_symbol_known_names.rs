use mechanism::prelude::*;

mechanism! {
    pub struct Pendulum;
    parameters { m = 1.0; l = 1.0; g = 9.81; }
    coordinates { phi = 0.5; }
    independent { phi = 0.5; der(phi) = 0.0; }
    kinetic = 1/2*m*l^2*der(phi)^2;
    potential = -m*g*l*cos(w);
}

fn main() {}
