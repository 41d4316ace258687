//! The emitter's API: output targets, zero skipping, per-body dead-code removal and counts,
//! typed errors, and constant literals that round-trip exactly.

use mechanism_codegen::error::{EvalError, ProgramError};
use mechanism_codegen::{
    Arena, EmitBindings, Error, Id, Matrix, OutputTarget, Program, SymbolKind, emit_body,
    f64_tokens,
};
use proptest::prelude::*;
use quote::quote;

fn squash(t: &proc_macro2::TokenStream) -> String {
    t.to_string()
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect()
}

struct Setup {
    a: Arena,
    q: Id,
    l: Id,
    b: EmitBindings,
}

fn setup() -> Setup {
    let mut a = Arena::new();
    let [q, ..] = a.coordinate("phi");
    let l = a.symbol("l1", SymbolKind::Parameter);
    let mut b = EmitBindings::new();
    b.bind(a.as_symbol(q).unwrap(), quote!(q[0]))
        .bind(a.as_symbol(l).unwrap(), quote!(self.l1));
    Setup { a, q, l, b }
}

#[test]
fn matrix_and_vector_targets() {
    let mut s = setup();
    let c = s.a.cos(s.q);
    let lc = s.a.mul2(s.l, c);
    let zero = s.a.int(0);
    let m = Matrix::new(2, 2, vec![lc, zero, zero, s.l]).unwrap();
    let v = Matrix::column(vec![c, zero]);
    let p = Program::new(&s.a, &[&m, &v]).unwrap();
    let zeroed = [
        OutputTarget::Matrix {
            name: quote!(out_m),
            zeroed: true,
        },
        OutputTarget::Vector {
            name: quote!(out_v),
            zeroed: true,
        },
    ];
    let body = emit_body(&p, &s.b, &zeroed).unwrap();
    assert_eq!(
        squash(&body.tokens),
        "out_m[(1,1)]=self.l1;letx0:f64=q[0].cos();out_v[0]=x0;letx1:f64=self.l1*x0;out_m[(0,0)]=x1;"
    );
    assert_eq!(
        (body.counts.muls, body.counts.calls, body.registers),
        (1, 1, 2)
    );
    let full = [
        OutputTarget::Matrix {
            name: quote!(out_m),
            zeroed: false,
        },
        OutputTarget::Vector {
            name: quote!(out_v),
            zeroed: false,
        },
    ];
    let body = emit_body(&p, &s.b, &full).unwrap();
    let text = squash(&body.tokens);
    assert!(
        text.contains("out_m[(0,1)]=0.0_f64;") && text.contains("out_v[1]=0.0_f64;"),
        "{text}"
    );
}

#[test]
fn skipped_outputs_drop_their_instructions() {
    let mut s = setup();
    let c = s.a.cos(s.q);
    let e = s.a.func(mechanism_codegen::Func::Exp, s.q).unwrap();
    let p = Program::new(&s.a, &[&Matrix::column(vec![c]), &Matrix::column(vec![e])]).unwrap();
    let body = emit_body(&p, &s.b, &[OutputTarget::Skip, OutputTarget::Return]).unwrap();
    assert_eq!(
        squash(&body.tokens),
        "q[0].exp()",
        "tail inlined, cos left out"
    );
    assert_eq!(body.counts, p.output_op_counts(1).unwrap());
    assert_eq!(
        body.symbols,
        vec![s.a.as_symbol(s.q).unwrap()],
        "l1 is not read by this body"
    );
    let both = emit_body(
        &p,
        &s.b,
        &[
            OutputTarget::Vector {
                name: quote!(o),
                zeroed: false,
            },
            OutputTarget::Return,
        ],
    )
    .unwrap();
    assert_eq!(
        squash(&both.tokens),
        "letx0:f64=q[0].cos();o[0]=x0;letx1:f64=q[0].exp();x1"
    );
    assert_eq!(both.counts, p.op_counts());
}

#[test]
fn returned_tail_is_never_let_and_return() {
    let mut s = setup();
    let c = s.a.cos(s.q);
    let si = s.a.sin(s.q);
    let p = Program::new(&s.a, &[&Matrix::column(vec![c]), &Matrix::column(vec![si])]).unwrap();
    // cos is the second half of the sin_cos pair: the tail reads the pair's register.
    let body = emit_body(
        &p,
        &s.b,
        &[
            OutputTarget::Return,
            OutputTarget::Vector {
                name: quote!(o),
                zeroed: false,
            },
        ],
    )
    .unwrap();
    assert_eq!(
        squash(&body.tokens),
        "let(x0,x1):(f64,f64)=q[0].sin_cos();o[0]=x0;x1"
    );
}

