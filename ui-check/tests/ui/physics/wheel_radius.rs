use mechanism::prelude::*;

mechanism! {
    pub struct Disc;
    parameters { m = 1.0; g = 9.81; }
    coordinates { x = 0.0; y = 0.0; z = 0.1; psi = 0.0; phi = 0.0; th = 0.0; }
    independent { psi = 0.0; phi = 0.0; th = 0.0; der(th) = 10.0; }
    gravity = [0, 0, -g];
    body disc {
        mass = m;
        orientation = rot_z(psi) * rot_x(phi) * rot_y(th);
        position = [x, y, z];
        inertia = diag(m/400, m/200, m/400);
        axis a = [0, 1, 0];
    }
    joints {
        rolling(disc, a, -0.1);
    }
}

fn main() {}
