use mechanism::prelude::*;

mechanism!(urdf = "world_fixed.urdf", floating = true);

fn main() {}
