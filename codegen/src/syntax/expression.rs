//! The expression language: a syntax tree, its recursive-descent parser over the flat token
//! list of [`crate::syntax::lex`] (turned into arena nodes by `mechanics::resolve`).
//!
//! Precedence, loosest first:
//!
//! | level | operators | associativity |
//! |-------|-----------|---------------|
//! | sum | `a + b`, `a - b` | left |
//! | product | `a * b`, `a / b` | left |
//! | unary | `-a`, `+a` | prefix |
//! | power | `a ^ b` | right; tighter than unary minus: `-x^2 = -(x^2)`; `x^-1` allowed |
//! | atom | numbers, names, `pi`, `t`, calls `f(..)`, `( .. )` | |
//!
//! Integers are exact rationals (`1/2` stays exact); decimals and exponent forms (`0.04`,
//! `1e-4`) are floats. A chain of sums or products is built with one n-ary constructor call,
//! so the result is the arena's canonical form of the whole chain.

use crate::error::{Error, Location, Result};
use crate::number::Number;
use crate::syntax::MAX_DEPTH;
use crate::syntax::lex::{Cursor, Delim, Tok};

/// Functions of the language and their arities, for calls and error messages.
pub(crate) const FUNCTIONS: &[(&str, usize)] = &[
    ("sin", 1),
    ("cos", 1),
    ("tan", 1),
    ("exp", 1),
    ("ln", 1),
    ("sqrt", 1),
    ("abs", 1),
    ("atan2", 2),
    ("pow", 2),
    ("der", 1),
    ("der2", 1),
];

/// A syntax tree node of an expression, with the location of its first token.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Ast {
    /// A numeric literal.
    Number(Number, Location),
    /// A name: a symbol, `t` or `pi`.
    Name(String, Location),
    /// `-a`.
    Neg(Box<Ast>, Location),
    /// `a ± b ± ...`; the flag is true for a subtracted term (never for the first).
    Sum(Vec<(bool, Ast)>),
    /// `a * b / c ...`; the flag is true for a divisor; the location is its operator's.
    Product(Vec<(bool, Ast, Location)>),
    /// `a ^ b`, with the location of `^`.
    Pow(Box<Ast>, Box<Ast>, Location),
    /// `f(a, ..)`, with the location of the name.
    Call(String, Vec<Ast>, Location),
}

impl Ast {
    /// Where the expression starts.
    pub(crate) fn location(&self) -> Location {
        match self {
            Ast::Number(_, l) | Ast::Name(_, l) | Ast::Neg(_, l) | Ast::Call(_, _, l) => *l,
            Ast::Sum(ts) => ts.first().map(|t| t.1.location()).unwrap_or_default(),
            Ast::Product(fs) => fs.first().map(|f| f.1.location()).unwrap_or_default(),
            Ast::Pow(b, _, _) => b.location(),
        }
    }

    /// The expression as text, for error messages (fully parenthesised where in doubt).
    pub(crate) fn text(&self) -> String {
        match self {
            Ast::Number(n, _) => n.to_string(),
            Ast::Name(s, _) => s.clone(),
            Ast::Neg(x, _) => format!("-{}", x.text_atom()),
            Ast::Sum(ts) => {
                let mut s = String::new();
                for (i, (minus, t)) in ts.iter().enumerate() {
                    if i > 0 {
                        s.push_str(if *minus { " - " } else { " + " });
                    }
                    s.push_str(&t.text());
                }
                s
            }
            Ast::Product(fs) => {
                let mut s = String::new();
                for (i, (div, f, _)) in fs.iter().enumerate() {
                    if i > 0 {
                        s.push(if *div { '/' } else { '*' });
                    }
                    s.push_str(&f.text_atom());
                }
                s
            }
            Ast::Pow(b, e, _) => format!("{}^{}", b.text_atom(), e.text_atom()),
            Ast::Call(f, args, _) => {
                let a: Vec<String> = args.iter().map(Ast::text).collect();
                format!("{f}({})", a.join(", "))
            }
        }
    }

