use mechanism::prelude::*;

mechanism! {
    pub struct Slider;
    parameters { m = 1.0; }
    coordinates { x = 0.0; }
    independent { x = 0.0; der(x) = 1.0; }
    body block {
        position = [x, 0, 0];
    }
}

fn main() {}
