//! Evaluation of vector expressions into symbolic [`Matrix`] values (a scalar is 1x1):
//! names of points, axes and bodies resolve through [`VectorNames`], the rest through the
//! arena's symbol table; `*` is the matrix product (a 1x1 factor scales), `rot_x`, `rot_y`,
//! `rot_z` are the elementary rotations, `dot(u, v) = u^T v`, `cross(u, v) = u x v`,
//! `norm(u) = sqrt(u^T u)`.

use crate::algebra::expr::{Arena, Func, Id};
use crate::algebra::matrix::Matrix;
use crate::algebra::rotation::{Axis, elementary_rotation};
use crate::error::{DeclarationError, Error, Location, Quantity, Result};
use crate::mechanics::joints::cross;
use crate::mechanics::resolve::{ArenaResolver, Resolver, arena_names, unknown_symbol};
use crate::syntax::ast::Ast;
use crate::syntax::expression::HELPERS;

/// A binary operation on matrix values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
}

/// How names of points, axes and bodies resolve while evaluating a vector expression.
pub(crate) trait VectorNames {
    /// The world vector called `name`, if there is one.
    fn vector(&self, name: &str) -> Option<[Id; 3]>;
    /// The names of the world vectors, in declaration order (for unknown-name errors).
    fn names(&self) -> Vec<&str>;
}

/// The 1x1 value's entry, or an error naming `what`.
pub(crate) fn scalar(m: &Matrix, what: Quantity, at: Location) -> Result<Id> {
    if (m.rows, m.cols) == (1, 1) {
        Ok(m.data[0])
    } else {
        let (rows, cols) = (m.rows, m.cols);
        let kind = DeclarationError::NotScalar { what, rows, cols };
        Err(Error::declaration(kind, at))
    }
}

/// The 3x1 value's entries, or an error naming `what`.
pub(crate) fn vec3(m: &Matrix, what: Quantity, at: Location) -> Result<[Id; 3]> {
    if (m.rows, m.cols) == (3, 1) {
        Ok([m.data[0], m.data[1], m.data[2]])
    } else {
        let (rows, cols) = (m.rows, m.cols);
        let kind = DeclarationError::NotVector3 { what, rows, cols };
        Err(Error::declaration(kind, at))
    }
}

fn one(id: Id) -> Matrix {
    Matrix::column(vec![id])
}

/// Lowers `ast` into `arena` as a matrix value.
pub(crate) fn vector_value(
    arena: &mut Arena,
    ast: &Ast,
    names: &dyn VectorNames,
) -> Result<Matrix> {
    match ast {
        Ast::Number(n, _) => Ok(one(arena.number(*n))),
        Ast::Name(n, _) if n == "pi" => Ok(one(arena.pi())),
        Ast::Name(n, at) => match names.vector(n) {
            Some(v) => Ok(Matrix::column(v.to_vec())),
            None => match ArenaResolver.name(arena, n, *at) {
                Ok(id) => Ok(one(id)),
                // Points, axes and bodies are names here too.
                Err(Error::Declaration { kind, .. })
                    if matches!(*kind, DeclarationError::UnknownSymbol { .. }) =>
                {
                    let mut known = names.names();
                    known.extend(arena_names(arena));
                    Err(unknown_symbol(n, *at, &known))
                }
                Err(e) => Err(e),
            },
        },
        Ast::Neg(a, _) => {
            let v = vector_value(arena, a, names)?;
            let m1 = arena.int(-1);
            v.scale(arena, m1)
        }
        Ast::Member(a, k, at) => {
            let v = vector_value(arena, a, names)?;
            let v = vec3(&v, Quantity::MemberBase, *at)?;
            Ok(one(v[*k]))
        }
        Ast::Brackets(items, at) => {
            let mut rows = Vec::new();
            for it in items {
                rows.push(vector_value(arena, it, names)?);
            }
            if items.iter().all(|i| matches!(i, Ast::Brackets(..))) && items.len() > 1 {
                let cols = rows[0].rows;
                let mut data = Vec::new();
                for r in &rows {
                    if r.cols != 1 || r.rows != cols {
                        return Err(Error::declaration(DeclarationError::RaggedMatrix, *at));
                    }
                    data.extend(&r.data);
                }
                return Ok(Matrix {
                    rows: rows.len(),
                    cols,
                    data,
                });
            }
            let mut data = Vec::new();
            for (r, it) in rows.iter().zip(items) {
                data.push(scalar(r, Quantity::VectorEntry, it.location())?);
            }
            Ok(Matrix::column(data))
        }
        Ast::Sum(terms) => fold(arena, terms, [Op::Add, Op::Sub], names),
        Ast::Product(factors) => fold(arena, factors, [Op::Mul, Op::Div], names),
        Ast::Pow(a, b, at) => {
            let (x, y) = (
                vector_value(arena, a, names)?,
                vector_value(arena, b, names)?,
            );
            binary(arena, Op::Pow, &x, &y, *at)
        }
        Ast::Call(f, args, at) => call(arena, f, args, *at, names),
    }
}

