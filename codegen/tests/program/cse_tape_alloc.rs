//! `Tape::eval` and `Tape::run` allocate nothing: a counting global allocator (this test binary only)
//! sees zero allocations across many evaluations of a realistic program.

use mechanism_codegen::{Arena, Matrix, Program, SymbolKind, Tape};

#[test]
fn tape_eval_does_not_allocate() {
    // A 3-link chain's positions and their squares: sums, products, sin_cos, powers, sqrt.
    let mut a = Arena::new();
    let th: Vec<_> = (0..3).map(|i| a.coordinate(&format!("th{i}"))[0]).collect();
    let l = a.symbol("l", SymbolKind::Parameter);
    let (mut xs, mut ys) = (vec![], vec![]);
    for &t in &th {
        let c = a.cos(t);
        let s = a.sin(t);
        xs.push(a.mul2(l, c));
        ys.push(a.mul2(l, s));
    }
    let x = a.add(&xs);
    let y = a.add(&ys);
    let x2 = a.powi(x, 2).unwrap();
    let y2 = a.powi(y, 2).unwrap();
    let r2 = a.add2(x2, y2);
    let r = a.sqrt(r2).unwrap();
    let inv = a.powi(r, -3).unwrap();
    let m = Matrix::column(vec![x, y, r, inv]);
    let p = Program::new(&a, &[&m]).unwrap();
    let mut tape = Tape::new(&p);
    let nsym = a.symbols().len();
    let mut inputs = vec![0.3; nsym];
    let mut out = vec![0.0; tape.output_len()];
    tape.eval(&inputs, &mut out).unwrap();
    let mut registers = vec![0.0; tape.register_len()];
    let slots: Vec<(usize, usize)> = tape.input_slots().map(|(s, k)| (s.index(), k)).collect();
    let before = mechanism_test_support::allocations();
    for k in 0..1000 {
        inputs[0] = 0.001 * k as f64;
        tape.eval(&inputs, &mut out).unwrap();
    }
    for k in 0..1000 {
        inputs[0] = 0.001 * k as f64;
        for &(s, slot) in &slots {
            registers[slot] = inputs[s];
        }
        tape.run(&mut registers, &mut out);
    }
    let after = mechanism_test_support::allocations();
    assert_eq!(after - before, 0, "Tape::eval or Tape::run allocated");
    assert!(out.iter().all(|v| v.is_finite()));
}
