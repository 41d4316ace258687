//! The bicycle through `mechanism!`: the emitted code runs the routines the interpreter
//! runs (the interpreter's are the emitted ones cut down to its roles; same bits), its velocity rows are labelled as such, and the cost
//! of deriving it and of one `evaluate_into` (printed; BENCHMARKS.md).

use std::hint::black_box;
use std::time::Instant;

use mechanism::nalgebra::SVector;
use mechanism::{
    Compiled, Evaluation, Interpreted, Kinematic, Mechanism, StaticEvaluation, System,
};

use crate::common::source;

mod emitted {
    mechanism::mechanism!(file = "mechanisms/whipple_bicycle.mech");
}
use emitted::WhippleBicycle;

/// A state away from every symmetry (q, q').
fn state() -> (SVector<f64, 9>, SVector<f64, 9>) {
    let q = SVector::<f64, 9>::from_fn(|i, _| 0.05 * (i as f64 + 1.0) - 0.2);
    let qd = SVector::<f64, 9>::from_fn(|i, _| 0.3 * (i as f64) - 1.1);
    (q, qd)
}

#[test]
fn emitted_bicycle_is_the_interpreted_one_bit_for_bit() {
    let interpreted = Interpreted::from_source(&source("whipple_bicycle")).unwrap();
    let mut model = mechanism_codegen::parse_model_str(&source("whipple_bicycle")).unwrap();
    let eqs = mechanism_codegen::derive(&mut model).unwrap();
    let tangent = mechanism_codegen::residual_tangent(&mut model, &eqs).unwrap();
    let routines = mechanism_codegen::compile(&mut model, &eqs, &tangent).unwrap();
    assert_eq!(WhippleBicycle::__ROUTINES, routines.fingerprint());
    let roles = mechanism_codegen::Role::interpreted(
        &model.drawing,
        mechanism_codegen::Tangents::WithConstraints,
    );
    assert_eq!(
        routines.restricted(&roles).fingerprint(),
        interpreted.routines_fingerprint()
    );
    assert_eq!(<WhippleBicycle as Mechanism<9, 6>>::VELOCITY_ROWS, 4);
    let compiled = Compiled::new(WhippleBicycle::default());
    assert_eq!(compiled.info().velocity_rows, 4);
    assert_eq!(
        compiled.info().constraint_label(5),
        "rolling(front_wheel, aF, rF) y"
    );
    let (q, qd) = state();
    let mut out = StaticEvaluation::zeros();
    WhippleBicycle::default().evaluate_into(0.0, &q, &qd, &mut out);
    let mut e = Evaluation::zeros(9, 6);
    interpreted.evaluate(0.0, q.as_slice(), qd.as_slice(), &mut e);
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(out.mass.as_slice()), bits(e.mass.as_slice()));
    assert_eq!(bits(out.phi_q.as_slice()), bits(e.phi_q.as_slice()));
    assert_eq!(bits(out.phi_t.as_slice()), bits(e.phi_t.as_slice()));
    assert_eq!(bits(out.gamma.as_slice()), bits(e.gamma.as_slice()));
    assert_eq!(bits(out.coriolis.as_slice()), bits(e.coriolis.as_slice()));
}

#[test]
fn cost_of_the_generated_bicycle() {
    let text = source("whipple_bicycle");
    let start = Instant::now();
    let mut model = mechanism_codegen::parse_model_str(&text).unwrap();
    let eqs = mechanism_codegen::derive(&mut model).unwrap();
    let tangent = mechanism_codegen::residual_tangent(&mut model, &eqs).unwrap();
    let routines = mechanism_codegen::compile(&mut model, &eqs, &tangent).unwrap();
    let derivation = start.elapsed().as_secs_f64();
    let m = WhippleBicycle::default();
    let (q, qd) = state();
    let mut out = StaticEvaluation::zeros();
    let calls = 20_000;
    let start = Instant::now();
    for _ in 0..calls {
        m.evaluate_into(0.0, black_box(&q), black_box(&qd), &mut out);
        black_box(&out);
    }
    let per_call = start.elapsed().as_secs_f64() / calls as f64;
    println!(
        "whipple_bicycle: derivation (parse, derive, tangents, compile) {derivation:.3} s, evaluation program {} operations, evaluate_into {:.2} us ({} profile)",
        routines
            .program(mechanism_codegen::Role::Evaluation)
            .unwrap()
            .op_counts()
            .total(),
        per_call * 1e6,
        if cfg!(debug_assertions) {
            "test"
        } else {
            "release"
        }
    );
    assert!(out.mass.iter().all(|v| v.is_finite()));
}
