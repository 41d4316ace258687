//! Direct numerical evaluation of expressions and matrices from a symbol table.
//!
//! This is the reference route: it walks the DAG once, children before parents (increasing
//! [`Id`] order is topological), so every shared node is evaluated once and no recursion depth
//! is involved. Every intermediate value is checked: a division by zero, ln or sqrt of a
//! negative number, or an overflow is [`crate::error::EvalError::NonFinite`], never a silent
//! NaN.
//!
//! For repeated evaluation of the same outputs use [`crate::Tape`], which compiles the
//! DAG once.

use crate::algebra::expr::{Arena, Func, Id, Node, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::{AlgebraError, EvalError};
use crate::error::{Error, Result};
use crate::number::Number;
use mechanism_math::sin_cos;

/// The value of the expression `id`, with each symbol s bound to `env(s)`.
///
/// Sums and products are evaluated left to right over their canonical operands; `x^k` for an
/// integer k by `powi`, `x^(1/2)` by `sqrt`, `x^(-1/2)` by `1/sqrt`, other powers by `powf`.
///
/// # Errors
/// [`crate::error::EvalError::MissingValue`] when `env` has no value for a symbol the
/// expression uses, [`crate::error::EvalError::NonFinite`] when an input or an intermediate
/// value is not finite, [`crate::error::AlgebraError::InvalidId`] when `id` is not a node of
/// `arena`.
///
/// # Example
/// ```
/// use mechanism_codegen::{eval, Arena, SymbolKind};
/// let mut a = Arena::new();
/// let x = a.symbol("x", SymbolKind::Free);
/// let s = a.sin(x);
/// let e = a.mul2(x, s);
/// let v = eval(&a, e, &|_| Some(0.5)).unwrap();
/// assert_eq!(v, 0.5 * mechanism_math::sin_cos(0.5).0);
/// ```
pub fn eval(arena: &Arena, id: Id, env: &dyn Fn(SymbolId) -> Option<f64>) -> Result<f64> {
    let v = eval_many(arena, &[id], env)?;
    v.first()
        .copied()
        .ok_or(Error::Algebra(AlgebraError::InvalidId {
            id: id.0,
            len: arena.len(),
        }))
}

/// The values of all entries of `m`, row-major (entry (i, j) at `i * m.cols() + j`), sharing
/// the evaluation of common subexpressions between entries.
///
/// # Errors
/// As [`eval`]; also [`crate::error::AlgebraError::MalformedMatrix`] for a matrix built inside
/// this crate whose entries do not fill rows x cols (the public constructors refuse one).
pub fn eval_matrix(
    arena: &Arena,
    m: &Matrix,
    env: &dyn Fn(SymbolId) -> Option<f64>,
) -> Result<Vec<f64>> {
    if m.rows.checked_mul(m.cols) != Some(m.data.len()) {
        return Err(Error::Algebra(AlgebraError::MalformedMatrix {
            rows: m.rows,
            cols: m.cols,
            len: m.data.len(),
        }));
    }
    eval_many(arena, &m.data, env)
}

/// The values of the expressions `ids`, in order, each shared node evaluated once.
///
/// # Errors
/// As [`eval`].
pub fn eval_many(
    arena: &Arena,
    ids: &[Id],
    env: &dyn Fn(SymbolId) -> Option<f64>,
) -> Result<Vec<f64>> {
    let len = arena.len();
    if let Some(bad) = ids.iter().find(|i| i.index() >= len) {
        return Err(Error::Algebra(AlgebraError::InvalidId { id: bad.0, len }));
    }
    let Some(top) = ids.iter().map(|i| i.index()).max() else {
        return Ok(Vec::new());
    };
    // Mark what is reachable: one reverse sweep suffices because children precede parents.
    let mut needed = vec![false; top + 1];
    for i in ids {
        needed[i.index()] = true;
    }
    let nodes = &arena.nodes()[..=top];
    for k in (0..=top).rev() {
        if needed[k] {
            nodes[k].for_each_child(|c| needed[c.index()] = true);
        }
    }
    let mut value = vec![0.0_f64; top + 1];
    for k in 0..=top {
        if needed[k] {
            value[k] = node_value(arena, &nodes[k], &value, env)?;
        }
    }
    // A reciprocal that overflowed and that no product brought back (see `node_value`).
    for i in ids {
        if let Node::Pow(b, e) = &nodes[i.index()]
            && !value[i.index()].is_finite()
        {
            return Err(non_finite("pow", &[value[b.index()], value[e.index()]]));
        }
    }
    Ok(ids.iter().map(|i| value[i.index()]).collect())
}

/// True for x^y with x finite and not 0 and y < 0 whose value overflowed: the reciprocal
/// of a tiny number (1e-320^-1), left infinite for the product that divides by it
/// ([`quotient`]) to evaluate as a quotient.
fn is_overflowed_reciprocal(x: f64, y: f64, r: f64) -> bool {
    !r.is_finite() && x.is_finite() && x != 0.0 && y < 0.0
}

/// The product `factors` as a quotient: the overflowed reciprocals b^y among them
/// ([`is_overflowed_reciprocal`]) divide by b^-y instead of multiplying by b^y, so that
/// 1e-320/1e-320 (1e-320 * 1e-320^-1) is 1, not inf.
fn quotient(arena: &Arena, factors: &[Id], value: &[f64]) -> f64 {
    let (mut numerator, mut denominator) = (1.0, 1.0);
    for f in factors {
        let v = value[f.index()];
        match arena.nodes().get(f.index()) {
            Some(Node::Pow(b, e))
                if is_overflowed_reciprocal(value[b.index()], value[e.index()], v) =>
            {
                let exponent = arena.as_number(*e).map(|n| -n);
                denominator *= pow_value(value[b.index()], -value[e.index()], exponent);
            }
            _ => numerator *= v,
        }
    }
    numerator / denominator
}

/// The value of one node whose children are already in `value`.
fn node_value(
    arena: &Arena,
    node: &Node,
    value: &[f64],
    env: &dyn Fn(SymbolId) -> Option<f64>,
) -> Result<f64> {
    let v = |i: &Id| value[i.index()];
    let (r, op): (f64, &str) = match node {
        Node::Num(n) => (n.to_f64(), "constant"),
        Node::Pi => (std::f64::consts::PI, "pi"),
        Node::Sym(s) => {
            let name = || {
                arena
                    .symbols()
                    .get(s.0 as usize)
                    .map_or_else(|| format!("#{}", s.0), |x| x.name.clone())
            };
            let x = env(*s).ok_or_else(|| Error::Eval(EvalError::MissingValue { name: name() }))?;
            if !x.is_finite() {
                return Err(Error::Eval(EvalError::NonFinite {
                    operation: name(),
                    arguments: format!("{x}"),
                }));
            }
            return Ok(x);
        }
        Node::Add(ts) => (ts.iter().map(v).sum(), "+"),
        Node::Mul(fs) => {
            let r: f64 = fs.iter().map(v).product();
            if r.is_finite() {
                (r, "*")
            } else {
                (quotient(arena, fs, value), "*")
            }
        }
        Node::Pow(b, e) => {
            let exponent = arena.as_number(*e);
            let (x, y) = (v(b), v(e));
            let r = pow_value(x, y, exponent);
            if is_overflowed_reciprocal(x, y, r) {
                // Left to the product that divides by it, or refused at the end.
                return Ok(r);
            }
            if !r.is_finite() {
                let op = if x == 0.0 && y < 0.0 {
                    "division by zero"
                } else {
                    "pow"
                };
                return Err(non_finite(op, &[x, y]));
            }
            return Ok(r);
        }
        Node::Func(f, a) => (apply(*f, v(a)), f.name()),
        Node::Atan2(y, x) => (v(y).atan2(v(x)), "atan2"),
        // The child's value, checked when it was evaluated.
        Node::Named(a) => return Ok(v(a)),
    };
    if r.is_finite() {
        Ok(r)
    } else {
        let args: Vec<f64> = match node {
            Node::Add(xs) | Node::Mul(xs) => xs.iter().map(v).collect(),
            Node::Func(_, a) => vec![v(a)],
            Node::Atan2(a, b) => vec![v(a), v(b)],
            _ => vec![],
        };
        Err(non_finite(op, &args))
    }
}

/// f(x), with sin and cos from `mechanism_math::sin_cos` as in the tape and the emitted code.
fn apply(f: Func, x: f64) -> f64 {
    match f {
        Func::Sin => sin_cos(x).0,
        Func::Cos => sin_cos(x).1,
        _ => f.apply(x),
    }
}

/// x^y, with the exponent's exact constant (if any) choosing the cheapest accurate form.
pub(crate) fn pow_value(x: f64, y: f64, exponent: Option<Number>) -> f64 {
    match exponent {
        Some(Number::Rational(k, 1)) if i32::try_from(k).is_ok() => x.powi(k as i32),
        Some(Number::Rational(1, 2)) => x.sqrt(),
        Some(Number::Rational(-1, 2)) => 1.0 / x.sqrt(),
        _ => x.powf(y),
    }
}

fn non_finite(operation: &str, args: &[f64]) -> Error {
    let arguments = args
        .iter()
        .map(|a| format!("{a:?}"))
        .collect::<Vec<_>>()
        .join(", ");
    Error::Eval(EvalError::NonFinite {
        operation: operation.to_string(),
        arguments: format!("({arguments})"),
    })
}
