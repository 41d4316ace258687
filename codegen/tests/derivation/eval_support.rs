//! Shared test support for the eval/cse/tape tests: a random expression tree (built both as
//! an arena expression and evaluated directly in f64) and a first-order rounding-error bound.
//!
//! Tolerances. Two evaluations of the same real function by different (canonicalised,
//! reassociated) operation sequences differ by at most the sum of their rounding errors.
//! To first order, a computed value carries an absolute error of at most `eps * E`, where E is
//! propagated through each operation (`E(a + b) = E(a) + E(b) + |a + b|`,
//! `E(a b) = |b| E(a) + |a| E(b) + |a b|`, `E(f(u)) = |f'(u)| E(u) + |f(u)|`, ...). The tests
//! accept `|x - y| <= 8 eps (E_x + E_y)`: a factor 8 covers libm's 1-ulp functions and the
//! first-order truncation. Cases whose bound is not finite (ill-conditioned) are skipped.
#![allow(dead_code)]

use mechanism_codegen::{Arena, Func, Id, SymbolKind};
use proptest::prelude::*;

pub use mechanism_test_support::rounding::*;

/// Number of free symbols the generator uses (x0 .. x3).
pub const NSYM: usize = 4;

/// A random expression tree.
#[derive(Clone, Debug)]
pub enum Ast {
    /// integer constant
    Int(i64),
    /// rational p/q
    Rat(i64, i64),
    /// float constant
    Float(f64),
    /// pi
    Pi,
    /// symbol x_i
    Sym(usize),
    /// a + b
    Add(Box<Ast>, Box<Ast>),
    /// a - b
    Sub(Box<Ast>, Box<Ast>),
    /// a * b
    Mul(Box<Ast>, Box<Ast>),
    /// a / b
    Div(Box<Ast>, Box<Ast>),
    /// -a
    Neg(Box<Ast>),
    /// a^k
    PowI(Box<Ast>, i64),
    /// sqrt(|a| + 1/4)
    SqrtSafe(Box<Ast>),
    /// ln(|a| + 1/2)
    LnSafe(Box<Ast>),
    /// sin, cos, tan, exp or abs of a
    Func(Func, Box<Ast>),
    /// atan2(a, b)
    Atan2(Box<Ast>, Box<Ast>),
}

/// A strategy for expression trees of moderate depth.
pub fn ast() -> impl Strategy<Value = Ast> {
    let leaf = prop_oneof![
        (-4i64..=4).prop_map(Ast::Int),
        ((-5i64..=5), (1i64..=4)).prop_map(|(p, q)| Ast::Rat(p, q)),
        (-3.0f64..3.0).prop_map(Ast::Float),
        Just(Ast::Pi),
        (0..NSYM).prop_map(Ast::Sym),
        (0..NSYM).prop_map(Ast::Sym),
        (0..NSYM).prop_map(Ast::Sym),
    ];
    leaf.prop_recursive(5, 48, 2, |inner| {
        let b = |x: Ast| Box::new(x);
        prop_oneof![
            (inner.clone(), inner.clone()).prop_map(move |(x, y)| Ast::Add(b(x), b(y))),
            (inner.clone(), inner.clone()).prop_map(move |(x, y)| Ast::Sub(b(x), b(y))),
            (inner.clone(), inner.clone()).prop_map(move |(x, y)| Ast::Mul(b(x), b(y))),
            (inner.clone(), inner.clone()).prop_map(move |(x, y)| Ast::Div(b(x), b(y))),
            inner.clone().prop_map(move |x| Ast::Neg(b(x))),
            (inner.clone(), -3i64..=4).prop_map(move |(x, k)| Ast::PowI(b(x), k)),
            inner.clone().prop_map(move |x| Ast::SqrtSafe(b(x))),
            inner.clone().prop_map(move |x| Ast::LnSafe(b(x))),
            (
                prop_oneof![
                    Just(Func::Sin),
                    Just(Func::Cos),
                    Just(Func::Tan),
                    Just(Func::Exp),
                    Just(Func::Abs)
                ],
                inner.clone()
            )
                .prop_map(move |(f, x)| Ast::Func(f, b(x))),
            (inner.clone(), inner).prop_map(move |(x, y)| Ast::Atan2(b(x), b(y))),
        ]
    })
}

/// Declares the free symbols x0..x3 and returns their node ids.
pub fn symbols(arena: &mut Arena) -> Vec<Id> {
    (0..NSYM)
        .map(|i| arena.symbol(&format!("x{i}"), SymbolKind::Free))
        .collect()
}

