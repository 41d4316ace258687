//! The one expression parser, for both expression languages: the scalar expressions of
//! energies, constraints, forces and values, and the vector expressions of the body sections
//! (`position = [x, y, z];`, `orientation = rot_z(phi) * rot_x(a);`, `B = C;`, `B.z = 0;`).
//! Both produce an [`Ast`]; the [`Language`] says which forms and functions exist.
//!
//! ```text
//! expr    := product (("+" | "-") product)*
//! product := unary (("*" | "/") unary)*       vectors: the matrix product; a 1x1 factor scales
//! unary   := ("-" | "+") unary | postfix ["^" unary]
//! postfix := atom ("." ("x" | "y" | "z"))*    vector language only: a component of a 3-vector
//! atom    := NUMBER | NAME | NAME "(" [expr ("," expr)*] ")" | "(" expr ")"
//!          | "[" expr ("," expr)* "]"         vector language only: a column; "[[..], ..]" by rows
//! ```
//!
//! It is precedence climbing over the binding powers of [`Infix`] (loosest first: `+ -`,
//! `* /`, unary `-`, `^`, the only table of precedence): `^` is right-associative and
//! tighter than unary minus (`-x^2 = -(x^2)`, `x^-1` allowed); a chain of sums or of
//! products becomes one n-ary node, so that name resolution builds the arena's canonical form
//! of the whole chain with one constructor call. Nesting deeper than [`MAX_DEPTH`] is an
//! error, not a stack overflow.
//!
//! Integers are exact rationals (`1/2` stays exact); decimals and exponent forms (`0.04`,
//! `1e-4`) are floats. Names in the vector language are points, axes and bodies (3-vectors)
//! as well as symbols; its extra functions are `rot_x`, `rot_y`, `rot_z` (3x3),
//! `diag(a, b, c)` (3x3), `dot(u, v)`, `cross(u, v)`, `norm(u)` and the joint helpers.

use crate::error::{DeclarationError, Error, Expected, Location, ParseError, Result};
use crate::number::Number;
use crate::syntax::MAX_DEPTH;
use crate::syntax::ast::Ast;
use crate::syntax::lex::{Cursor, Delim, Tok};

/// Which expression language is parsed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Language {
    /// Scalar expressions: energies, constraint rows, forces, values.
    Scalar,
    /// Vector and matrix expressions of the body sections: `[..]`, `.x`, the vector
    /// functions; no `der` (body quantities are position-level).
    Vector,
}

/// Functions of both languages and their arities, for calls and error messages.
const FUNCTIONS: &[(&str, usize)] = &[
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

/// Functions of the vector language only, with their arities (the joint helpers among them).
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
    ("rolling", 3),
];

/// Joint helpers: parsed as calls, valid only as statements of `joints`.
pub(crate) const HELPERS: &[&str] = &["spherical", "revolute", "prismatic", "distance", "rolling"];

/// The arity of the function `name` in `language`, if it has one.
fn arity(language: Language, name: &str) -> Option<usize> {
    let vector = match language {
        Language::Scalar => &[][..],
        Language::Vector => VECTOR_FUNCTIONS,
    };
    FUNCTIONS
        .iter()
        .chain(vector)
        .find(|f| f.0 == name)
        .map(|f| f.1)
}

/// A binary operator with its binding power (higher binds tighter).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Infix {
    /// `+` or `-` (true: `-`).
    Sum(bool),
    /// `*` or `/` (true: `/`).
    Product(bool),
    /// `^`.
    Pow,
}

/// Binding power of a prefix `-` or `+`: between products and powers.
const PREFIX: u8 = 3;

impl Infix {
    /// The operator at the cursor, if any.
    fn at(c: &Cursor<'_>) -> Option<Infix> {
        match c.peek().tok {
            Tok::Punct('+') => Some(Infix::Sum(false)),
            Tok::Punct('-') => Some(Infix::Sum(true)),
            Tok::Punct('*') => Some(Infix::Product(false)),
            Tok::Punct('/') => Some(Infix::Product(true)),
            Tok::Punct('^') => Some(Infix::Pow),
            _ => None,
        }
    }

