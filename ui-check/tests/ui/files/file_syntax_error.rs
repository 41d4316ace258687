use mechanism::prelude::*;

mechanism!(file = "broken.mech");

fn main() {}
