use mechanism::prelude::*;

mechanism!(file = "unknown_symbol.mech");

fn main() {}
