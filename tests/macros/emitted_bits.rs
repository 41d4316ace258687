//! The emitted combined evaluation gives the interpreter's bits, whichever copy the CPU
//! runs.
//!
//! A build for every x86-64 CPU compiles `evaluate_into` twice, the second time with AVX2,
//! and calls that copy where the CPU has AVX2. Both copies call the same rounding functions
//! as the interpreter's tape (`mechanism::math`: `sin_cos`, `mul_add`, ...), on the same
//! program (the tape runs the same CSE'd, fused instructions; the parameter-only values the
//! emitted code caches are the same operations done earlier), so every entry must be equal
//! bit for bit, not merely close. A copy that fused a product the other does not, or a
//! four-lane sine that rounded differently from the scalar one, would show here.

use mechanism::builtin::{builtin, builtin_names, builtin_source};
use mechanism::{Evaluation, Interpreted, System};

/// Every entry of an evaluation, as bits (outputs in the evaluation's order).
fn bits(e: &Evaluation) -> Vec<u64> {
    let vectors = [
        &e.coriolis,
        &e.gravity,
        &e.forces,
        &e.phi,
        &e.phi_t,
        &e.gamma,
    ];
    e.mass
        .iter()
        .chain(e.phi_q.iter())
        .chain(vectors.into_iter().flatten())
        .chain([&e.kinetic, &e.potential])
        .map(|x| x.to_bits())
        .collect()
}

/// States on and off the sine's fast path: ordinary angles, exact multiples of pi/2 (the
/// four-bar's crank at 90 degrees), a value just off one, large and negative-zero angles.
fn coordinates(n: usize, k: usize) -> Vec<f64> {
    use std::f64::consts::FRAC_PI_2;
    (0..n)
        .map(|i| match (k + i) % 7 {
            0 => 0.3 + 0.7 * i as f64 - 0.11 * k as f64,
            1 => FRAC_PI_2 * (k as f64 - 3.0),
            2 => FRAC_PI_2 + 1.4e-8,
            3 => -2.5e6 + 0.37 * k as f64,
            4 => -0.0,
            5 => 1.0 / (1.0 + k as f64),
            _ => -3.0 + 0.9 * (i + k) as f64,
        })
        .collect()
}

#[test]
fn emitted_evaluation_is_the_tape_bit_for_bit() {
    let copy = if cfg!(target_arch = "x86_64") && !cfg!(target_feature = "avx2") {
        "the AVX2 copy where the CPU has it"
    } else {
        "the build's only copy"
    };
    for name in builtin_names() {
        let mut compiled = builtin(name).expect("registered");
        let source = builtin_source(name).expect("registered");
        let mut tape = Interpreted::from_source(source).expect("a library file");
        let (n, m) = (compiled.info().n(), compiled.info().m());
        let mut defaults = vec![0.0; compiled.info().parameters.len()];
        compiled.parameter_values(&mut defaults);
        for k in 0..7 {
            // Parameters changed too: the emitted cache is refreshed, the tape reads them.
            for (i, p) in defaults.iter().enumerate() {
                let p = p * (1.0 + 0.01 * k as f64);
                assert!(compiled.set_parameter(i, p).is_ok() && tape.set_parameter(i, p).is_ok());
            }
            let q = coordinates(n, k);
            let qd: Vec<f64> = (0..n).map(|i| -1.1 + 0.4 * (i + k) as f64).collect();
            let t = 0.25 * k as f64;
            let (mut a, mut b) = (Evaluation::zeros(n, m), Evaluation::zeros(n, m));
            compiled.evaluate(t, &q, &qd, &mut a);
            tape.evaluate(t, &q, &qd, &mut b);
            assert_eq!(bits(&a), bits(&b), "{name} at q = {q:?} ({copy})");
        }
    }
}
