//! The declaration grammar: a syntax tree of a whole `mechanism!` declaration and its parser.
//!
//! ```text
//! declaration := doc* ["pub"] "struct" NAME ";" section*
//! doc         := "#" "[" "doc" "=" STRING "]"            (what `/// text` becomes)
//! section     := "parameters"  "{" (NAME "=" expr [range] ";")* "}"   (range: parameter_range.rs)
//!              | "coordinates" "{" (NAME "=" expr ";")* "}"           (initial guesses)
//!              | "independent" "{" ((NAME | "der" "(" NAME ")") "=" expr ";")* "}"
//!              | "kinetic" "=" expr ";"
//!              | "potential" "=" expr ";"
//!              | "constraints" "{" (row ";")* "}"
//!              | "velocity_constraints" "{" (row ";")* "}"     A(q, t) q' + a(q, t) = 0
//!              | "forces" "{" (NAME ":" expr ";")* "}"
//! row         := expr ["=" expr] | vector ["=" vector]
//! vector      := "[" expr ("," expr)* "]"
//! ```
//! Sections come in any order, each at most once; every statement of a block ends with `;`
//! (the last one too), and a `;` after a block is allowed. A row `a = b` means a - b = 0;
//! `[a1, a2, a3] = [b1, b2, b3]` is three rows a_i - b_i = 0.

use crate::error::{Error, Expected, Location, ParseError, Result};
use crate::syntax::ast::Ast;
use crate::syntax::expression::{Language, parse};
use crate::syntax::lex::{Cursor, Delim, Tok, Tokens, block, name};
use crate::syntax::parameter_range::{ParameterRange, parameter_range};
use crate::syntax::spelling::closest;

/// The section keywords, in the order the book's chapter "Declaring a mechanism" documents
/// them.
pub(crate) const SECTIONS: &[&str] = &[
    "parameters",
    "coordinates",
    "independent",
    "kinetic",
    "potential",
    "constraints",
    "velocity_constraints",
    "forces",
];

/// `name = value;` (a parameter default or a coordinate's initial guess), or
/// `name = value positive;` (a parameter with its range).
#[derive(Clone, Debug)]
pub(crate) struct Item {
    /// The declared name.
    pub(crate) name: String,
    /// Where the name is.
    pub(crate) at: Location,
    /// The value.
    pub(crate) value: Ast,
    /// The range written after a parameter's default ([`ParameterRange::Any`] when none,
    /// and always for a coordinate).
    pub(crate) range: ParameterRange,
}

/// `phi = 0.0;` (rate false) or `der(phi) = 2*pi;` (rate true) in `independent`.
#[derive(Clone, Debug)]
pub(crate) struct IndependentItem {
    /// The coordinate's name.
    pub(crate) name: String,
    /// True for `der(name) = ...`.
    pub(crate) rate: bool,
    /// Where the name is.
    pub(crate) at: Location,
    /// The value.
    pub(crate) value: Ast,
}

/// One scalar constraint row lhs - rhs = 0.
#[derive(Clone, Debug)]
pub(crate) struct Row {
    /// Left side.
    pub(crate) lhs: Ast,
    /// Right side, when written `lhs = rhs`.
    pub(crate) rhs: Option<Ast>,
    /// Where the row (or its vector component) starts.
    pub(crate) at: Location,
    /// The 1-based index of the statement in `constraints { .. }` (a vector equation is one
    /// statement of several rows).
    pub(crate) statement: usize,
    /// The component of a vector statement (`x`, `y`, `z` or `1`, `2`, ..); empty for a
    /// scalar row (see [`components`]).
    pub(crate) component: String,
}

/// `name: expr;` in `forces`.
#[derive(Clone, Debug)]
pub(crate) struct Force {
    /// The coordinate the force acts along.
    pub(crate) name: String,
    /// Where the name is.
    pub(crate) at: Location,
    /// The generalised force.
    pub(crate) value: Ast,
}

/// A section with the location of its keyword.
#[derive(Clone, Debug)]
pub(crate) struct Section<T> {
    /// Where the keyword is.
    pub(crate) at: Location,
    /// The contents.
    pub(crate) body: T,
}

