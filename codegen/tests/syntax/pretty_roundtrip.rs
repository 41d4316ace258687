//! parse(to_text(e)) == e for random expression trees built through the arena's public
//! constructors (the printed text reads back to the very same node).

use mechanism_codegen::{Arena, Func, Id, SymbolKind, parse_expr, to_text};
use proptest::prelude::*;

/// A small expression tree over x, y, z, a rate der(phi) and time t.
#[derive(Clone, Debug)]
enum T {
    Sym(usize),
    Int(i64),
    Rat(i64, i64),
    Float(f64),
    Pi,
    Neg(Box<T>),
    Add(Vec<T>),
    Sub(Box<T>, Box<T>),
    Mul(Vec<T>),
    Div(Box<T>, Box<T>),
    Pow(Box<T>, Box<T>),
    Powi(Box<T>, i64),
    Sqrt(Box<T>),
    Func(Func, Box<T>),
    Atan2(Box<T>, Box<T>),
}

fn leaf() -> impl Strategy<Value = T> {
    prop_oneof![
        4 => (0usize..5).prop_map(T::Sym),
        2 => (-5i64..6).prop_map(T::Int),
        1 => (-7i64..8, 1i64..6).prop_map(|(a, b)| T::Rat(a, b)),
        1 => prop_oneof![Just(0.5), Just(0.04), Just(1e-4), Just(-2.5), Just(1e-9), Just(3.0), Just(-1.0)].prop_map(T::Float),
        1 => Just(T::Pi),
    ]
}

fn tree() -> impl Strategy<Value = T> {
    let funcs = prop_oneof![
        Just(Func::Sin),
        Just(Func::Cos),
        Just(Func::Tan),
        Just(Func::Exp),
        Just(Func::Ln),
        Just(Func::Abs)
    ];
    leaf().prop_recursive(5, 48, 4, move |inner| {
        prop_oneof![
            inner.clone().prop_map(|a| T::Neg(Box::new(a))),
            prop::collection::vec(inner.clone(), 2..4).prop_map(T::Add),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| T::Sub(Box::new(a), Box::new(b))),
            prop::collection::vec(inner.clone(), 2..4).prop_map(T::Mul),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| T::Div(Box::new(a), Box::new(b))),
            (inner.clone(), inner.clone()).prop_map(|(a, b)| T::Pow(Box::new(a), Box::new(b))),
            (inner.clone(), -3i64..4).prop_map(|(a, k)| T::Powi(Box::new(a), k)),
            inner.clone().prop_map(|a| T::Sqrt(Box::new(a))),
            (funcs.clone(), inner.clone()).prop_map(|(f, a)| T::Func(f, Box::new(a))),
            (inner.clone(), inner).prop_map(|(a, b)| T::Atan2(Box::new(a), Box::new(b))),
        ]
    })
}

/// Builds `t` through the public constructors; a constructor that refuses (a division by
/// zero, ln of a non-positive constant) leaves its first operand.
fn build(a: &mut Arena, s: &[Id; 5], t: &T) -> Id {
    match t {
        T::Sym(i) => s[*i],
        T::Int(n) => a.int(*n),
        T::Rat(p, q) => a.rational(*p, *q).unwrap(),
        T::Float(x) => a.float(*x).unwrap(),
        T::Pi => a.pi(),
        T::Neg(x) => {
            let v = build(a, s, x);
            a.neg(v)
        }
        T::Add(ts) => {
            let v: Vec<Id> = ts.iter().map(|t| build(a, s, t)).collect();
            a.add(&v)
        }
        T::Sub(x, y) => {
            let (u, v) = (build(a, s, x), build(a, s, y));
            a.sub(u, v)
        }
        T::Mul(ts) => {
            let v: Vec<Id> = ts.iter().map(|t| build(a, s, t)).collect();
            a.mul(&v)
        }
        T::Div(x, y) => {
            let (u, v) = (build(a, s, x), build(a, s, y));
            a.div(u, v).unwrap_or(u)
        }
        T::Pow(x, y) => {
            let (u, v) = (build(a, s, x), build(a, s, y));
            a.pow(u, v).unwrap_or(u)
        }
        T::Powi(x, k) => {
            let u = build(a, s, x);
            a.powi(u, *k).unwrap_or(u)
        }
        T::Sqrt(x) => {
            let u = build(a, s, x);
            a.sqrt(u).unwrap_or(u)
        }
        T::Func(f, x) => {
            let u = build(a, s, x);
            a.func(*f, u).unwrap_or(u)
        }
        T::Atan2(y, x) => {
            let (u, v) = (build(a, s, y), build(a, s, x));
            a.atan2(u, v)
        }
    }
}

fn symbols(a: &mut Arena) -> [Id; 5] {
    let [x, y, z] = ["x", "y", "z"].map(|n| a.symbol(n, SymbolKind::Free));
    let [_, rate, _] = a.coordinate("phi");
    let t = a.symbol("t", SymbolKind::Time);
    [x, y, z, rate, t]
}

fn round_trip(t: &T) -> Result<(), TestCaseError> {
    let mut a = Arena::new();
    let s = symbols(&mut a);
    let e = build(&mut a, &s, t);
    let text = to_text(&a, e);
    let back = parse_expr(&mut a, &text);
    prop_assert!(back.is_ok(), "{text}: {:?}", back);
    let back = back.unwrap();
    prop_assert_eq!(back, e, "{} reads back as {}", text, to_text(&a, back));
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 3000, ..ProptestConfig::default() })]

    #[test]
    fn printed_text_reads_back_to_the_same_node(t in tree()) {
        round_trip(&t)?;
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200_000, ..ProptestConfig::default() })]

    /// The same property on many more trees (about a minute): `cargo test -- --ignored`.
    #[test]
    #[ignore]
    fn printed_text_reads_back_exhaustive(t in tree()) {
        round_trip(&t)?;
    }
}
