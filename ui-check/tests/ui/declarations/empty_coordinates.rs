use mechanism::prelude::*;

mechanism! {
    pub struct Nothing;
    parameters { m = 1.0; }
    coordinates { }
    kinetic = 0;
    potential = 0;
}

fn main() {}