    fn text_atom(&self) -> String {
        match self {
            Ast::Sum(_) | Ast::Product(_) | Ast::Neg(..) | Ast::Pow(..) => {
                format!("({})", self.text())
            }
            _ => self.text(),
        }
    }
}

/// The recursive-descent expression parser.
pub(crate) struct ExprParser<'c, 'a> {
    cursor: &'c mut Cursor<'a>,
    depth: usize,
}

impl<'c, 'a> ExprParser<'c, 'a> {
    /// Parses one expression at the cursor (stopping before `;`, `,`, `=`, `:` or a closing
    /// bracket, which the caller handles).
    pub(crate) fn parse(cursor: &'c mut Cursor<'a>) -> Result<Ast> {
        let mut p = ExprParser { cursor, depth: 0 };
        p.sum()
    }

    fn enter(&mut self) -> Result<()> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self
                .cursor
                .error_here("the expression is nested too deeply"));
        }
        Ok(())
    }

    fn sum(&mut self) -> Result<Ast> {
        let mut terms = vec![(false, self.product()?)];
        loop {
            let minus = if self.cursor.at_punct('+') {
                false
            } else if self.cursor.at_punct('-') {
                true
            } else {
                break;
            };
            self.cursor.next();
            terms.push((minus, self.product()?));
        }
        Ok(if terms.len() == 1 {
            terms.swap_remove(0).1
        } else {
            Ast::Sum(terms)
        })
    }

    fn product(&mut self) -> Result<Ast> {
        let first = self.unary()?;
        let at = first.location();
        let mut factors = vec![(false, first, at)];
        loop {
            let div = if self.cursor.at_punct('*') {
                false
            } else if self.cursor.at_punct('/') {
                true
            } else {
                break;
            };
            let op = self.cursor.next().location;
            if !div && self.cursor.at_punct('*') {
                return Err(self
                    .cursor
                    .error_here("powers are written `x^2` (not `x**2`)"));
            }
            factors.push((div, self.unary()?, op));
        }
        Ok(if factors.len() == 1 {
            factors.swap_remove(0).1
        } else {
            Ast::Product(factors)
        })
    }

    fn unary(&mut self) -> Result<Ast> {
        self.enter()?;
        let out = if self.cursor.at_punct('-') {
            let at = self.cursor.next().location;
            Ast::Neg(Box::new(self.unary()?), at)
        } else if self.cursor.at_punct('+') {
            self.cursor.next();
            self.unary()?
        } else {
            self.power()?
        };
        self.depth -= 1;
        Ok(out)
    }

    fn power(&mut self) -> Result<Ast> {
        let base = self.atom()?;
        if !self.cursor.at_punct('^') {
            return Ok(base);
        }
        let at = self.cursor.next().location;
        let exp = self.exponent()?;
        Ok(Ast::Pow(Box::new(base), Box::new(exp), at))
    }

    /// The right side of `^`: `-e`, `+e` or another power (right-associative).
    fn exponent(&mut self) -> Result<Ast> {
        self.enter()?;
        let out = if self.cursor.at_punct('-') {
            let at = self.cursor.next().location;
            Ast::Neg(Box::new(self.exponent()?), at)
        } else if self.cursor.at_punct('+') {
            self.cursor.next();
            self.exponent()?
        } else {
            self.power()?
        };
        self.depth -= 1;
        Ok(out)
    }

    fn atom(&mut self) -> Result<Ast> {
        let t = self.cursor.peek();
        match &t.tok {
            Tok::Literal(s) => {
                let n = parse_number(s).map_err(|m| Error::Parse {
                    message: m,
                    location: t.location,
                })?;
                self.cursor.next();
                Ok(Ast::Number(n, t.location))
            }
            Tok::Ident(name) => {
                self.cursor.next();
                if self.cursor.at(&Tok::Open(Delim::Paren)) {
                    self.call(name.clone(), t.location)
                } else {
                    Ok(Ast::Name(name.clone(), t.location))
                }
            }
            Tok::Open(Delim::Paren) => {
                self.enter()?;
                self.cursor.next();
                let inner = self.sum()?;
                self.cursor
                    .expect(&Tok::Close(Delim::Paren), "`)` or an operator")?;
                self.depth -= 1;
                Ok(inner)
            }
            Tok::Punct('^') => Err(self.cursor.error_here("`^` needs a base on its left")),
            _ => Err(self.cursor.error_here("expected a number, a name or `(`")),
        }
    }

    fn call(&mut self, name: String, at: Location) -> Result<Ast> {
        self.enter()?;
        self.cursor.next(); // `(`
        let mut args = Vec::new();
        if !self.cursor.at(&Tok::Close(Delim::Paren)) {
            loop {
                args.push(self.sum()?);
                if !self.cursor.eat(&Tok::Punct(',')) {
                    break;
                }
            }
        }
        self.cursor.expect(
            &Tok::Close(Delim::Paren),
            "`,` or `)` after a function argument",
        )?;
        self.depth -= 1;
        match FUNCTIONS.iter().find(|f| f.0 == name) {
            None => Err(Error::UnknownFunction { name, location: at }),
            Some(&(_, arity)) if arity != args.len() => Err(Error::Parse {
                message: format!(
                    "`{name}` takes {arity} argument{}, found {}",
                    if arity == 1 { "" } else { "s" },
                    args.len()
                ),
                location: at,
            }),
            Some(_) => Ok(Ast::Call(name, args, at)),
        }
    }
}