    fn power(self) -> u8 {
        match self {
            Infix::Sum(_) => 1,
            Infix::Product(_) => 2,
            Infix::Pow => 4,
        }
    }
}

/// Parses one expression of `language` at the cursor, stopping before a token that cannot
/// continue it (`;`, `,`, `=`, `:`, a closing bracket), which the caller handles.
pub(crate) fn parse(cursor: &mut Cursor<'_>, language: Language) -> Result<Ast> {
    Parser {
        c: cursor,
        language,
        depth: 0,
    }
    .expr(0)
}

struct Parser<'c, 'a> {
    c: &'c mut Cursor<'a>,
    language: Language,
    depth: usize,
}

impl Parser<'_, '_> {
    /// An expression whose operators all bind at least as tightly as `min`.
    fn expr(&mut self, min: u8) -> Result<Ast> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(self.c.error_here(ParseError::TooDeep {
                found: self.c.found(),
            }));
        }
        let mut lhs = self.prefix()?;
        while let Some(op) = Infix::at(self.c) {
            if op.power() < min {
                break;
            }
            lhs = match op {
                // Right-associative: the exponent takes the following `^` too.
                Infix::Pow => {
                    let at = self.c.next().location();
                    let exponent = self.expr(op.power())?;
                    Ast::Pow(Box::new(lhs), Box::new(exponent), at)
                }
                Infix::Sum(_) => Ast::Sum(self.chain(lhs, op)?),
                Infix::Product(_) => Ast::Product(self.chain(lhs, op)?),
            };
        }
        self.depth -= 1;
        Ok(lhs)
    }

    /// `first op b op c ...` for the operators of `op`'s level (left-associative), each
    /// operand with its inverse flag (`-`, `/`) and its operator's location.
    fn chain(&mut self, first: Ast, op: Infix) -> Result<Vec<(bool, Ast, Location)>> {
        let at = first.location();
        let mut items = vec![(false, first, at)];
        while let Some(next) = Infix::at(self.c) {
            let inverse = match (op, next) {
                (Infix::Sum(_), Infix::Sum(minus)) => minus,
                (Infix::Product(_), Infix::Product(div)) => div,
                _ => break,
            };
            let at = self.c.next().location();
            if next == Infix::Product(false) && self.c.at_punct('*') {
                return Err(self.c.error_here(ParseError::DoubleStar));
            }
            items.push((inverse, self.expr(op.power() + 1)?, at));
        }
        // Most chains are short (a product of two factors): the growth's spare capacity
        // would be most of a large declaration's syntax tree.
        items.shrink_to_fit();
        Ok(items)
    }

    /// A prefix sign and its operand, or a postfix expression.
    fn prefix(&mut self) -> Result<Ast> {
        if self.c.at_punct('-') {
            let at = self.c.next().location();
            return Ok(Ast::Neg(Box::new(self.expr(PREFIX)?), at));
        }
        if self.c.at_punct('+') {
            self.c.next();
            return self.expr(PREFIX);
        }
        let mut a = self.atom()?;
        while self.language == Language::Vector && self.c.at_punct('.') {
            let at = self.c.next().location();
            let k = match &self.c.peek().tok {
                Tok::Ident(s) if &**s == "x" => 0,
                Tok::Ident(s) if &**s == "y" => 1,
                Tok::Ident(s) if &**s == "z" => 2,
                _ => return Err(self.c.expected(Expected::Component)),
            };
            self.c.next();
            a = Ast::Member(Box::new(a), k, at);
        }
        Ok(a)
    }

    fn atom(&mut self) -> Result<Ast> {
        let t = self.c.peek();
        match &t.tok {
            Tok::Literal(s) => {
                let n = parse_number(s).map_err(|kind| Error::parse(kind, t.location()))?;
                self.c.next();
                Ok(Ast::Number(n, t.location()))
            }
            Tok::Ident(name) => {
                self.c.next();
                if self.c.at(&Tok::Open(Delim::Paren)) {
                    self.call(name, t.location())
                } else {
                    Ok(Ast::Name(name.to_string(), t.location()))
                }
            }
            Tok::Open(Delim::Paren) => {
                self.c.next();
                let inner = self.expr(0)?;
                self.c
                    .expect(&Tok::Close(Delim::Paren), Expected::CloseParen)?;
                Ok(inner)
            }
            Tok::Open(Delim::Bracket) if self.language == Language::Vector => {
                self.c.next();
                let items = self.list(Delim::Bracket, Expected::VectorSeparator)?;
                if items.is_empty() {
                    return Err(Error::parse(ParseError::EmptyVector, t.location()));
                }
                Ok(Ast::Brackets(items, t.location()))
            }
            Tok::Punct('^') => Err(self.c.error_here(ParseError::CaretWithoutBase)),
            _ => Err(self.c.expected(match self.language {
                Language::Scalar => Expected::Operand,
                Language::Vector => Expected::VectorOperand,
            })),
        }
    }

    /// `name(args)`, the cursor at `(`.
    fn call(&mut self, name: &str, at: Location) -> Result<Ast> {
        if self.language == Language::Vector && (name == "der" || name == "der2") {
            return Err(Error::declaration(
                DeclarationError::RateInBody {
                    function: name.to_string(),
                },
                at,
            ));
        }
        self.c.next();
        let args = self.list(Delim::Paren, Expected::ArgumentSeparator)?;
        match arity(self.language, name) {
            None => Err(Error::declaration(
                DeclarationError::UnknownFunction {
                    name: name.to_string(),
                },
                at,
            )),
            Some(arity) if arity != args.len() => Err(Error::parse(
                ParseError::Arity {
                    function: name.to_string(),
                    expected: arity,
                    found: args.len(),
                },
                at,
            )),
            Some(_) => Ok(Ast::Call(name.to_string(), args, at)),
        }
    }

    /// `a, b, ...` up to the closing `close` (consumed; `expected` names it in the error).
    fn list(&mut self, close: Delim, expected: Expected) -> Result<Vec<Ast>> {
        let mut out = Vec::new();
        if !self.c.at(&Tok::Close(close)) {
            loop {
                out.push(self.expr(0)?);
                if !self.c.eat(&Tok::Punct(',')) {
                    break;
                }
            }
        }
        self.c.expect(&Tok::Close(close), expected)?;
        // Most lists are one argument: without this, four slots each.
        out.shrink_to_fit();
        Ok(out)
    }
}

