//! Vector and matrix expressions of the body sections (`position = [x, y, z];`,
//! `orientation = rot_z(phi) * rot_x(a);`, `B = C;`, `B.z = 0;`): their syntax tree,
//! and parser (evaluated into symbolic matrices by `mechanics::vectors`).
//!
//! ```text
//! vexpr   := product (("+" | "-") product)*
//! product := unary (("*" | "/") unary)*          matrix product; a 1x1 factor scales
//! unary   := ("-" | "+") unary | power
//! power   := postfix ["^" unary]                 scalars only
//! postfix := atom ("." ("x" | "y" | "z"))*       a component of a 3-vector
//! atom    := NUMBER | NAME | NAME "(" vexpr ("," vexpr)* ")" | "(" vexpr ")"
//!          | "[" vexpr ("," vexpr)* "]"          a column; "[[..], [..], ..]" a matrix by rows
//! ```
//! Names are points, axes and bodies (3-vectors: the point, the axis direction, the centre of
//! mass; world components), then parameters, coordinates, `t` and `pi`. Functions: the
//! scalar ones of the expression language (sin, cos, tan, exp, ln, sqrt, abs, atan2, pow),
//! `rot_x`, `rot_y`, `rot_z` (3x3), `diag(a, b, c)` (3x3), `dot(u, v)`, `cross(u, v)`,
//! `norm(u)`.

use crate::error::{Error, Location, Result};
use crate::number::Number;
use crate::syntax::MAX_DEPTH;
use crate::syntax::expression::FUNCTIONS;
use crate::syntax::lex::{Cursor, Delim, Tok};

/// Functions that only vector expressions have, with their arities; the scalar ones come
/// from the expression parser's table (`der` is refused before the lookup).
const VECTOR_FUNCTIONS: &[(&str, usize)] = &[
    ("rot_x", 1),
    ("rot_y", 1),
    ("rot_z", 1),
    ("diag", 3),
    ("dot", 2),
    ("cross", 2),
    ("norm", 1),
    ("spherical", 2),
    ("revolute", 4),
    ("prismatic", 4),
    ("distance", 3),
];

/// Joint helpers: parsed as calls, valid only as statements of `joints`.
pub(crate) const HELPERS: &[&str] = &["spherical", "revolute", "prismatic", "distance"];

/// A binary operator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Op {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
}

/// A vector expression as written.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum VectorAst {
    Number(Number, Location),
    Name(String, Location),
    Neg(Box<VectorAst>, Location),
    Binary(Op, Box<VectorAst>, Box<VectorAst>, Location),
    Call(String, Vec<VectorAst>, Location),
    Member(Box<VectorAst>, usize, Location),
    Brackets(Vec<VectorAst>, Location),
}

impl VectorAst {
    /// Where the expression starts.
    pub(crate) fn location(&self) -> Location {
        match self {
            VectorAst::Number(_, l)
            | VectorAst::Name(_, l)
            | VectorAst::Neg(_, l)
            | VectorAst::Call(_, _, l)
            | VectorAst::Brackets(_, l) => *l,
            VectorAst::Binary(_, a, _, _) | VectorAst::Member(a, _, _) => a.location(),
        }
    }

    /// The expression as text, with the parentheses its precedence needs (`B1`,
    /// `P.z`, `l2/2`, `rot_z(beta)*[0, 0, 1]`): what names a joint in constraint labels.
    pub(crate) fn text(&self) -> String {
        self.text_in(0)
    }

    /// The text inside a context of binding strength `outer` (0 none, 1 sum, 2 product,
    /// 3 unary, 4 power, 5 postfix), parenthesised when `self` binds more loosely.
    fn text_in(&self, outer: u8) -> String {
        let (strength, s) = match self {
            VectorAst::Number(n, _) => (5, n.to_string()),
            VectorAst::Name(n, _) => (5, n.clone()),
            VectorAst::Neg(a, _) => (3, format!("-{}", a.text_in(3))),
            VectorAst::Binary(op, a, b, _) => match op {
                Op::Add | Op::Sub => {
                    let sign = if *op == Op::Add { '+' } else { '-' };
                    (1, format!("{} {sign} {}", a.text_in(1), b.text_in(2)))
                }
                Op::Mul | Op::Div => {
                    let sign = if *op == Op::Mul { '*' } else { '/' };
                    (2, format!("{}{sign}{}", a.text_in(2), b.text_in(3)))
                }
                Op::Pow => (4, format!("{}^{}", a.text_in(5), b.text_in(3))),
            },
            VectorAst::Call(f, args, _) => {
                let a: Vec<String> = args.iter().map(VectorAst::text).collect();
                (5, format!("{f}({})", a.join(", ")))
            }
            VectorAst::Member(a, k, _) => (5, format!("{}.{}", a.text_in(5), ["x", "y", "z"][*k])),
            VectorAst::Brackets(items, _) => {
                let a: Vec<String> = items.iter().map(VectorAst::text).collect();
                (5, format!("[{}]", a.join(", ")))
            }
        };
        if strength < outer {
            format!("({s})")
        } else {
            s
        }
    }

