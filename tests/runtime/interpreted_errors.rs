//! The interpreter route refuses a malformed hand-built model with a typed error when it is
//! built, not a panic or a NaN at an evaluation.

use mechanism::Interpreted;
use mechanism_codegen::error::EvalError;
use mechanism_codegen::fixtures::closed_chain_model;
use mechanism_codegen::{Error, Matrix, SymbolKind, derive};

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

#[test]
fn equations_that_read_an_undeclared_symbol_are_a_typed_error() {
    let mut model = closed_chain_model(4);
    let mut eqs = derive(&mut model).expect("the chain derives");
    // Corrupt the equations: Phi reads a symbol that is neither a parameter, a coordinate
    // nor time, which no evaluation could give a value.
    let stray = model.arena.symbol("stray", SymbolKind::Free);
    eqs.phi = Matrix::column(vec![stray; eqs.m]);
    let err = Interpreted::from_equations(model, eqs).expect_err("must be refused");
    assert_eq!(
        err,
        Error::Eval(EvalError::MissingValue {
            name: "stray".into()
        })
    );
}
