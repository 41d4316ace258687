use mechanism::prelude::*;

mechanism!(urdf = "bad.urdf", damping = 1);

fn main() {}