    /// (rows, cols) of the value, knowing which names are 3-vectors; `None` when the shapes
    /// do not fit (evaluation reports it).
    pub(crate) fn shape(&self, is_vector: &dyn Fn(&str) -> bool) -> Option<(usize, usize)> {
        Some(match self {
            VectorAst::Number(..) => (1, 1),
            VectorAst::Name(n, _) => {
                if is_vector(n) {
                    (3, 1)
                } else {
                    (1, 1)
                }
            }
            VectorAst::Neg(a, _) => a.shape(is_vector)?,
            VectorAst::Binary(op, a, b, _) => {
                let (sa, sb) = (a.shape(is_vector)?, b.shape(is_vector)?);
                match op {
                    Op::Add | Op::Sub => sa,
                    Op::Div | Op::Pow => sa,
                    Op::Mul if sa == (1, 1) => sb,
                    Op::Mul if sb == (1, 1) => sa,
                    Op::Mul => (sa.0, sb.1),
                }
            }
            VectorAst::Call(f, _, _) => match f.as_str() {
                "rot_x" | "rot_y" | "rot_z" | "diag" => (3, 3),
                "cross" => (3, 1),
                _ => (1, 1),
            },
            VectorAst::Member(..) => (1, 1),
            VectorAst::Brackets(items, _) => match items.first() {
                Some(VectorAst::Brackets(row, _)) => (items.len(), row.len()),
                _ => (items.len(), 1),
            },
        })
    }
}

/// The recursive-descent parser of vector expressions.
pub(crate) struct VectorParser<'c, 'a> {
    c: &'c mut Cursor<'a>,
    depth: usize,
}

impl<'c, 'a> VectorParser<'c, 'a> {
    /// Parses one vector expression at the cursor (stopping before `;`, `,`, `=`, `:` or a
    /// closing bracket).
    pub(crate) fn parse(c: &'c mut Cursor<'a>) -> Result<VectorAst> {
        VectorParser { c, depth: 0 }.sum()
    }

