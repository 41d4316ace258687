//! Declarations whose numbers or physics cannot be right: constants that overflow when
//! folded, a kinetic energy that is not a positive semi-definite quadratic form in the
//! rates, bodies without a mass or with an impossible inertia. Each is a typed error at the
//! offending expression, never a silently wrong model.

use mechanism_codegen::error::DeclarationError;
use mechanism_codegen::error::{BudgetError, DerivationError};
use mechanism_codegen::{Error, Model, derive, parse_model_str};

/// A pendulum in Cartesian coordinates with `kinetic`, `potential` and `params` replaced.
fn pendulum(params: &str, kinetic: &str, potential: &str) -> String {
    format!(
        "struct P;\n\
         parameters {{ {params} }}\n\
         coordinates {{ x = 0.6; y = -0.8; }}\n\
         independent {{ x = 0.6; der(x) = 0.0; }}\n\
         kinetic = {kinetic};\n\
         potential = {potential};\n\
         constraints {{ x^2 + y^2 - l^2; }}\n"
    )
}

const PARAMS: &str = "m = 1.0; l = 1.0; g = 9.81;";
const T: &str = "1/2*m*(der(x)^2 + der(y)^2)";
const PI: &str = "m*g*y";

/// The declaration's model, derived.
fn derived(text: &str) -> Result<Model, Error> {
    let mut model = parse_model_str(text)?;
    derive(&mut model)?;
    Ok(model)
}

/// The kind and the (line, column) of a declaration error.
fn declaration_error(text: &str) -> (DeclarationError, (usize, usize)) {
    match derived(text) {
        Err(Error::Declaration { kind, location }) => (*kind, (location.line, location.column)),
        other => panic!("expected a declaration error, got {other:?}"),
    }
}

#[test]
fn the_reference_pendulum_is_accepted() {
    derived(&pendulum(PARAMS, T, PI)).unwrap();
}

#[test]
fn a_folded_product_beyond_f64_is_an_error_at_its_expression() {
    let kinetic = "1/2*m*1e200*1e200*(der(x)^2 + der(y)^2)";
    let (kind, at) = declaration_error(&pendulum(PARAMS, kinetic, PI));
    match &kind {
        DeclarationError::ConstantOverflow {
            expression,
            operation,
        } => {
            assert_eq!(expression, kinetic);
            assert_eq!(operation, "5e199 * 1e200");
        }
        other => panic!("{other:?}"),
    }
    assert_eq!(at, (5, 11));
    assert!(
        kind.to_string().contains("beyond the largest f64"),
        "{kind}"
    );
}

