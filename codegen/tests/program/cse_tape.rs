//! The tape's contract: output layout, typed errors for bad inputs and non-finite results.

use mechanism_codegen::error::{EvalError, ProgramError};
use mechanism_codegen::{Arena, Error, Func, Matrix, Program, SymbolKind, Tape};
use mechanism_math::sin_cos;

fn setup() -> (Arena, [mechanism_codegen::Id; 2]) {
    let mut a = Arena::new();
    let x = a.symbol("x", SymbolKind::Free);
    let y = a.symbol("y", SymbolKind::Free);
    (a, [x, y])
}

#[test]
fn outputs_are_written_matrix_after_matrix_row_major() {
    let (mut a, [x, y]) = setup();
    let s = a.sin(x);
    let xy = a.mul2(x, y);
    let one = a.int(1);
    let m = Matrix::new(2, 2, vec![x, y, s, one]).unwrap();
    let v = Matrix::column(vec![xy, s]);
    let p = Program::new(&a, &[&m, &v]).unwrap();
    let mut t = Tape::new(&p);
    assert_eq!(t.output_shapes(), &[(2, 2), (2, 1)]);
    assert_eq!(t.output_len(), 6);
    let mut out = [0.0; 6];
    t.eval(&[0.25, 3.0], &mut out).unwrap();
    // The tape computes sin with `trig::sin_cos` (what emitted code calls), bit for bit.
    let s = |x: f64| sin_cos(x).0;
    assert_eq!(out, [0.25, 3.0, s(0.25), 1.0, 0.75, s(0.25)]);
    // re-evaluation at another point overwrites everything
    t.eval(&[1.0, -2.0], &mut out).unwrap();
    assert_eq!(out, [1.0, -2.0, s(1.0), 1.0, -2.0, s(1.0)]);
}

#[test]
fn short_or_non_finite_inputs_are_errors() {
    let (mut a, [x, y]) = setup();
    let e = a.add2(x, y);
    let p = Program::new(&a, &[&Matrix::column(vec![e])]).unwrap();
    let mut t = Tape::new(&p);
    let mut out = [0.0];
    assert_eq!(
        t.eval(&[1.0], &mut out),
        Err(Error::Eval(EvalError::MissingValue { name: "y".into() }))
    );
    assert!(matches!(
        t.eval(&[1.0, f64::INFINITY], &mut out),
        Err(Error::Eval(EvalError::NonFinite { .. }))
    ));
    assert!(matches!(
        t.eval(&[1.0, 2.0], &mut [0.0; 2]),
        Err(Error::Program(ProgramError::OutputCount { .. }))
    ));
    assert_eq!(t.eval(&[1.0, 2.0], &mut out), Ok(()));
    assert_eq!(out, [3.0]);
}

#[test]
fn runtime_domain_errors_reach_the_outputs() {
    let (mut a, [x, y]) = setup();
    let d = a.div(y, x).unwrap();
    let l = a.func(Func::Ln, x).unwrap();
    let p = Program::new(&a, &[&Matrix::column(vec![d, l])]).unwrap();
    let mut t = Tape::new(&p);
    let mut out = [0.0; 2];
    assert!(
        matches!(
            t.eval(&[0.0, 1.0], &mut out),
            Err(Error::Eval(EvalError::NonFinite { .. }))
        ),
        "y/0"
    );
    assert!(
        matches!(
            t.eval(&[-1.0, 1.0], &mut out),
            Err(Error::Eval(EvalError::NonFinite { .. }))
        ),
        "ln(-1)"
    );
    t.eval(&[2.0, 1.0], &mut out).unwrap();
    assert_eq!(out, [0.5, 2.0_f64.ln()]);
}

/// `run` in the caller's register file gives what `eval` gives, bit for bit, and lets a
/// non-finite value through to the outputs it reaches (as the emitted code does).
#[test]
fn run_in_a_caller_register_file_matches_eval() {
    let (mut a, [x, y]) = setup();
    let s = a.sin(x);
    let xy = a.mul2(x, y);
    let l = a.func(Func::Ln, y).unwrap();
    let p = Program::new(&a, &[&Matrix::column(vec![s, xy, l])]).unwrap();
    let mut t = Tape::new(&p);
    let mut registers = vec![0.0; t.register_len()];
    let slots: Vec<(usize, usize)> = t.input_slots().map(|(s, k)| (s.index(), k)).collect();
    let load = |registers: &mut [f64], values: [f64; 2]| {
        for &(sym, slot) in &slots {
            registers[slot] = values[sym];
        }
    };
    let (mut by_run, mut by_eval) = ([0.0; 3], [0.0; 3]);
    load(&mut registers, [0.4, 2.5]);
    t.run(&mut registers, &mut by_run);
    t.eval(&[0.4, 2.5], &mut by_eval).unwrap();
    assert_eq!(by_run.map(f64::to_bits), by_eval.map(f64::to_bits));
    // ln of a negative: NaN in its output only, no error.
    load(&mut registers, [0.4, -1.0]);
    t.run(&mut registers, &mut by_run);
    assert_eq!(by_run[..2], [sin_cos(0.4).0, -0.4]);
    assert!(by_run[2].is_nan());
}
