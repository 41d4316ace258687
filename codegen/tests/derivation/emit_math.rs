//! The emitter with a math module: every real function is a call into it (what lets the
//! generated code build without std), and without one the f64 methods.

use mechanism_codegen::{Arena, EmitBindings, Matrix, OutputTarget, Program, emit_body};
use quote::quote;

/// sin(phi), cos(phi) (a pair), cos(psi) alone, sqrt(psi), psi^11 (small powers become
/// products) and atan2(phi, psi),
/// emitted with the given bindings; the code with whitespace removed.
fn emitted(set_math: bool) -> String {
    let mut a = Arena::new();
    let [phi, ..] = a.coordinate("phi");
    let [psi, ..] = a.coordinate("psi");
    let (c, s) = (a.cos(phi), a.sin(phi));
    let lone = a.cos(psi);
    let root = a.sqrt(psi).unwrap();
    let eleven = a.int(11);
    let power = a.pow(psi, eleven).unwrap();
    let angle = a.atan2(phi, psi);
    let m = Matrix::column(vec![c, s, lone, root, power, angle]);
    let program = Program::new(&a, &[&m]).unwrap();
    let mut b = EmitBindings::new();
    b.bind(a.lookup("phi").unwrap(), quote!(q[0]))
        .bind(a.lookup("psi").unwrap(), quote!(q[1]));
    if set_math {
        b.set_math(quote!(::mechanism_math));
    }
    let target = OutputTarget::Vector {
        name: quote!(out),
        zeroed: false,
    };
    let body = emit_body(&program, &b, &[target]).unwrap();
    body.tokens.to_string().split_whitespace().collect()
}

#[test]
fn with_a_math_module_every_function_is_a_call_into_it() {
    let code = emitted(true);
    for call in [
        // The pair and the lone cosine, side by side (sin q[1] is not needed), the
        // coordinates read one by one.
        "let([x0,_],[x1,x2])=::mechanism_math::sin_cos_lanes([::mechanism_math::read(&(q[0])),::mechanism_math::read(&(q[1]))]);",
        "=::mechanism_math::sqrt(q[1]);",
        "=::mechanism_math::powi(q[1],11);",
        "=::mechanism_math::atan2(q[0],q[1]);",
    ] {
        assert!(code.contains(call), "{call} not in {code}");
    }
    // No method call survives: those need std.
    for method in [".sin", ".cos", ".sqrt", ".powi", ".atan2"] {
        assert!(!code.contains(method), "{method} in {code}");
    }
}

#[test]
fn without_one_the_code_calls_the_f64_methods() {
    let code = emitted(false);
    for call in [
        "=q[0].sin_cos();",
        "=q[1].cos();",
        "=q[1].sqrt();",
        "q[1].powi(11)",
        "=q[0].atan2(q[1]);",
    ] {
        assert!(code.contains(call), "{call} not in {code}");
    }
}
