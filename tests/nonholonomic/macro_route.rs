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
    let tangent = mechanism_codegen::full_tangent(&mut model, &eqs).unwrap();
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

/// The forward speed follows `v` and `rR` (issue 53, item 1): the declared
/// `der(thR) = v/rR` is evaluated at the parameters of the run, on both routes and through a
/// field of the emitted struct. Truth: upright and straight ahead, the rear wheel rolls
/// without slipping, so its centre moves forward at x' = rR thR' (the sliding rows give it,
/// independently of the declared rate), and that must be v. Before, `v = 3` ran at 5 m/s
/// and `rR = 0.5` at 8.33 m/s.
#[test]
fn the_bicycle_moves_at_the_speed_its_parameters_give() {
    let (ix, ith) = (0, 7); // x and thR in q
    let options = mechanism::SimulationOptions {
        t_end: 0.05,
        ..Default::default()
    };
    for (name, value, speed, rate) in [("v", 3.0, 3.0, 10.0), ("rR", 0.5, 5.0, 10.0)] {
        let mut field = WhippleBicycle::default();
        match name {
            "v" => field.v = value,
            _ => field.rR = value,
        }
        let mut interpreted = Interpreted::from_source(&source("whipple_bicycle")).unwrap();
        let mut compiled = Compiled::new(WhippleBicycle::default());
        let k = compiled.info().parameter_index(name).unwrap();
        assert!(interpreted.set_parameter(k, value).is_ok());
        assert!(compiled.set_parameter(k, value).is_ok());
        let through_field = Compiled::new(field);
        let systems: [&dyn System; 3] = [&compiled, &through_field, &interpreted];
        for system in systems {
            let tr = mechanism::simulate(system, &options).expect("runs");
            let s = tr.sample(0);
            let r_rear = if name == "rR" { value } else { 0.3 };
            // Rate and speed from one solve of the rolling rows: a few ulp.
            assert!(
                (s.qd[ith] - rate).abs() < 1e-12,
                "{name}: thR' = {}",
                s.qd[ith]
            );
            assert!((s.qd[ix] - s.qd[ith] * r_rear).abs() < 1e-12, "{name}");
            assert!(
                (s.qd[ix] - speed).abs() < 1e-12,
                "{name}: x' = {}",
                s.qd[ix]
            );
        }
    }
}
