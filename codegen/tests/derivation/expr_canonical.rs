//! Canonical forms of the arena: equal expressions built different ways get one id.

use mechanism_codegen::{Arena, Func, SymbolKind};

fn setup() -> (Arena, [mechanism_codegen::Id; 3]) {
    let mut a = Arena::new();
    let x = a.symbol("x", SymbolKind::Free);
    let y = a.symbol("y", SymbolKind::Free);
    let z = a.symbol("z", SymbolKind::Free);
    (a, [x, y, z])
}

#[test]
fn like_terms_collect_and_cancel() {
    let (mut a, [x, y, _]) = setup();
    let two = a.int(2);
    let xx = a.add(&[x, x]);
    let tx = a.mul(&[two, x]);
    assert_eq!(xx, tx, "x + x = 2*x");
    // 2*(x + y) - 2*x - 2*y = 0 (a numeric factor distributes over one sum)
    let s = a.add2(x, y);
    let ts = a.mul2(two, s);
    let m2x = a.neg(tx);
    let ty = a.mul2(two, y);
    let m2y = a.neg(ty);
    let zero = a.add(&[ts, m2x, m2y]);
    assert!(a.is_zero(zero));
}

#[test]
fn powers_collect() {
    let (mut a, [x, y, _]) = setup();
    let x2 = a.powi(x, 2).unwrap();
    let x3 = a.powi(x, 3).unwrap();
    assert_eq!(a.mul(&[x, x, x]), x3);
    assert_eq!(a.mul2(x2, x), x3);
    let xy = a.mul2(x, y);
    let xy2 = a.powi(xy, 2).unwrap();
    let y2 = a.powi(y, 2).unwrap();
    assert_eq!(xy2, a.mul2(x2, y2), "(x*y)^2 = x^2*y^2");
    let one = a.div(x, x).unwrap();
    assert_eq!(a.as_number(one).map(|n| n.to_f64()), Some(1.0));
    let zero = a.int(0);
    assert!(a.div(x, zero).is_err(), "x/0 is a typed error");
}

#[test]
fn parity_of_sin_and_cos() {
    let (mut a, [x, y, _]) = setup();
    let d = a.sub(x, y);
    let md = a.sub(y, x);
    let s1 = a.sin(d);
    let s2 = a.sin(md);
    assert_eq!(a.neg(s1), s2, "sin(y - x) = -sin(x - y)");
    assert_eq!(a.cos(d), a.cos(md), "cos(y - x) = cos(x - y)");
}

#[test]
fn pythagoras_with_common_factor() {
    let (mut a, [x, y, z]) = setup();
    let s = a.sin(x);
    let c = a.cos(x);
    let s2 = a.powi(s, 2).unwrap();
    let c2 = a.powi(c, 2).unwrap();
    let three = a.int(3);
    let t1 = a.mul(&[three, y, s2]);
    let t2 = a.mul(&[three, y, c2]);
    let sum = a.add(&[t1, z, t2]);
    let three_y = a.mul2(three, y);
    assert_eq!(sum, a.add2(three_y, z), "3y sin^2 + z + 3y cos^2 = 3y + z");
    let plain = a.add2(s2, c2);
    assert_eq!(a.as_number(plain).map(|n| n.to_f64()), Some(1.0));
}

#[test]
fn constant_folding() {
    let (mut a, [x, ..]) = setup();
    let zero = a.int(0);
    let s0 = a.func(Func::Sin, zero).unwrap();
    assert!(a.is_zero(s0));
    let c0 = a.func(Func::Cos, zero).unwrap();
    assert_eq!(a.as_number(c0).map(|n| n.to_f64()), Some(1.0));
    assert!(a.func(Func::Ln, zero).is_err(), "ln(0) is a domain error");
    let h = a.rational(1, 2).unwrap();
    let q = a.rational(1, 3).unwrap();
    let s = a.add2(h, q);
    assert_eq!(s, a.rational(5, 6).unwrap());
    let e = a.add2(x, zero);
    assert_eq!(e, x);
}
