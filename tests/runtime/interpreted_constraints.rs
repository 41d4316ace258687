//! The constraint rows compiled alone (`InterpretedConstraints`, what `mechanism equations`
//! assembles a file with) against the whole interpreted system: the same Phi, Phi_q and
//! Phi_t bit for bit, the same assembly and the same mobility, and Phi_q's pattern read off
//! the Jacobian's own program equal to the evaluation's.

use mechanism::builtin::builtin_source;
use mechanism::nalgebra::DMatrix;
use mechanism::{
    AssemblyOptions, Interpreted, InterpretedConstraints, Kinematic, assemble, mobility,
};
use mechanism_codegen::{
    EvaluationOutput, Tangents, compile_constraints, compile_interpreted, derive,
};

use crate::sparsity::Lcg;

/// Redundant rows (bricard, the planar four-bar of spatial bodies), velocity rows
/// (chaplygin_sleigh), parameters in the rows (the seed), a sparse Phi_q (A02 with N = 40).
const MECHANISMS: [&str; 5] = [
    "bricard",
    "planar_four_bar_bodies",
    "chaplygin_sleigh",
    "spatial_crank_slider",
    "n_four_bar",
];

/// Both systems of the built-in `name`, from one derivation.
fn both(name: &str) -> (Interpreted, InterpretedConstraints) {
    let mut model = mechanism_codegen::parse_model_str(builtin_source(name).unwrap()).unwrap();
    let eqs = derive(&mut model).unwrap();
    let rows = InterpretedConstraints::from_equations(model.clone(), &eqs).unwrap();
    let full = Interpreted::from_equations_with(model, eqs, Tangents::None).unwrap();
    (full, rows)
}

/// Phi, then Phi_q and Phi_t, of `system` at (t, q), each into fresh buffers.
fn rows_at(system: &dyn Kinematic, t: f64, q: &[f64]) -> (Vec<f64>, DMatrix<f64>, Vec<f64>) {
    let (n, m) = (system.info().n(), system.info().m());
    let mut phi = vec![f64::NAN; m];
    system.constraints(t, q, &mut phi);
    let (mut phi_q, mut phi_t) = (DMatrix::zeros(m, n), vec![f64::NAN; m]);
    system.constraint_jacobian(t, q, &mut phi_q, &mut phi_t);
    (phi, phi_q, phi_t)
}

#[test]
fn constraint_rows_alone_compute_what_the_whole_system_computes() {
    let mut rng = Lcg(0x5eed);
    for name in MECHANISMS {
        let (full, rows) = both(name);
        assert_eq!(rows.info(), full.info(), "{name}");
        let options = AssemblyOptions::default();
        let assembled = assemble(&full, 0.0, &options).unwrap();
        // The same programs up to cache-slot numbers: the same operations in the same order.
        assert_eq!(assemble(&rows, 0.0, &options).unwrap(), assembled, "{name}");
        assert_eq!(
            mobility(&rows, 0.0, &assembled.q).unwrap(),
            mobility(&full, 0.0, &assembled.q).unwrap(),
            "{name}"
        );
        for _ in 0..3 {
            let t = rng.next();
            let q: Vec<f64> = assembled.q.iter().map(|x| x + 0.3 * rng.next()).collect();
            let (phi, phi_q, phi_t) = rows_at(&full, t, &q);
            assert!(
                phi.iter()
                    .chain(phi_q.iter())
                    .chain(&phi_t)
                    .all(|x| x.is_finite())
            );
            assert_eq!(rows_at(&rows, t, &q), (phi, phi_q, phi_t), "{name}");
        }
    }
}

#[test]
fn jacobian_pattern_of_the_rows_alone_is_the_evaluations() {
    for name in MECHANISMS {
        let mut model = mechanism_codegen::parse_model_str(builtin_source(name).unwrap()).unwrap();
        let eqs = derive(&mut model).unwrap();
        let alone = compile_constraints(&mut model.clone(), &eqs).unwrap();
        let all = compile_interpreted(&mut model, &eqs, None).unwrap();
        let pattern = alone.sparsity(EvaluationOutput::PhiQ).unwrap();
        assert_eq!(
            pattern,
            all.sparsity(EvaluationOutput::PhiQ).unwrap(),
            "{name}"
        );
        assert_eq!(
            (pattern.rows, pattern.cols),
            (eqs.m, model.coordinates.len())
        );
        // The rows alone have no evaluation to read M's pattern from.
        assert!(alone.sparsity(EvaluationOutput::Mass).is_err(), "{name}");
    }
}

/// Parameters set on the rows alone act as on the whole system: after each parameter of
/// the seed (its lengths enter the rows) is changed in both, Phi, Phi_q and Phi_t agree bit
/// for bit again, and they differ from the rows before the change for some parameter (so
/// the setting reached the rows). An index past the parameters is refused by both.
#[test]
fn parameters_set_on_the_rows_alone_act_as_on_the_whole_system() {
    use mechanism::System;
    let (mut full, mut rows) = both("spatial_crank_slider");
    let count = rows.info().parameters.len();
    let mut declared = vec![f64::NAN; count];
    full.parameter_values(&mut declared);
    assert_eq!(rows.parameter_values(), &declared[..]);
    let q = rows.info().initial_guess.clone();
    let mut reached = false;
    for (k, &old) in declared.iter().enumerate() {
        let before = rows_at(&rows, 0.3, &q);
        let value = 1.25 * old + 0.01;
        assert!(rows.set_parameter(k, value).is_ok() && full.set_parameter(k, value).is_ok());
        assert_eq!(rows.parameter_values()[k], value);
        let after = rows_at(&rows, 0.3, &q);
        assert_eq!(after, rows_at(&full, 0.3, &q), "parameter {k}");
        reached |= after != before;
    }
    assert!(reached, "no parameter changed the rows");
    assert!(rows.set_parameter(count, 1.0).is_err());
    assert!(full.set_parameter(count, 1.0).is_err());
}