/// A numeric literal: decimal integers are exact, decimals and exponent forms are floats.
fn parse_number(text: &str) -> std::result::Result<Number, String> {
    // A negative literal only arises from tokens built by code, never from the lexer.
    if let Some(rest) = text.strip_prefix('-') {
        return parse_number(rest).map(|n| -n);
    }
    if text.starts_with(['"', '\'', 'b', 'c', 'r']) {
        return Err(format!("expected a number, found the literal {text}"));
    }
    let clean: String = text.chars().filter(|&c| c != '_').collect();
    let bad = || {
        format!(
            "`{text}` is not a number of the language (write e.g. 2, 0.04 or 1e-4, without a type suffix)"
        )
    };
    if clean.starts_with("0x") || clean.starts_with("0o") || clean.starts_with("0b") {
        return Err(bad());
    }
    if clean.chars().all(|c| c.is_ascii_digit()) {
        return Ok(match clean.parse::<i64>() {
            Ok(n) => Number::int(n),
            Err(_) => clean
                .parse::<f64>()
                .ok()
                .and_then(Number::float)
                .ok_or_else(bad)?,
        });
    }
    let float_chars = clean
        .chars()
        .all(|c| c.is_ascii_digit() || matches!(c, '.' | 'e' | 'E' | '+' | '-'));
    if !float_chars {
        return Err(bad());
    }
    let x: f64 = clean.parse().map_err(|_| bad())?;
    Number::float(x).ok_or_else(|| format!("`{text}` is too large for a 64-bit float"))
}

/// The candidate closest to `name` by edit distance, when it is a likely typo: at most 2
/// edits, and at most half the longer name (so `x` does not suggest `y`). A candidate equal
/// up to letter case wins.
pub(crate) fn closest<'n>(
    name: &str,
    candidates: impl IntoIterator<Item = &'n str>,
) -> Option<String> {
    let mut best: Option<(usize, &str)> = None;
    for c in candidates {
        if c == name {
            continue;
        }
        let d = if c.eq_ignore_ascii_case(name) {
            0
        } else {
            edit_distance(name, c)
        };
        let longer = name.chars().count().max(c.chars().count());
        if d <= 2 && d <= longer / 2 && best.is_none_or(|b| d < b.0) {
            best = Some((d, c));
        }
    }
    best.map(|b| b.1.to_string())
}

/// Levenshtein distance in characters.
pub(crate) fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.iter().enumerate() {
        let mut cur = vec![i + 1; b.len() + 1];
        for (j, cb) in b.iter().enumerate() {
            cur[j + 1] = (prev[j] + usize::from(ca != cb))
                .min(prev[j + 1] + 1)
                .min(cur[j] + 1);
        }
        prev = cur;
    }
    prev[b.len()]
}
