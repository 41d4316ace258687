use mechanism::prelude::*;

mechanism!(urdf = "bad.urdf");

fn main() {}
