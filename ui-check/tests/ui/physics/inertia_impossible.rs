use mechanism::prelude::*;

mechanism! {
    pub struct Spinner;
    parameters { m = 1.0; }
    coordinates { th = 0.0; }
    independent { th = 0.0; der(th) = 1.0; }
    body disc {
        mass = m;
        position = [0, 0, 0];
        orientation = rot_z(th);
        inertia = diag(0.1, 0.1, 0.5);
    }
}

fn main() {}
