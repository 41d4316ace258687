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

use std::collections::HashMap;

use mechanism_codegen::{Arena, Func, Id, Node, Number, SymbolId, SymbolKind};
use proptest::prelude::*;

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

/// A value with its first-order rounding-error bound in units of eps.
#[derive(Clone, Copy, Debug)]
pub struct Approx {
    /// The computed value.
    pub v: f64,
    /// Absolute error bound / eps.
    pub e: f64,
}

fn ap(v: f64, e: f64) -> Approx {
    Approx { v, e }
}

fn func_approx(f: Func, u: Approx) -> Approx {
    let r = f.apply(u.v);
    let d = match f {
        Func::Sin | Func::Cos | Func::Abs => 1.0,
        Func::Tan => 1.0 + r * r,
        Func::Exp => r.abs(),
        Func::Ln => 1.0 / u.v.abs(),
    };
    ap(r, d * u.e + r.abs() + 1e-300)
}

fn atan2_approx(y: Approx, x: Approx) -> Approx {
    let r = y.v.atan2(x.v);
    let n2 = x.v * x.v + y.v * y.v;
    // Near the branch cut (y ~ 0, x < 0) a rounding error in y flips the sign: ill-conditioned.
    let cut = x.v < 0.0 && y.v.abs() <= 1e-6 * x.v.abs();
    let e = if cut || n2 == 0.0 {
        f64::INFINITY
    } else {
        (x.v.abs() * y.e + y.v.abs() * x.e) / n2 + r.abs()
    };
    ap(r, e)
}

fn mul_approx(xs: &[Approx]) -> Approx {
    let v: f64 = xs.iter().map(|x| x.v).product();
    let mut e = (xs.len() as f64 - 1.0) * v.abs();
    for i in 0..xs.len() {
        let others: f64 = xs
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != i)
            .map(|(_, x)| x.v.abs())
            .product();
        e += others * xs[i].e;
    }
    ap(v, e)
}

fn add_approx(xs: &[Approx]) -> Approx {
    let v: f64 = xs.iter().map(|x| x.v).sum();
    let mag: f64 = xs.iter().map(|x| x.v.abs()).sum();
    let e: f64 = xs.iter().map(|x| x.e).sum::<f64>() + (xs.len() as f64 - 1.0) * mag;
    ap(v, e)
}

fn powi_approx(x: Approx, k: i64) -> Approx {
    let r = x.v.powi(k as i32);
    let d = (k as f64 * x.v.powi(k as i32 - 1)).abs();
    ap(r, d * x.e + (k.unsigned_abs() as f64 + 1.0) * r.abs())
}

fn pow_approx(x: Approx, y: Approx, k: Option<Number>) -> Approx {
    if let Some(Number::Rational(k, 1)) = k {
        return powi_approx(x, k);
    }
    let r = x.v.powf(y.v);
    let dx = (y.v * x.v.powf(y.v - 1.0)).abs();
    let dy = (x.v.abs().ln() * r).abs();
    ap(r, dx * x.e + dy * y.e + 2.0 * r.abs())
}

/// Direct f64 evaluation of the tree (no arena, no canonical forms), with its error bound.
pub fn direct(e: &Ast, x: &[f64]) -> Approx {
    let c = |v: f64| ap(v, 0.0);
    match e {
        Ast::Int(n) => c(*n as f64),
        Ast::Rat(p, q) => ap(*p as f64 / *q as f64, (*p as f64 / *q as f64).abs()),
        Ast::Float(v) => c(*v),
        Ast::Pi => c(std::f64::consts::PI),
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

/// Independent evaluation of an arena expression (a recursive walk with a memo, written
/// separately from the crate's evaluator), with the error bound of that operation order.
pub fn dag(
    arena: &Arena,
    id: Id,
    x: &dyn Fn(SymbolId) -> f64,
    memo: &mut HashMap<Id, Approx>,
) -> Approx {
    if let Some(r) = memo.get(&id) {
        return *r;
    }
    let r = match arena.node(id).clone() {
        Node::Num(n) => match n {
            Number::Rational(_, 1) | Number::Float(_) => ap(n.to_f64(), 0.0),
            Number::Rational(..) => ap(n.to_f64(), n.to_f64().abs()),
        },
        Node::Pi => ap(std::f64::consts::PI, 0.0),
        Node::Sym(s) => ap(x(s), 0.0),
        Node::Add(ts) => {
            let v: Vec<Approx> = ts.iter().map(|t| dag(arena, *t, x, memo)).collect();
            add_approx(&v)
        }
        Node::Mul(fs) => {
            let v: Vec<Approx> = fs.iter().map(|t| dag(arena, *t, x, memo)).collect();
            mul_approx(&v)
        }
        Node::Pow(b, e) => {
            let (bv, ev) = (dag(arena, b, x, memo), dag(arena, e, x, memo));
            pow_approx(bv, ev, arena.as_number(e))
        }
        Node::Func(f, a) => func_approx(f, dag(arena, a, x, memo)),
        Node::Atan2(y, xx) => atan2_approx(dag(arena, y, x, memo), dag(arena, xx, x, memo)),
    };
    memo.insert(id, r);
    r
}

/// `|a - b| <= 8 eps (ea + eb)`, the first-order rounding bound of two evaluation orders.
pub fn close(a: f64, b: f64, ea: f64, eb: f64) -> bool {
    (a - b).abs() <= 8.0 * f64::EPSILON * (ea + eb) + 1e-300
}

/// A strategy for symbol values in [-2, 2].
pub fn point() -> impl Strategy<Value = Vec<f64>> {
    proptest::collection::vec(-2.0f64..2.0, NSYM)
}
