//! A first-order rounding-error bound for expressions: a computed value carries an absolute
//! error of at most `eps * E`, with E propagated through each operation
//! (`E(a + b) = E(a) + E(b) + |a + b|`, `E(a b) = |b| E(a) + |a| E(b) + |a b|`,
//! `E(f(u)) = |f'(u)| E(u) + |f(u)|`, ...). Two evaluation orders of the same DAG differ by at
//! most the sum of their errors. Shared by codegen's eval tests and `emit-check`.

use std::collections::HashMap;

use mechanism_codegen::{Arena, Func, Id, Node, Number, SymbolId};

/// A value with its first-order rounding-error bound in units of eps.
#[derive(Clone, Copy, Debug)]
pub struct Approx {
    /// The computed value.
    pub v: f64,
    /// Absolute error bound / eps.
    pub e: f64,
}

/// The value `v` with the error bound `e` (in units of eps).
pub fn ap(v: f64, e: f64) -> Approx {
    Approx { v, e }
}

/// f(u) with E = |f'(u)| E(u) + |f(u)|.
pub fn func_approx(f: Func, u: Approx) -> Approx {
    let r = f.apply(u.v);
    let d = match f {
        Func::Sin | Func::Cos | Func::Abs => 1.0,
        Func::Tan => 1.0 + r * r,
        Func::Exp => r.abs(),
        Func::Ln => 1.0 / u.v.abs(),
    };
    ap(r, d * u.e + r.abs() + 1e-300)
}

/// atan2(y, x) with E = (|x| E(y) + |y| E(x)) / (x^2 + y^2) + |atan2(y, x)|; infinite at the
/// branch cut and at (or within rounding of) the origin, where it is ill-conditioned.
pub fn atan2_approx(y: Approx, x: Approx) -> Approx {
    let r = y.v.atan2(x.v);
    let n2 = x.v * x.v + y.v * y.v;
    // Near the branch cut (y ~ 0, x < 0) a rounding error in y flips the sign: ill-conditioned.
    let cut = x.v < 0.0 && y.v.abs() <= 1e-6 * x.v.abs();
    // Within its rounding error of the origin (exact arithmetic may put it at (0, 0), where
    // atan2 is 0, while f64 gives +-pi/2): ill-conditioned too.
    let near = |a: Approx| a.v.abs() <= 8.0 * f64::EPSILON * a.e;
    let e = if cut || n2 == 0.0 || (near(x) && near(y)) {
        f64::INFINITY
    } else {
        (x.v.abs() * y.e + y.v.abs() * x.e) / n2 + r.abs()
    };
    ap(r, e)
}

/// The product of `xs` with E = sum_i E(x_i) prod_{j != i} |x_j| + (k - 1) |prod|.
pub fn mul_approx(xs: &[Approx]) -> Approx {
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

/// The sum of `xs` with E = sum E(x_i) + (k - 1) sum |x_i|.
pub fn add_approx(xs: &[Approx]) -> Approx {
    let v: f64 = xs.iter().map(|x| x.v).sum();
    let mag: f64 = xs.iter().map(|x| x.v.abs()).sum();
    let e: f64 = xs.iter().map(|x| x.e).sum::<f64>() + (xs.len() as f64 - 1.0) * mag;
    ap(v, e)
}

/// x^k for an integer k with E = |k x^(k-1)| E(x) + (|k| + 1) |x^k|.
pub fn powi_approx(x: Approx, k: i64) -> Approx {
    let r = x.v.powi(k as i32);
    let d = (k as f64 * x.v.powi(k as i32 - 1)).abs();
    ap(r, d * x.e + (k.unsigned_abs() as f64 + 1.0) * r.abs())
}

/// x^y (an integer power when the exponent `k` is a known integer) with
/// E = |y x^(y-1)| E(x) + |ln|x| x^y| E(y) + 2 |x^y|.
pub fn pow_approx(x: Approx, y: Approx, k: Option<Number>) -> Approx {
    if let Some(Number::Rational(k, 1)) = k {
        return powi_approx(x, k);
    }
    let r = x.v.powf(y.v);
    let dx = (y.v * x.v.powf(y.v - 1.0)).abs();
    let dy = (x.v.abs().ln() * r).abs();
    ap(r, dx * x.e + dy * y.e + 2.0 * r.abs())
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
        // Its child's value, with its child's bound.
        Node::Named(a) => dag(arena, a, x, memo),
    };
    memo.insert(id, r);
    r
}

/// `|a - b| <= 8 eps (ea + eb)`, the first-order rounding bound of two evaluation orders.
pub fn close(a: f64, b: f64, ea: f64, eb: f64) -> bool {
    (a - b).abs() <= 8.0 * f64::EPSILON * (ea + eb) + 1e-300
}