/// A left-associative chain `a op b op c ..`, evaluated left to right (`ops[1]` for an
/// operand flagged inverse, `ops[0]` otherwise).
fn fold(
    arena: &mut Arena,
    items: &[(bool, Ast, Location)],
    ops: [Op; 2],
    names: &dyn VectorNames,
) -> Result<Matrix> {
    let Some(((_, first, _), rest)) = items.split_first() else {
        // The parser never builds an empty chain; its value would be the identity.
        return Ok(one(arena.int(i64::from(ops[0] == Op::Mul))));
    };
    let mut acc = vector_value(arena, first, names)?;
    for (inverse, item, at) in rest {
        let y = vector_value(arena, item, names)?;
        acc = binary(arena, ops[usize::from(*inverse)], &acc, &y, *at)?;
    }
    Ok(acc)
}

fn binary(arena: &mut Arena, op: Op, x: &Matrix, y: &Matrix, at: Location) -> Result<Matrix> {
    let (left, right) = ((x.rows, x.cols), (y.rows, y.cols));
    match op {
        Op::Add | Op::Sub => {
            if left != right {
                let kind = DeclarationError::SumShapes { left, right };
                return Err(Error::declaration(kind, at));
            }
            if op == Op::Add {
                x.add(arena, y)
            } else {
                x.sub(arena, y)
            }
        }
        Op::Mul => {
            if (x.rows, x.cols) == (1, 1) {
                y.scale(arena, x.data[0])
            } else if (y.rows, y.cols) == (1, 1) {
                x.scale(arena, y.data[0])
            } else if x.cols == y.rows {
                x.mul(arena, y)
            } else {
                let kind = DeclarationError::ProductShapes { left, right };
                Err(Error::declaration(kind, at))
            }
        }
        Op::Div => {
            let d = scalar(y, Quantity::Divisor, at)?;
            let inv = arena.powi(d, -1).map_err(|_| {
                Error::declaration(
                    DeclarationError::ZeroDivisor {
                        divisor: "0".into(),
                    },
                    at,
                )
            })?;
            x.scale(arena, inv)
        }
        Op::Pow => {
            let b = scalar(x, Quantity::PowerBase, at)?;
            let e = scalar(y, Quantity::Exponent, at)?;
            Ok(one(arena.pow(b, e).map_err(|_| {
                Error::declaration(
                    DeclarationError::ZeroDivisor {
                        divisor: "0".into(),
                    },
                    at,
                )
            })?))
        }
    }
}

// One function: one match arm per built-in function, each its formula.
fn call(
    arena: &mut Arena,
    f: &str,
    args: &[Ast],
    at: Location,
    names: &dyn VectorNames,
) -> Result<Matrix> {
    if HELPERS.contains(&f) {
        let kind = DeclarationError::JointInExpression {
            helper: f.to_string(),
        };
        return Err(Error::declaration(kind, at));
    }
    let mut v = Vec::with_capacity(args.len());
    for a in args {
        v.push(vector_value(arena, a, names)?);
    }
    let s = |i: usize, arena: &mut Arena| -> Result<Id> {
        let _ = arena;
        scalar(&v[i], Quantity::Argument(f.to_string()), args[i].location())
    };
    let w = |i: usize| vec3(&v[i], Quantity::Argument(f.to_string()), args[i].location());
    let domain = |e: Error| {
        let kind = DeclarationError::FunctionOutOfDomain {
            function: f.to_string(),
            error: Box::new(e),
        };
        Error::declaration(kind, at)
    };
    Ok(match f {
        "rot_x" | "rot_y" | "rot_z" => {
            let axis = match f {
                "rot_x" => Axis::X,
                "rot_y" => Axis::Y,
                _ => Axis::Z,
            };
            let a = s(0, arena)?;
            elementary_rotation(arena, axis, a)
        }
        "diag" => {
            let (a, b, c) = (s(0, arena)?, s(1, arena)?, s(2, arena)?);
            let z = arena.int(0);
            Matrix {
                rows: 3,
                cols: 3,
                data: vec![a, z, z, z, b, z, z, z, c],
            }
        }
        "dot" => {
            let (p, q) = (w(0)?, w(1)?);
            one(crate::mechanics::bodies::dot(arena, &p, &q))
        }
        "cross" => {
            let (p, q) = (w(0)?, w(1)?);
            Matrix::column(cross(arena, &p, &q).to_vec())
        }
        "norm" => {
            let p = w(0)?;
            let dd = crate::mechanics::bodies::dot(arena, &p, &p);
            one(arena.sqrt(dd).map_err(domain)?)
        }
        "sqrt" => {
            let x = s(0, arena)?;
            one(arena.sqrt(x).map_err(domain)?)
        }
        "atan2" => {
            let (y, x) = (s(0, arena)?, s(1, arena)?);
            one(arena.atan2(y, x))
        }
        "pow" => {
            let (b, e) = (s(0, arena)?, s(1, arena)?);
            one(arena.pow(b, e).map_err(domain)?)
        }
        _ => {
            let x = s(0, arena)?;
            let func = Func::from_name(f).ok_or_else(|| {
                Error::declaration(
                    DeclarationError::UnknownFunction {
                        name: f.to_string(),
                    },
                    at,
                )
            })?;
            one(arena.func(func, x).map_err(domain)?)
        }
    })
}
