use mechanism::prelude::*;

mechanism!(file = "mechanisms/does_not_exist.mech");

fn main() {}
