//! A large declaration (the closed 32-bar chain, N = 32 coordinates): its emitted code groups
//! the `let`s into nested blocks (more than `BLOCK_LETS_ABOVE` instructions) so that a
//! debuginfo build (this test profile's) compiles, and must still equal the interpreter route.

use mechanism::{Compiled, Evaluation, Interpreted, Kinematic, System};

mechanism::mechanism!(file = "benches/mechanisms/closed_chain_32.mech");

#[test]
fn emitted_register_array_code_equals_the_interpreter() {
    let source = include_str!("../../benches/mechanisms/closed_chain_32.mech");
    let interpreted = Interpreted::from_source(source).expect("derives");
    let compiled = Compiled::new(ClosedChain32::default());
    let (n, m) = (compiled.info().n(), compiled.info().m());
    assert_eq!((n, m), (32, 2));
    let q: Vec<f64> = compiled
        .info()
        .initial_guess
        .iter()
        .enumerate()
        .map(|(i, g)| g + 0.01 * (i as f64).sin())
        .collect();
    let qd: Vec<f64> = (0..n).map(|i| (0.7 * i as f64).cos()).collect();
    let (mut a, mut b) = (Evaluation::zeros(n, m), Evaluation::zeros(n, m));
    compiled.evaluate(0.2, &q, &qd, &mut a);
    interpreted.evaluate(0.2, &q, &qd, &mut b);
    // Same CSE'd program, two back ends: equal up to reassociation, 1e-12 of each
    // quantity's largest entry.
    let close = |x: &nalgebra::DMatrix<f64>, y: &nalgebra::DMatrix<f64>| {
        (x - y).amax() <= 1e-12 * y.amax().max(1.0)
    };
    assert!(close(&a.mass, &b.mass), "M");
    for (x, y, what) in [
        (&a.coriolis, &b.coriolis, "C q'"),
        (&a.gravity, &b.gravity, "g"),
        (&a.phi, &b.phi, "Phi"),
        (&a.gamma, &b.gamma, "gamma"),
    ] {
        assert!((x - y).amax() <= 1e-12 * y.amax().max(1.0), "{what}");
    }
    assert!(close(&a.phi_q, &b.phi_q), "Phi_q");
    assert!((a.kinetic - b.kinetic).abs() <= 1e-12 * b.kinetic.abs().max(1.0));
}