/// A numeric literal: decimal integers are exact, decimals and exponent forms are floats.
fn parse_number(text: &str) -> std::result::Result<Number, ParseError> {
    // A negative literal only arises from tokens built by code, never from the lexer.
    if let Some(rest) = text.strip_prefix('-') {
        return parse_number(rest).map(|n| -n);
    }
    let literal = || text.to_string();
    if text.starts_with(['"', '\'', 'b', 'c', 'r']) {
        return Err(ParseError::NotANumber { literal: literal() });
    }
    let clean: String = text.chars().filter(|&c| c != '_').collect();
    let bad = || ParseError::BadNumber { literal: literal() };
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
    Number::float(x).ok_or_else(|| ParseError::NumberTooLarge { literal: literal() })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::syntax::plain_lex::tokens_from_str;

    fn parsed(text: &str, language: Language) -> Result<(Ast, Tok)> {
        let tokens = tokens_from_str(text)?;
        let mut c = Cursor::new(&tokens);
        let ast = parse(&mut c, language)?;
        Ok((ast, c.peek().tok.clone()))
    }

    fn text(source: &str, language: Language) -> String {
        parsed(source, language).unwrap().0.text()
    }

    fn error(source: &str, language: Language) -> String {
        parsed(source, language).unwrap_err().to_string()
    }

    /// One precedence table for both languages: the printed form shows the tree.
    #[test]
    fn both_languages_bind_alike() {
        for language in [Language::Scalar, Language::Vector] {
            for (source, tree) in [
                ("-x^2", "-x^2"),
                ("(-x)^2", "(-x)^2"),
                ("x^-y^2", "x^-y^2"),
                ("x^(-y)^2", "x^(-y)^2"),
                ("2^3^2", "2^3^2"),
                ("(2^3)^2", "(2^3)^2"),
                ("a - (b - c)", "a - (b - c)"),
                ("a*(b*c)/d", "a*(b*c)/d"),
                ("-a*b + c", "-a*b + c"),
                ("a/(b + c)", "a/(b + c)"),
            ] {
                assert_eq!(text(source, language), tree, "{source} ({language:?})");
            }
        }
    }

    /// A chain of one level is one n-ary node; parentheses keep their own node.
    #[test]
    fn chains_are_n_ary_and_parentheses_nest() {
        let (ast, _) = parsed("a - b + c - d", Language::Scalar).unwrap();
        let Ast::Sum(terms) = &ast else {
            panic!("{ast:?}")
        };
        let signs: Vec<bool> = terms.iter().map(|t| t.0).collect();
        assert_eq!(signs, [false, true, false, true]);
        let (ast, _) = parsed("(a*b)*c", Language::Scalar).unwrap();
        let Ast::Product(factors) = &ast else {
            panic!("{ast:?}")
        };
        assert_eq!(factors.len(), 2);
        assert!(matches!(factors[0].1, Ast::Product(_)));
        // The operator's location, for errors at the operator.
        let (ast, _) = parsed("a / b", Language::Scalar).unwrap();
        let Ast::Product(factors) = &ast else {
            panic!("{ast:?}")
        };
        assert_eq!(factors[1].2.column, 3);
    }

    /// The vector forms exist only in the vector language.
    #[test]
    fn vector_forms_only_in_the_vector_language() {
        assert_eq!(
            text("rot_z(b)*[0, 0, l/2] + P.x", Language::Vector),
            "rot_z(b)*[0, 0, l/2] + P.x"
        );
        assert_eq!(
            text("[[1, 0], [0, -(l - 1)]]", Language::Vector),
            "[[1, 0], [0, -(l - 1)]]"
        );
        assert!(
            error("[x, y]", Language::Scalar)
                .contains("expected a number, a name or `(`, found `[`")
        );
        assert!(error("cross(u, v)", Language::Scalar).contains("unknown function `cross`"));
        // The scalar parser stops before `.`, for the caller to report.
        let (_, next) = parsed("P.x", Language::Scalar).unwrap();
        assert_eq!(next, Tok::Punct('.'));
        assert!(error("der(x)", Language::Vector).contains("position-level"));
        assert!(error("[]", Language::Vector).contains("at least one entry"));
        assert!(error("P.w", Language::Vector).contains("expected `x`, `y` or `z`"));
    }

    #[test]
    fn errors_name_what_was_expected() {
        for language in [Language::Scalar, Language::Vector] {
            assert!(error("x**2", language).contains("powers are written `x^2`"));
            assert!(error("^x", language).contains("`^` needs a base"));
            assert!(error("atan2(x)", language).contains("`atan2` takes 2 arguments, found 1"));
            assert!(error("sin(x y)", language).contains("`,` or `)` after a function argument"));
            assert!(error("2f64", language).contains("without a type suffix"));
        }
    }

    /// One depth limit for parentheses, signs and exponents, in both languages.
    #[test]
    fn nesting_is_limited_in_both_languages() {
        for language in [Language::Scalar, Language::Vector] {
            let deep = |open: &str, close: &str, k: usize| {
                format!("{}x{}", open.repeat(k), close.repeat(k))
            };
            assert!(parsed(&deep("(", ")", MAX_DEPTH - 1), language).is_ok());
            for text in [
                deep("(", ")", MAX_DEPTH),
                deep("-", "", MAX_DEPTH),
                deep("x^", "", MAX_DEPTH),
                deep("sin(", ")", MAX_DEPTH),
            ] {
                assert!(error(&text, language).contains("nested too deeply"));
            }
        }
    }
}