/// Builds the tree in the arena with the canonical constructors (`None` when a constructor
/// refuses, e.g. division by a constant zero).
pub fn build(a: &mut Arena, syms: &[Id], e: &Ast) -> Option<Id> {
    Some(match e {
        Ast::Int(n) => a.int(*n),
        Ast::Rat(p, q) => a.rational(*p, *q).ok()?,
        Ast::Float(x) => a.float(*x).ok()?,
        Ast::Pi => a.pi(),
        Ast::Sym(i) => syms[*i],
        Ast::Add(x, y) => {
            let (x, y) = (build(a, syms, x)?, build(a, syms, y)?);
            a.add2(x, y)
        }
        Ast::Sub(x, y) => {
            let (x, y) = (build(a, syms, x)?, build(a, syms, y)?);
            a.sub(x, y)
        }
        Ast::Mul(x, y) => {
            let (x, y) = (build(a, syms, x)?, build(a, syms, y)?);
            a.mul2(x, y)
        }
        Ast::Div(x, y) => {
            let (x, y) = (build(a, syms, x)?, build(a, syms, y)?);
            a.div(x, y).ok()?
        }
        Ast::Neg(x) => {
            let x = build(a, syms, x)?;
            a.neg(x)
        }
        Ast::PowI(x, k) => {
            let x = build(a, syms, x)?;
            a.powi(x, *k).ok()?
        }
        Ast::SqrtSafe(x) => {
            let x = build(a, syms, x)?;
            let ax = a.func(Func::Abs, x).ok()?;
            let q = a.rational(1, 4).ok()?;
            let s = a.add2(ax, q);
            a.sqrt(s).ok()?
        }
        Ast::LnSafe(x) => {
            let x = build(a, syms, x)?;
            let ax = a.func(Func::Abs, x).ok()?;
            let h = a.rational(1, 2).ok()?;
            let s = a.add2(ax, h);
            a.func(Func::Ln, s).ok()?
        }
        Ast::Func(f, x) => {
            let x = build(a, syms, x)?;
            a.func(*f, x).ok()?
        }
        Ast::Atan2(y, x) => {
            let (y, x) = (build(a, syms, y)?, build(a, syms, x)?);
            a.atan2(y, x)
        }
    })
}

/// Direct f64 evaluation of the tree (no arena, no canonical forms), with its error bound.
pub fn direct(e: &Ast, x: &[f64]) -> Approx {
    let c = |v: f64| ap(v, 0.0);
    match e {
        Ast::Int(n) => c(*n as f64),
        Ast::Rat(p, q) => ap(*p as f64 / *q as f64, (*p as f64 / *q as f64).abs()),
        Ast::Float(v) => c(*v),
        // The double nearest pi is one rounding off the exact value, which the arena keeps
        // (sin(pi) is exactly 0 there, 1.2e-16 in f64).
        Ast::Pi => ap(std::f64::consts::PI, std::f64::consts::PI),
        Ast::Sym(i) => c(x[*i]),
        Ast::Add(a, b) => add_approx(&[direct(a, x), direct(b, x)]),
        Ast::Sub(a, b) => {
            let b = direct(b, x);
            add_approx(&[direct(a, x), ap(-b.v, b.e)])
        }
        Ast::Mul(a, b) => mul_approx(&[direct(a, x), direct(b, x)]),
        Ast::Div(a, b) => {
            let (a, b) = (direct(a, x), direct(b, x));
            let r = a.v / b.v;
            ap(r, a.e / b.v.abs() + (r / b.v).abs() * b.e + r.abs())
        }
        Ast::Neg(a) => {
            let a = direct(a, x);
            ap(-a.v, a.e)
        }
        Ast::PowI(a, k) => powi_approx(direct(a, x), *k),
        Ast::SqrtSafe(a) => {
            let u = func_approx(Func::Abs, direct(a, x));
            let s = add_approx(&[u, ap(0.25, 0.0)]);
            let r = s.v.sqrt();
            ap(r, s.e / (2.0 * r) + r)
        }
        Ast::LnSafe(a) => {
            let u = func_approx(Func::Abs, direct(a, x));
            func_approx(Func::Ln, add_approx(&[u, ap(0.5, 0.0)]))
        }
        Ast::Func(f, a) => func_approx(*f, direct(a, x)),
        Ast::Atan2(a, b) => atan2_approx(direct(a, x), direct(b, x)),
    }
}

/// A strategy for symbol values in [-2, 2].
pub fn point() -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec(-2.0f64..2.0, NSYM)
}