    fn enter(&mut self) -> Result<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.c.error_here("the expression is nested too deeply"));
        }
        Ok(())
    }

    fn sum(&mut self) -> Result<VectorAst> {
        self.enter()?;
        let mut acc = self.product()?;
        loop {
            let op = if self.c.at_punct('+') {
                Op::Add
            } else if self.c.at_punct('-') {
                Op::Sub
            } else {
                break;
            };
            let at = self.c.next().location;
            let rhs = self.product()?;
            acc = VectorAst::Binary(op, Box::new(acc), Box::new(rhs), at);
        }
        self.depth -= 1;
        Ok(acc)
    }

    fn product(&mut self) -> Result<VectorAst> {
        let mut acc = self.unary()?;
        loop {
            let op = if self.c.at_punct('*') {
                Op::Mul
            } else if self.c.at_punct('/') {
                Op::Div
            } else {
                break;
            };
            let at = self.c.next().location;
            let rhs = self.unary()?;
            acc = VectorAst::Binary(op, Box::new(acc), Box::new(rhs), at);
        }
        Ok(acc)
    }

    fn unary(&mut self) -> Result<VectorAst> {
        self.enter()?;
        let out = if self.c.at_punct('-') {
            let at = self.c.next().location;
            VectorAst::Neg(Box::new(self.unary()?), at)
        } else if self.c.at_punct('+') {
            self.c.next();
            self.unary()?
        } else {
            let base = self.postfix()?;
            if self.c.at_punct('^') {
                let at = self.c.next().location;
                let e = self.unary()?;
                VectorAst::Binary(Op::Pow, Box::new(base), Box::new(e), at)
            } else {
                base
            }
        };
        self.depth -= 1;
        Ok(out)
    }

    fn postfix(&mut self) -> Result<VectorAst> {
        let mut a = self.atom()?;
        while self.c.at_punct('.') {
            let at = self.c.next().location;
            let t = self.c.peek();
            let k = match &t.tok {
                Tok::Ident(s) if s == "x" => 0,
                Tok::Ident(s) if s == "y" => 1,
                Tok::Ident(s) if s == "z" => 2,
                _ => return Err(self.c.error_here("expected `x`, `y` or `z` after `.`")),
            };
            self.c.next();
            a = VectorAst::Member(Box::new(a), k, at);
        }
        Ok(a)
    }

    fn list(&mut self, close: Delim, what: &str) -> Result<Vec<VectorAst>> {
        let mut out = Vec::new();
        if !self.c.at(&Tok::Close(close)) {
            loop {
                out.push(self.sum()?);
                if !self.c.eat(&Tok::Punct(',')) {
                    break;
                }
            }
        }
        self.c.expect(&Tok::Close(close), what)?;
        Ok(out)
    }

    fn atom(&mut self) -> Result<VectorAst> {
        let t = self.c.peek();
        match &t.tok {
            Tok::Literal(s) => {
                let n = number(s).ok_or_else(|| Error::Parse {
                    message: format!(
                        "`{s}` is not a number of the language (write e.g. 2, 0.04 or 1e-4)"
                    ),
                    location: t.location,
                })?;
                self.c.next();
                Ok(VectorAst::Number(n, t.location))
            }
            Tok::Ident(name) => {
                self.c.next();
                if !self.c.at(&Tok::Open(Delim::Paren)) {
                    return Ok(VectorAst::Name(name.clone(), t.location));
                }
                if name == "der" || name == "der2" {
                    return Err(Error::Declaration {
                        message: format!(
                            "`{name}(..)` cannot appear in a body, point, spring or joint: they are position-level (functions of q and t)"
                        ),
                        location: t.location,
                    });
                }
                self.c.next();
                let args = self.list(Delim::Paren, "`,` or `)` after a function argument")?;
                match FUNCTIONS
                    .iter()
                    .chain(VECTOR_FUNCTIONS)
                    .find(|f| f.0 == name)
                {
                    None => Err(Error::UnknownFunction {
                        name: name.clone(),
                        location: t.location,
                    }),
                    Some(&(_, arity)) if arity != args.len() => Err(Error::Parse {
                        message: format!(
                            "`{name}` takes {arity} argument(s), found {}",
                            args.len()
                        ),
                        location: t.location,
                    }),
                    Some(_) => Ok(VectorAst::Call(name.clone(), args, t.location)),
                }
            }
            Tok::Open(Delim::Paren) => {
                self.c.next();
                let inner = self.sum()?;
                self.c
                    .expect(&Tok::Close(Delim::Paren), "`)` or an operator")?;
                Ok(inner)
            }
            Tok::Open(Delim::Bracket) => {
                self.c.next();
                let items = self.list(Delim::Bracket, "`,` or `]` in a vector")?;
                if items.is_empty() {
                    return Err(Error::Parse {
                        message: "a vector needs at least one entry".into(),
                        location: t.location,
                    });
                }
                Ok(VectorAst::Brackets(items, t.location))
            }
            _ => Err(self.c.error_here("expected a number, a name, `(` or `[`")),
        }
    }
}

/// A numeric literal: decimal integers are exact, decimals and exponent forms are floats.
fn number(text: &str) -> Option<Number> {
    let clean: String = text.chars().filter(|&c| c != '_').collect();
    if clean.is_empty() || !clean.starts_with(|c: char| c.is_ascii_digit()) {
        return None;
    }
    if clean.chars().all(|c| c.is_ascii_digit()) {
        return clean
            .parse::<i64>()
            .ok()
            .map(Number::int)
            .or_else(|| clean.parse::<f64>().ok().and_then(Number::float));
    }
    if !clean
        .chars()
        .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-'))
    {
        return None;
    }
    clean.parse::<f64>().ok().and_then(Number::float)
}