/// A whole declaration, as written.
#[derive(Clone, Debug, Default)]
pub(crate) struct Declaration {
    /// Doc comment lines.
    pub(crate) doc: Vec<String>,
    /// `pub struct`.
    pub(crate) public: bool,
    /// The struct name.
    pub(crate) name: String,
    /// Where the struct name is.
    pub(crate) name_at: Location,
    /// `parameters { .. }`.
    pub(crate) parameters: Option<Section<Vec<Item>>>,
    /// `coordinates { .. }`.
    pub(crate) coordinates: Option<Section<Vec<Item>>>,
    /// `independent { .. }`.
    pub(crate) independent: Option<Section<Vec<IndependentItem>>>,
    /// `kinetic = ..;`.
    pub(crate) kinetic: Option<Section<Ast>>,
    /// `potential = ..;`.
    pub(crate) potential: Option<Section<Ast>>,
    /// `constraints { .. }`, vector rows expanded.
    pub(crate) constraints: Option<Section<Vec<Row>>>,
    /// `velocity_constraints { .. }`, vector rows expanded: rows linear in the rates der(q).
    pub(crate) velocity_constraints: Option<Section<Vec<Row>>>,
    /// `forces { .. }`.
    pub(crate) forces: Option<Section<Vec<Force>>>,
    /// `body`, `gravity`, `point`, `axis`, `spring`, `damper` and `joints` (parse_bodies.rs).
    pub(crate) bodies: crate::syntax::bodies::Bodies,
}

/// Parses a declaration from its tokens. Stops at the first syntax error.
pub(crate) fn parse_declaration_tokens(tokens: &Tokens) -> Result<Declaration> {
    let mut c = Cursor::new(tokens);
    let mut d = Declaration::default();
    header(&mut c, &mut d)?;
    while !c.at(&Tok::End) {
        section(&mut c, &mut d)?;
        c.eat(&Tok::Punct(';'));
    }
    Ok(d)
}

fn header(c: &mut Cursor<'_>, d: &mut Declaration) -> Result<()> {
    while c.at_punct('#') {
        c.next();
        c.eat(&Tok::Punct('!'));
        c.expect(&Tok::Open(Delim::Bracket), Expected::AttributeOpen)?;
        match &c.peek().tok {
            Tok::Ident(s) if &**s == "doc" => {}
            _ => return Err(c.error_here(ParseError::NotADocComment { found: c.found() })),
        }
        c.next();
        c.expect(&Tok::Punct('='), Expected::DocEquals)?;
        let t = c.next();
        let Tok::Literal(lit) = &t.tok else {
            return Err(Error::parse(ParseError::MissingDocText, t.location()));
        };
        let text =
            unquote(lit).ok_or_else(|| Error::parse(ParseError::DocNotAString, t.location()))?;
        d.doc.extend(
            text.lines()
                .map(|l| l.strip_prefix(' ').unwrap_or(l).to_string()),
        );
        c.expect(&Tok::Close(Delim::Bracket), Expected::AttributeClose)?;
    }
    if let Tok::Ident(s) = &c.peek().tok
        && &**s == "pub"
    {
        d.public = true;
        c.next();
    }
    match &c.peek().tok {
        Tok::Ident(s) if &**s == "struct" => {
            c.next();
        }
        _ => return Err(c.error_here(ParseError::NoStruct { found: c.found() })),
    }
    let t = c.next();
    match &t.tok {
        Tok::Ident(name) => {
            d.name = name.to_string();
            d.name_at = t.location();
        }
        _ => return Err(Error::parse(ParseError::NoStructName, t.location())),
    }
    c.expect(&Tok::Punct(';'), Expected::StructSemicolon)?;
    Ok(())
}

/// The value of a string literal, with the common escapes; `None` if it is not a string.
fn unquote(lit: &str) -> Option<String> {
    if let Some(raw) = lit.strip_prefix('r') {
        let hashes = raw.len() - raw.trim_start_matches('#').len();
        let inner = raw.get(hashes + 1..raw.len().checked_sub(hashes + 1)?)?;
        return Some(inner.to_string());
    }
    let inner = lit.strip_prefix('"')?.strip_suffix('"')?;
    let mut out = String::with_capacity(inner.len());
    let mut chars = inner.chars();
    while let Some(ch) = chars.next() {
        if ch != '\\' {
            out.push(ch);
            continue;
        }
        match chars.next()? {
            'n' => out.push('\n'),
            't' => out.push('\t'),
            'r' => out.push('\r'),
            '0' => out.push('\0'),
            'u' => {
                let code: String = chars.by_ref().skip(1).take_while(|&c| c != '}').collect();
                out.push(char::from_u32(u32::from_str_radix(&code, 16).ok()?)?);
            }
            '\n' => {
                while chars.clone().next().is_some_and(char::is_whitespace) {
                    chars.next();
                }
            }
            other => out.push(other),
        }
    }
    Some(out)
}

