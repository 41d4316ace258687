//! The `draw` section: which declared points are drawn, the lines that join them, and the
//! points whose paths are traced. It names points only; their positions are the `point`
//! items and body points declared before it (world vectors, built by `mechanics`).
//!
//! ```text
//! draw := "draw" "{" (("line" NAME ("," NAME)+ | "trace" NAME ("," NAME)*) ";")* "}"
//! ```

use crate::error::{Error, Location, ParseError, Result};
use crate::syntax::lex::{Cursor, Tok, block, name};

/// A name as written, and where.
pub(crate) type NameAt = (String, Location);

/// The syntax tree of `draw { .. }`.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct DrawSection {
    /// Where the `draw` keyword is.
    pub(crate) at: Location,
    /// Each `line A, B, C;`: a polyline through the named points.
    pub(crate) lines: Vec<Vec<NameAt>>,
    /// The names of every `trace A, B;`.
    pub(crate) traces: Vec<NameAt>,
}

enum Statement {
    Line(Vec<NameAt>),
    Trace(Vec<NameAt>),
}

/// Parses the block after `draw` (the keyword, at `at`, already consumed).
pub(crate) fn parse_draw(c: &mut Cursor<'_>, at: Location) -> Result<DrawSection> {
    let statements = block(c, statement)?;
    let mut section = DrawSection {
        at,
        ..DrawSection::default()
    };
    for s in statements {
        match s {
            Statement::Line(names) => section.lines.push(names),
            Statement::Trace(names) => section.traces.extend(names),
        }
    }
    Ok(section)
}

fn statement(c: &mut Cursor<'_>) -> Result<Statement> {
    let (keyword, at) = name(c, "draw")?;
    if keyword != "line" && keyword != "trace" {
        return Err(Error::parse(
            ParseError::NotADrawStatement { found: keyword },
            at,
        ));
    }
    let mut names = vec![name(c, &keyword)?];
    while c.eat(&Tok::Punct(',')) {
        names.push(name(c, &keyword)?);
    }
    if keyword == "trace" {
        return Ok(Statement::Trace(names));
    }
    if names.len() < 2 {
        return Err(Error::parse(ParseError::ShortLine, at));
    }
    Ok(Statement::Line(names))
}
