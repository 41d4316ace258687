use mechanism::prelude::*;

mechanism! {
    pub struct ShakenPendulum;
    parameters { m = 2.0; l = 1.0; g = 9.81; A = 0.1; w = 7.0; }
    coordinates { th = 0.3; }
    independent { th = 0.3; }
    kinetic = 1/2*m*((A*w*cos(w*t) + l/2*sin(th)*der(th))^2 + (l/2*cos(th)*der(th))^2);
    potential = -m*g*l/2*sin(th);
}

fn main() {}
