use mechanism::prelude::*;

mechanism!(urdf = "bad.urdf", snap_angles = 0.25);

fn main() {}
