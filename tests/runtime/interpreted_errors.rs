//! The interpreter route refuses a malformed hand-built model with a typed error, not a panic.

use mechanism::Interpreted;
use mechanism_codegen::derive;
use mechanism_codegen::fixtures::closed_chain_model;

#[test]
fn a_coordinate_that_is_not_a_symbol_is_a_typed_error() {
    let mut model = closed_chain_model(4);
    let eqs = derive(&mut model).expect("the chain derives");
    // Corrupt the model after derivation: the coordinate entry points at the constant 0.
    model.coordinates[0].q = model.arena.int(0);
    let err = Interpreted::from_equations(model, eqs).expect_err("must be refused");
    let text = err.to_string();
    assert!(
        text.contains("coordinate `th1`") && text.contains("not a symbol"),
        "{text}"
    );
}
