//! The syntax tree of an expression, scalar or vector, as written (built by
//! [`crate::syntax::expression`]; resolved into arena nodes by `mechanics::resolve` and
//! evaluated into matrices by `mechanics::vectors`).
//!
//! One tree serves both languages: a scalar expression never contains the vector-only
//! nodes ([`Ast::Member`], [`Ast::Brackets`]) nor the vector functions, because the parser
//! of the scalar language refuses them.

use crate::error::Location;
use crate::number::Number;

/// A syntax tree node, with the location of its first token (or of its operator, where the
/// variant says so).
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Ast {
    /// A numeric literal.
    Number(Number, Location),
    /// A name: a symbol, `t`, `pi`, or (vector language) a point, axis or body.
    Name(String, Location),
    /// `-a`.
    Neg(Box<Ast>, Location),
    /// `a ± b ± ...`: each term with a flag, true for a subtracted term (never the first),
    /// and the location of its operator (the first term's own location).
    Sum(Vec<(bool, Ast, Location)>),
    /// `a * b / c ...`: each factor with a flag, true for a divisor, and the location of
    /// its operator (the first factor's own location).
    Product(Vec<(bool, Ast, Location)>),
    /// `a ^ b`, with the location of `^`.
    Pow(Box<Ast>, Box<Ast>, Location),
    /// `f(a, ..)`, with the location of the name.
    Call(String, Vec<Ast>, Location),
    /// `a.x`, `a.y`, `a.z` (component 0, 1, 2 of a 3-vector), with the location of `.`.
    Member(Box<Ast>, usize, Location),
    /// `[a, b, ..]` (a column) or `[[..], [..]]` (a matrix by rows), with the location of `[`.
    Brackets(Vec<Ast>, Location),
}

/// Binding strengths of the printed forms, loosest first (see [`Ast::text`]).
const SUM: u8 = 1;
const PRODUCT: u8 = 2;
const UNARY: u8 = 3;
const POWER: u8 = 4;
const ATOM: u8 = 5;

impl Ast {
    /// Where the expression starts.
    pub(crate) fn location(&self) -> Location {
        match self {
            Ast::Number(_, l)
            | Ast::Name(_, l)
            | Ast::Neg(_, l)
            | Ast::Call(_, _, l)
            | Ast::Brackets(_, l) => *l,
            Ast::Sum(items) | Ast::Product(items) => {
                items.first().map(|i| i.1.location()).unwrap_or_default()
            }
            Ast::Pow(a, _, _) | Ast::Member(a, _, _) => a.location(),
        }
    }

    /// The expression as text, with the parentheses its precedence needs (`B1`, `P.z`,
    /// `l2/2`, `rot_z(beta)*[0, 0, 1]`, `-(l - 1)`): what error messages quote and what
    /// names a joint in constraint labels.
    pub(crate) fn text(&self) -> String {
        self.text_in(0)
    }

    /// The text inside a context of binding strength `outer`, parenthesised when `self`
    /// binds more loosely.
    fn text_in(&self, outer: u8) -> String {
        let (strength, s) = match self {
            Ast::Number(n, _) => (ATOM, n.to_string()),
            Ast::Name(n, _) => (ATOM, n.clone()),
            Ast::Neg(a, _) => (UNARY, format!("-{}", a.text_in(UNARY))),
            Ast::Sum(terms) => {
                let sign = |minus| if minus { " - " } else { " + " };
                (SUM, chain_text(terms, SUM, PRODUCT, sign))
            }
            Ast::Product(factors) => {
                let sign = |div| if div { "/" } else { "*" };
                (PRODUCT, chain_text(factors, PRODUCT, UNARY, sign))
            }
            Ast::Pow(a, b, _) => (POWER, format!("{}^{}", a.text_in(ATOM), b.text_in(UNARY))),
            Ast::Call(f, args, _) => (ATOM, format!("{f}({})", list_text(args))),
            Ast::Member(a, k, _) => (ATOM, format!("{}.{}", a.text_in(ATOM), ["x", "y", "z"][*k])),
            Ast::Brackets(items, _) => (ATOM, format!("[{}]", list_text(items))),
        };
        if strength < outer {
            format!("({s})")
        } else {
            s
        }
    }

    /// (rows, cols) of a vector expression's value, knowing which names are 3-vectors;
    /// `None` when the shapes do not fit (evaluation reports it).
    pub(crate) fn shape(&self, is_vector: &dyn Fn(&str) -> bool) -> Option<(usize, usize)> {
        Some(match self {
            Ast::Number(..) | Ast::Member(..) => (1, 1),
            Ast::Name(n, _) => {
                if is_vector(n) {
                    (3, 1)
                } else {
                    (1, 1)
                }
            }
            Ast::Neg(a, _) => a.shape(is_vector)?,
            Ast::Pow(a, b, _) => {
                b.shape(is_vector)?;
                a.shape(is_vector)?
            }
            Ast::Sum(terms) => {
                let mut shape = None;
                for (_, t, _) in terms {
                    let s = t.shape(is_vector)?;
                    shape.get_or_insert(s);
                }
                shape?
            }
            Ast::Product(factors) => {
                let mut acc: Option<(usize, usize)> = None;
                for (div, f, _) in factors {
                    let s = f.shape(is_vector)?;
                    acc = Some(match acc {
                        None => s,
                        Some(a) if *div => a,
                        Some(a) => product_shape(a, s),
                    });
                }
                acc?
            }
            Ast::Call(f, _, _) => match f.as_str() {
                "rot_x" | "rot_y" | "rot_z" | "diag" => (3, 3),
                "cross" => (3, 1),
                _ => (1, 1),
            },
            Ast::Brackets(items, _) => match items.first() {
                Some(Ast::Brackets(row, _)) => (items.len(), row.len()),
                _ => (items.len(), 1),
            },
        })
    }
}

/// The shape of the product of values of shapes `a` and `b` (a 1x1 factor scales).
fn product_shape(a: (usize, usize), b: (usize, usize)) -> (usize, usize) {
    if a == (1, 1) {
        b
    } else if b == (1, 1) {
        a
    } else {
        (a.0, b.1)
    }
}

/// A chain `a op b op c`: the first item inside `first`, the others inside `rest` (so that
/// `a - (b - c)` keeps its parentheses and `(a - b) - c` needs none), each after its
/// operator `op(inverse)`.
fn chain_text(
    items: &[(bool, Ast, Location)],
    first: u8,
    rest: u8,
    op: impl Fn(bool) -> &'static str,
) -> String {
    let mut s = String::new();
    for (k, (inverse, item, _)) in items.iter().enumerate() {
        if k == 0 {
            s.push_str(&item.text_in(first));
        } else {
            s.push_str(op(*inverse));
            s.push_str(&item.text_in(rest));
        }
    }
    s
}

fn list_text(items: &[Ast]) -> String {
    items.iter().map(Ast::text).collect::<Vec<_>>().join(", ")
}