#[test]
fn errors_are_typed() {
    let mut s = setup();
    let c = s.a.cos(s.q);
    let t = s.a.symbol("t", SymbolKind::Time);
    let ct = s.a.mul2(c, t);
    let p = Program::new(&s.a, &[&Matrix::column(vec![ct, c])]).unwrap();
    let v = OutputTarget::Vector {
        name: quote!(o),
        zeroed: false,
    };
    assert_eq!(
        emit_body(&p, &s.b, std::slice::from_ref(&v)).unwrap_err(),
        Error::Eval(EvalError::MissingValue { name: "t".into() })
    );
    assert!(
        matches!(
            emit_body(&p, &s.b, &[]),
            Err(Error::Program(ProgramError::OutputCount { .. }))
        ),
        "target count"
    );
    assert!(
        matches!(
            emit_body(&p, &s.b, &[OutputTarget::Return]),
            Err(Error::Program(ProgramError::ReturnNotScalar { .. }))
        ),
        "2 x 1 returned"
    );
    let p2 = Program::new(&s.a, &[&Matrix::column(vec![c]), &Matrix::column(vec![c])]).unwrap();
    assert!(matches!(
        emit_body(&p2, &s.b, &[OutputTarget::Return, OutputTarget::Return]),
        Err(Error::Program(ProgramError::SeveralReturns {
            first: 0,
            second: 1
        }))
    ));
    let square = Program::new(&s.a, &[&Matrix::new(2, 2, vec![c; 4]).unwrap()]).unwrap();
    let as_vector = OutputTarget::Vector {
        name: quote!(o),
        zeroed: false,
    };
    assert!(
        matches!(
            emit_body(&square, &s.b, &[as_vector]),
            Err(Error::Program(ProgramError::MatrixAsVector { .. }))
        ),
        "a 2 x 2 output is not a vector (nalgebra's linear index is column-major)"
    );
    let mut bad = s.b.clone();
    bad.set_prefix("1x");
    assert!(matches!(
        emit_body(&p2, &bad, &[OutputTarget::Return, OutputTarget::Skip]),
        Err(Error::Program(ProgramError::RegisterPrefix { .. }))
    ));
    // with t bound, it works and names registers with the prefix
    let mut ok = s.b.clone();
    ok.bind(s.a.as_symbol(t).unwrap(), quote!(t))
        .set_prefix("v_");
    let body = emit_body(&p, &ok, &[v]).unwrap();
    assert_eq!(
        squash(&body.tokens),
        "letv_0:f64=q[0].cos();o[1]=v_0;letv_1:f64=v_0*t;o[0]=v_1;"
    );
}

#[test]
fn named_constants_are_paths() {
    assert_eq!(
        squash(&f64_tokens(std::f64::consts::PI)),
        "::core::f64::consts::PI"
    );
    assert_eq!(
        squash(&f64_tokens(-std::f64::consts::FRAC_PI_2)),
        "-::core::f64::consts::FRAC_PI_2"
    );
    assert_eq!(squash(&f64_tokens(0.5)), "0.5_f64");
    assert_eq!(squash(&f64_tokens(-2.0)), "-2.0_f64");
    assert_eq!(squash(&f64_tokens(1e-300)), "1e-300_f64");
}

proptest! {
    /// Every finite f64 is written as a literal that reads back to the same bits.
    #[test]
    fn literals_round_trip(bits in any::<u64>()) {
        let v = f64::from_bits(bits);
        prop_assume!(v.is_finite());
        let text = squash(&f64_tokens(v));
        prop_assume!(!text.contains("consts"));
        let (sign, body) = match text.strip_prefix('-') { Some(b) => (-1.0, b), None => (1.0, text.as_str()) };
        let lit = body.strip_suffix("_f64").expect("suffixed literal");
        let back: f64 = sign * lit.parse::<f64>().unwrap();
        prop_assert_eq!(back.to_bits(), if v == 0.0 { 0.0f64.to_bits() } else { v.to_bits() });
    }
}