fn duplicate_section(name: &str, at: Location) -> Error {
    Error::parse(
        ParseError::DuplicateSection {
            section: name.to_string(),
        },
        at,
    )
}

/// One section, by its keyword: the grammar as one table of a line per keyword (see the
/// module docs); a section given twice is an error at its second keyword.
fn section(c: &mut Cursor<'_>, d: &mut Declaration) -> Result<()> {
    let t = c.peek();
    let Tok::Ident(keyword) = &t.tok else {
        return Err(c.expected(Expected::Section { sections: SECTIONS }));
    };
    let at = t.location();
    c.next();
    let keyword: &str = keyword;
    match keyword {
        "parameters" => fill(
            &mut d.parameters,
            keyword,
            at,
            named_values(c, keyword, true)?,
        ),
        "coordinates" => fill(
            &mut d.coordinates,
            keyword,
            at,
            named_values(c, keyword, false)?,
        ),
        "independent" => fill(&mut d.independent, keyword, at, independent_items(c)?),
        "kinetic" => fill(&mut d.kinetic, keyword, at, energy(c, keyword)?),
        "potential" => fill(&mut d.potential, keyword, at, energy(c, keyword)?),
        "constraints" => fill(&mut d.constraints, keyword, at, constraint_rows(c)?),
        "velocity_constraints" => fill(
            &mut d.velocity_constraints,
            keyword,
            at,
            constraint_rows(c)?,
        ),
        "forces" => fill(&mut d.forces, keyword, at, forces(c)?),
        kw if crate::syntax::bodies::is_body_section(kw) => {
            crate::syntax::bodies::parse_body_section(c, kw, at, &mut d.bodies)
        }
        other => {
            let kind = ParseError::UnknownSection {
                name: other.to_string(),
                sections: SECTIONS,
                suggestion: closest(other, SECTIONS.iter().copied()),
            };
            Err(Error::parse(kind, at))
        }
    }
}

/// Puts the section `keyword` at `at` into its empty `slot`.
fn fill<T>(slot: &mut Option<Section<T>>, keyword: &str, at: Location, body: T) -> Result<()> {
    if slot.is_some() {
        return Err(duplicate_section(keyword, at));
    }
    *slot = Some(Section { at, body });
    Ok(())
}

/// `{ name = value; ... }`: the body of `parameters` (each value optionally followed by its
/// range, when `ranges`) and `coordinates`.
fn named_values(c: &mut Cursor<'_>, keyword: &str, ranges: bool) -> Result<Vec<Item>> {
    block(c, |c| {
        let (name, at) = name(c, keyword)?;
        c.expect(&Tok::Punct('='), Expected::Value { name: name.clone() })?;
        let value = parse(c, Language::Scalar)?;
        let mut range = ParameterRange::Any;
        if ranges {
            range = parameter_range(c);
            if let (ParameterRange::Any, Tok::Ident(word)) = (range, &c.peek().tok) {
                // A word after the default that is no range: say what may stand there.
                return Err(c.error_here(ParseError::NotARange {
                    word: word.to_string(),
                    name,
                    suggestion: closest(word, ParameterRange::KEYWORDS),
                }));
            }
        }
        Ok(Item {
            name,
            at,
            value,
            range,
        })
    })
}

/// `{ name = value; der(name) = value; ... }`: the body of `independent`.
fn independent_items(c: &mut Cursor<'_>) -> Result<Vec<IndependentItem>> {
    block(c, |c| {
        let (first, first_at) = name(c, "independent")?;
        let (name, at, rate) = if first == "der" && c.at(&Tok::Open(Delim::Paren)) {
            c.next();
            let (n, a) = name(c, "independent")?;
            c.expect(&Tok::Close(Delim::Paren), Expected::CoordinateClose)?;
            (n, a, true)
        } else {
            (first, first_at, false)
        };
        c.expect(&Tok::Punct('='), Expected::InitialValue)?;
        let value = parse(c, Language::Scalar)?;
        Ok(IndependentItem {
            name,
            rate,
            at,
            value,
        })
    })
}