#[test]
fn a_folded_sum_beyond_f64_is_an_error() {
    // Inside a larger expression: the innermost overflowing one is named.
    let potential = "m*g*y + (1.5e308 + 1.5e308)";
    let (kind, _) = declaration_error(&pendulum(PARAMS, T, potential));
    match &kind {
        DeclarationError::ConstantOverflow {
            expression,
            operation,
        } => {
            assert_eq!(expression, "1.5e308 + 1.5e308");
            assert_eq!(operation, "1.5e308 + 1.5e308");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_parameter_value_beyond_f64_is_an_error() {
    let (kind, at) = declaration_error(&pendulum("m = 1e300*1e300; l = 1.0; g = 9.81;", T, PI));
    assert!(
        matches!(kind, DeclarationError::ConstantOverflow { .. }),
        "{kind:?}"
    );
    assert_eq!(at.0, 2);
}

#[test]
fn large_but_finite_constants_are_kept_exactly() {
    // 1e154 squared is 1e308: finite, folded, and in the model as written.
    let potential = "1e154*1e154*y";
    let model = derived(&pendulum(PARAMS, T, potential)).unwrap();
    let text = mechanism_codegen::to_text(&model.arena, model.potential);
    assert!(text.contains("1e308"), "{text}");
}

#[test]
fn an_overflow_in_the_derivation_is_an_error_naming_the_mechanism() {
    // Pi = 1e308 y^2 is finite; its gradient 2e308 y is not.
    match derived(&pendulum(PARAMS, T, "1e308*y^2")) {
        Err(Error::Derivation(DerivationError::Overflow {
            mechanism,
            operation,
        })) => {
            assert_eq!(mechanism, "P");
            assert!(operation.contains("1e308"), "{operation}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_kinetic_energy_of_higher_degree_in_the_rates_is_an_error() {
    for kinetic in [
        "1/2*m*(der(x)^4 + der(y)^2)",
        "m*cos(der(x)) + 1/2*m*der(y)^2",
        "1/2*m*(der(x)^2 + der(y)^2)*(1 + der(y))",
    ] {
        let (kind, at) = declaration_error(&pendulum(PARAMS, kinetic, PI));
        assert!(
            matches!(kind, DeclarationError::KineticNotQuadratic { .. }),
            "{kinetic}: {kind:?}"
        );
        assert_eq!(at.0, 5, "{kinetic}");
    }
    let (kind, _) = declaration_error(&pendulum(PARAMS, "1/2*m*(der(x)^4 + der(y)^2)", PI));
    assert_eq!(
        kind,
        DeclarationError::KineticNotQuadratic {
            row: "x".into(),
            column: "x".into(),
            rate: "x".into(),
        }
    );
}

#[test]
fn a_kinetic_energy_that_can_be_negative_is_an_error_naming_the_coordinate() {
    let (kind, at) = declaration_error(&pendulum(PARAMS, "-3*der(x)^2 + 1/2*m*der(y)^2", PI));
    assert_eq!(
        kind,
        DeclarationError::KineticNotPositive {
            coordinate: "x".into(),
            pivot: -6.0,
            diagonal: -6.0,
        }
    );
    assert_eq!(at.0, 5);
    // A negative mass parameter, at its declared value.
    let (kind, _) = declaration_error(&pendulum("m = -1.0; l = 1.0; g = 9.81;", T, PI));
    assert!(
        matches!(kind, DeclarationError::KineticNotPositive { .. }),
        "{kind:?}"
    );
    // Positive diagonal, but indefinite: 1/2 (x'^2 + y'^2) + 2 x' y' has M = [1 2; 2 1].
    let (kind, _) = declaration_error(&pendulum(
        PARAMS,
        "1/2*(der(x)^2 + der(y)^2) + 2*der(x)*der(y)",
        PI,
    ));
    match kind {
        DeclarationError::KineticNotPositive { pivot, .. } => assert_eq!(pivot, -3.0),
        other => panic!("{other:?}"),
    }
}

#[test]
fn semi_definite_and_non_homogeneous_kinetic_energies_are_accepted() {
    // y without mass (M singular, as the seed's): semi-definite is enough.
    derived(&pendulum(PARAMS, "1/2*m*der(x)^2", PI)).unwrap();
    // Terms linear in the rates and free of them (a moving frame): T = T2 + T1 + T0.
    derived(&pendulum(
        PARAMS,
        "1/2*m*(der(x)^2 + der(y)^2) + m*der(x)*sin(t) + 1/2*m*x^2",
        PI,
    ))
    .unwrap();
}

#[test]
fn a_rate_of_a_coordinate_the_section_does_not_free_is_an_error() {
    let text = pendulum(PARAMS, T, PI).replace(
        "independent { x = 0.6; der(x) = 0.0; }",
        "independent { x = 0.6; der(y) = 1.0; }",
    );
    let (kind, at) = declaration_error(&text);
    assert_eq!(
        kind,
        DeclarationError::RateOfDependent {
            name: "y".into(),
            independent: vec!["x".into()],
        }
    );
    assert_eq!(at, (4, 28), "at the coordinate inside der(..)");
    assert!(kind.to_string().contains("give `y = value;` too"), "{kind}");
    // The rate before the position of the same coordinate is fine.
    let text = pendulum(PARAMS, T, PI).replace(
        "independent { x = 0.6; der(x) = 0.0; }",
        "independent { der(x) = 0.5; x = 0.6; }",
    );
    derived(&text).unwrap();
}

/// n coordinates q_i, all independent, with T = 1/2 sum `term(i)` q_i'^2.
fn many_coordinates(n: usize, term: impl Fn(usize) -> String) -> String {
    let coordinates: String = (0..n).map(|i| format!("q{i} = 0.1; ")).collect();
    let independent: String = (0..n)
        .map(|i| format!("q{i} = 0.1; der(q{i}) = 0.0; "))
        .collect();
    let kinetic: Vec<String> = (0..n).map(|i| format!("{}*der(q{i})^2", term(i))).collect();
    format!(
        "struct Big;\ncoordinates {{ {coordinates}}}\nindependent {{ {independent}}}\nkinetic = 1/2*({});\n",
        kinetic.join(" + ")
    )
}

/// dM/dq is counted by its nonzeros (M_ij depending on q_k) before any is formed: 520
/// coordinates each in its own diagonal entry make 520 of the dense 520^3 = 140.6 million,
/// so they derive within the default budget, and a budget of 519 refuses them.
#[test]
fn a_derivation_beyond_its_matrix_budget_fails_before_allocating() {
    let text = many_coordinates(520, |i| format!("(1 + q{i}^2)"));
    derived(&text).unwrap();
    let budget = mechanism_codegen::Budget {
        entries: 519,
        ..Default::default()
    };
    let mut model = mechanism_codegen::parse_model_str_with(&text, budget).unwrap();
    match derive(&mut model) {
        Err(Error::Budget(BudgetError::Entries {
            coordinates,
            entries,
            limit,
            links: None,
        })) => assert_eq!((coordinates, entries, limit), (520, 520, 519)),
        other => panic!("{:?}", other.map(|e| e.n)),
    }
}

/// A derivation past its work budget stops with the figure, the budget and the variable
/// that raises it, instead of running on.
#[test]
fn a_derivation_beyond_its_work_budget_stops() {
    let text = many_coordinates(40, |i| format!("(1 + q{i}^2)"));
    // The work of the whole derivation, then half of it as the budget.
    let whole = derived(&text).unwrap().arena.effort().work;
    let budget = mechanism_codegen::Budget {
        work: whole / 2,
        ..Default::default()
    };
    let mut model = mechanism_codegen::parse_model_str_with(&text, budget).unwrap();
    let e = match derive(&mut model) {
        Err(e) => e,
        Ok(eqs) => panic!("derived {} coordinates within half its work", eqs.n),
    };
    let Error::Budget(BudgetError::Work {
        work,
        budget,
        links: None,
    }) = e
    else {
        panic!("{e:?}");
    };
    assert!(work > budget && budget == whole / 2, "{work} of {budget}");
    assert!(work < whole, "it stopped early: {work} of {whole}");
    assert!(e.to_string().contains("MECHANISM_MAX_WORK="), "{e}");
}

#[test]
fn a_mass_matrix_free_of_the_coordinates_needs_no_kronecker_matrices() {
    // The same size with a constant M derives (C = 0 without dM/dq).
    derived(&many_coordinates(520, |_| "1".to_string())).unwrap();
}

/// Printed as a tree, a DAG of n levels that each use the level below twice has 2^n
/// copies of the bottom: 60 levels would be exabytes of text. The printer stops at its
/// budget and elides the rest.
#[test]
fn printing_shared_subexpressions_stays_within_the_text_budget() {
    let mut a = mechanism_codegen::Arena::new();
    let [x, ..] = a.coordinate("x");
    let [y, ..] = a.coordinate("y");
    let mut e = x;
    for _ in 0..60 {
        let p = a.mul2(e, y);
        e = a.add(&[e, p]);
    }
    assert!(a.len() < 200, "{} nodes", a.len());
    let text = mechanism_codegen::to_text(&a, e);
    assert!(text.contains("<...>"), "elided");
    assert!(text.len() <= 2 * (64 << 20) + 64, "{} bytes", text.len());
}

#[test]
fn the_size_of_the_expressions_is_counted_and_checked() {
    let mut a = mechanism_codegen::Arena::new();
    let [x, ..] = a.coordinate("x");
    let [y, ..] = a.coordinate("y");
    let before = a.size();
    let s = a.add(&[x, y]);
    // One new node with two child references.
    assert_eq!(a.size(), before + 3);
    a.add(&[x, y]);
    assert_eq!(a.size(), before + 3, "an existing node costs nothing");
    let _ = s;
    let budget = |size: usize, work: u64| mechanism_codegen::Budget {
        size,
        work,
        ..Default::default()
    };
    let effort = a.effort();
    a.set_budget(budget(a.size(), effort.work));
    assert!(a.check_budget().is_ok());
    a.set_budget(budget(a.size() - 1, effort.work));
    match a.check_budget() {
        Err(Error::Budget(BudgetError::Size {
            size,
            budget,
            links: None,
        })) => {
            assert_eq!((size, budget), (a.size(), a.size() - 1));
        }
        other => panic!("{other:?}"),
    }
    // Work counts every constructor call, found or new: the second sum above cost work
    // but no size.
    a.set_budget(budget(a.size(), effort.work - 1));
    match a.check_budget() {
        Err(Error::Budget(BudgetError::Work {
            work,
            budget,
            links: None,
        })) => {
            assert_eq!((work, budget), (effort.work, effort.work - 1));
        }
        other => panic!("{other:?}"),
    }
    let before = a.effort().work;
    a.add(&[x, y]);
    assert_eq!(
        a.effort().work,
        before + 1,
        "a found node costs one unit of work"
    );
}

/// The progress hook hears the work at every PROGRESS_EVERY units, in order.
#[test]
fn a_long_derivation_reports_its_progress() {
    use std::sync::atomic::{AtomicU64, Ordering};
    static LAST: AtomicU64 = AtomicU64::new(0);
    static CALLS: AtomicU64 = AtomicU64::new(0);
    fn hear(e: mechanism_codegen::Effort) {
        assert!(e.work > LAST.swap(e.work, Ordering::SeqCst), "work grows");
        CALLS.fetch_add(1, Ordering::SeqCst);
    }
    let mut a = mechanism_codegen::Arena::new();
    a.set_budget(mechanism_codegen::Budget {
        progress: Some(hear),
        ..Default::default()
    });
    let [x, ..] = a.coordinate("x");
    for k in 0..(3u64 << 20) {
        a.int(k as i64 % 7);
    }
    let _ = x;
    let calls = CALLS.load(Ordering::SeqCst);
    assert_eq!(calls, a.effort().work / mechanism_codegen::PROGRESS_EVERY);
    assert!(calls >= 3, "{calls} reports");
}
