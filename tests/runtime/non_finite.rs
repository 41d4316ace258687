//! A NaN or an infinity produced by one expression of a declaration is reported as that
//! entry (`Phi row 2 (constraint 2)`, `tau of x`, `M[x, x]`, `Phi_t row 1 (constraint 1)`)
//! at the time and configuration where it appeared, by the assembly and by the dynamics,
//! never hidden by a norm that skips NaN.

use mechanism::{AssemblyOptions, Dynamics, Error, Interpreted, Kinematic, assemble};

fn interpreted(source: &str) -> Interpreted {
    Interpreted::from_source(source).expect("the declaration derives")
}

/// The term named by a [`Error::NonFiniteTerm`], or a panic naming what came instead.
fn term(err: Error) -> String {
    match err {
        Error::NonFiniteTerm { term, value, .. } => {
            assert!(!value.is_finite(), "{term} = {value}");
            term
        }
        other => panic!("expected NonFiniteTerm, got {other}"),
    }
}

/// The planar four-bar of `mechanisms/` with ln(th1 - 5), NaN for every reachable th1, added
/// to its second constraint row.
fn four_bar_with_nan_in_row_2() -> Interpreted {
    let source = include_str!("../../mechanisms/planar_four_bar.mech").replace(
        "l1*sin(th1) + l2*sin(th2) - l3*sin(th3);",
        "l1*sin(th1) + l2*sin(th2) - l3*sin(th3) + ln(th1 - 5);",
    );
    assert!(
        source.contains("ln(th1 - 5)"),
        "the row to corrupt is there"
    );
    interpreted(&source)
}

#[test]
fn a_nan_constraint_row_is_named_by_the_assembly() {
    let system = four_bar_with_nan_in_row_2();
    let err = assemble(&system, 0.0, &AssemblyOptions::default()).expect_err("NaN row");
    let text = err.to_string();
    assert_eq!(term(err), "Phi row 2 (constraint 2)");
    assert!(text.contains("is NaN at t = 0 s, q = ["), "{text}");
}

#[test]
fn a_nan_force_is_named_by_the_dynamics() {
    // tau = sqrt(0.5 - t) on x: finite up to t = 0.5 s, NaN after.
    let system = interpreted(
        "struct Failing;\ncoordinates { x = 0.0; }\nindependent { x = 0.0; }\n\
         kinetic = 1/2*der(x)^2;\nforces { x: sqrt(0.5 - t); }\n",
    );
    let mut dynamics = Dynamics::new(system.info());
    dynamics
        .solve(&system, 0.25, &[0.0], &[0.0])
        .expect("finite");
    let err = dynamics
        .solve(&system, 0.75, &[0.1], &[0.0])
        .expect_err("NaN force");
    let text = err.to_string();
    assert_eq!(term(err), "tau of x");
    assert!(text.contains("at t = 0.75 s, q = [0.1]"), "{text}");
}

#[test]
fn a_nan_mass_entry_is_named_by_the_dynamics() {
    // The inertia sqrt(x - 1) is NaN for x < 1.
    let system = interpreted(
        "struct Soft;\ncoordinates { x = 2.0; }\nindependent { x = 2.0; }\n\
         kinetic = 1/2*sqrt(x - 1)*der(x)^2;\n",
    );
    let mut dynamics = Dynamics::new(system.info());
    dynamics
        .solve(&system, 0.0, &[2.0], &[0.0])
        .expect("finite");
    let err = dynamics
        .solve(&system, 0.0, &[0.5], &[1.0])
        .expect_err("NaN mass");
    assert_eq!(term(err), "M[x, x]");
}

#[test]
fn an_infinite_constraint_rate_is_named_by_the_assembly() {
    // Phi = x - sqrt(t): Phi_t = -1/(2 sqrt(t)) is -inf at t = 0 (the interpreter route
    // reports a failed entry as NaN).
    let system = interpreted(
        "struct Rooted;\ncoordinates { x = 0.0; y = 0.0; }\nindependent { y = 0.0; }\n\
         kinetic = 1/2*der(x)^2 + 1/2*der(y)^2;\nconstraints { x - sqrt(t); }\n",
    );
    let err = assemble(&system, 0.0, &AssemblyOptions::default()).expect_err("inf Phi_t");
    let text = err.to_string();
    assert_eq!(term(err), "Phi_t row 1 (constraint 1)");
    assert!(text.contains(" at t = 0 s"), "{text}");
}

#[test]
fn a_nan_mass_entry_of_a_chain_is_named_by_the_banded_route() {
    // A02 with N = 40 (the banded direct route reads M and Phi_q for finiteness while it
    // fills its matrix) and the inertia sqrt(x7 - 10), NaN while x7 < 10.
    let source = mechanism::builtin::builtin_source("n_four_bar")
        .unwrap()
        .replacen("kinetic = ", "kinetic = 1/2*sqrt(x7 - 10)*der(x7)^2 + ", 1);
    let system = interpreted(&source);
    let n = system.info().n();
    let mut q = vec![0.0; n];
    for (i, tip) in q.chunks_exact_mut(2).enumerate() {
        tip.copy_from_slice(&[i as f64 + 20.0, 1.0]);
    }
    let mut dynamics = Dynamics::new(system.info());
    dynamics
        .solve(&system, 0.0, &q, &vec![0.0; n])
        .expect("finite");
    assert_eq!(dynamics.banded_solves, 1, "the banded route solved it");
    q[14] = 7.0;
    let err = dynamics
        .solve(&system, 0.0, &q, &vec![0.0; n])
        .expect_err("NaN mass");
    assert_eq!(term(err), "M[x7, x7]");
}