/// `= expression;`: the rest of `kinetic` and `potential`.
fn energy(c: &mut Cursor<'_>, keyword: &str) -> Result<Ast> {
    let written = keyword.to_string();
    c.expect(&Tok::Punct('='), Expected::EqualsAfter { written })?;
    let body = parse(c, Language::Scalar)?;
    let energy = keyword.to_string();
    c.expect(&Tok::Punct(';'), Expected::EnergySemicolon { energy })?;
    Ok(body)
}

/// `{ row; [row, row]; ... }`: the body of `constraints` and `velocity_constraints`, each
/// row labelled with its statement (1-based) and its component in a vector statement.
fn constraint_rows(c: &mut Cursor<'_>) -> Result<Vec<Row>> {
    let rows = block(c, row)?;
    let mut body = Vec::new();
    for (k, rows) in rows.into_iter().enumerate() {
        let labels = components(rows.len(), 1);
        for (mut row, component) in rows.into_iter().zip(labels) {
            row.statement = k + 1;
            row.component = component;
            body.push(row);
        }
    }
    Ok(body)
}

/// `{ name: value; ... }`: the body of `forces`.
fn forces(c: &mut Cursor<'_>) -> Result<Vec<Force>> {
    block(c, |c| {
        let (name, at) = name(c, "forces")?;
        c.expect(
            &Tok::Punct(':'),
            Expected::ForceColon { name: name.clone() },
        )?;
        let value = parse(c, Language::Scalar)?;
        Ok(Force { name, at, value })
    })
}

/// One constraint statement: a scalar row or a vector of rows.
fn row(c: &mut Cursor<'_>) -> Result<Vec<Row>> {
    let at = c.peek().location();
    if !c.at(&Tok::Open(Delim::Bracket)) {
        let lhs = parse(c, Language::Scalar)?;
        let rhs = if c.eat(&Tok::Punct('=')) {
            Some(parse(c, Language::Scalar)?)
        } else {
            None
        };
        return Ok(vec![Row {
            lhs,
            rhs,
            at,
            statement: 0,
            component: String::new(),
        }]);
    }
    let lhs = vector(c)?;
    if !c.at_punct('=') {
        return Ok(lhs
            .into_iter()
            .map(|(lhs, at)| Row {
                lhs,
                rhs: None,
                at,
                statement: 0,
                component: String::new(),
            })
            .collect());
    }
    let eq = c.next().location();
    if !c.at(&Tok::Open(Delim::Bracket)) {
        return Err(c.error_here(ParseError::ScalarRightOfVector { found: c.found() }));
    }
    let rhs = vector(c)?;
    if lhs.len() != rhs.len() {
        let kind = ParseError::VectorLengths {
            left: lhs.len(),
            right: rhs.len(),
        };
        return Err(Error::parse(kind, eq));
    }
    Ok(lhs
        .into_iter()
        .zip(rhs)
        .map(|((l, at), (r, _))| Row {
            lhs: l,
            rhs: Some(r),
            at,
            statement: 0,
            component: String::new(),
        })
        .collect())
}

/// `[e1, e2, ...]` with the location of each entry.
fn vector(c: &mut Cursor<'_>) -> Result<Vec<(Ast, Location)>> {
    c.next(); // `[`
    let mut out = Vec::new();
    while !c.at(&Tok::Close(Delim::Bracket)) {
        let at = c.peek().location();
        out.push((parse(c, Language::Scalar)?, at));
        if !c.eat(&Tok::Punct(',')) {
            break;
        }
    }
    c.expect(&Tok::Close(Delim::Bracket), Expected::VectorSeparator)?;
    if out.is_empty() {
        return Err(c.error_here(ParseError::EmptyVectorConstraint { found: c.found() }));
    }
    Ok(out)
}

/// The component labels of the rows x cols entries of a vector or matrix statement, in the
/// (row-major) order of its rows: `""` for a scalar, `x`, `y` (, `z`) for a vector of 2 (3)
/// entries, `1`, `2`, .. for a longer vector, `(i, j)` (1-based) for a matrix.
pub(crate) fn components(rows: usize, cols: usize) -> Vec<String> {
    let len = rows * cols;
    if len == 1 {
        return vec![String::new()];
    }
    if rows == 1 || cols == 1 {
        if len <= 3 {
            return ["x", "y", "z"][..len]
                .iter()
                .map(|s| s.to_string())
                .collect();
        }
        return (1..=len).map(|k| k.to_string()).collect();
    }
    (0..len)
        .map(|k| format!("({}, {})", k / cols + 1, k % cols + 1))
        .collect()
}
