//! Tokens of the declaration language, from a `proc_macro2::TokenStream` (inline macro input)
//! or from text (a `.mech` file), flattened into one list the parsers walk with a cursor.
//!
//! Both routes use proc_macro2's tokenizer (or, for plain text, a direct lexer that gives
//! the same tokens, `plain_lex`, which is the text route's entry), so the two forms have one
//! grammar: `//` and
//! `/* */` comments vanish, `///` doc comments arrive as `#[doc = "..."]`, `1e-4` and `0.04`
//! are single literals, `^` is a punctuation character. Groups are flattened into an opening
//! token, their contents and a closing token; every token keeps its [`Location`] (1-based
//! line and column, and its index in the list) and, for the token-stream route, its span.

use std::rc::Rc;
use std::str::FromStr;

use proc_macro2::{Delimiter, Span, TokenStream, TokenTree};

use crate::algebra::expr::FxHashSet;
use crate::error::{Error, Expected, Location, ParseError, Result};

/// A bracket kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Delim {
    /// `( )`, and the invisible groups of macro_rules interpolation.
    Paren,
    /// `[ ]`
    Bracket,
    /// `{ }`
    Brace,
}

impl Delim {
    /// The opening and closing characters.
    pub(crate) fn chars(self) -> (char, char) {
        match self {
            Delim::Paren => ('(', ')'),
            Delim::Bracket => ('[', ']'),
            Delim::Brace => ('{', '}'),
        }
    }
}

/// What a token is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Tok {
    /// A name or keyword (one shared string per distinct name of the input).
    Ident(Rc<str>),
    /// One punctuation character (`+`, `^`, `;`, ...).
    Punct(char),
    /// A literal, as written (`0.04`, `2`, `1e-4`, `"doc text"`).
    Literal(Rc<str>),
    /// An opening bracket.
    Open(Delim),
    /// A closing bracket.
    Close(Delim),
    /// The end of the input.
    End,
}

impl Tok {
    /// How the token reads in an error message.
    pub(crate) fn describe(&self) -> String {
        match self {
            Tok::Ident(s) => format!("`{s}`"),
            Tok::Punct(c) => format!("`{c}`"),
            Tok::Literal(s) => format!("`{s}`"),
            Tok::Open(d) => format!("`{}`", d.chars().0),
            Tok::Close(d) => format!("`{}`", d.chars().1),
            Tok::End => "the end of the input".to_string(),
        }
    }
}

/// One token with where it is: its line, column (1-based, in characters) and index in the
/// token list, kept in 32 bits each (40 bytes a token, against 80 with a [`Location`] and
/// a span each: a generated declaration of an 800-bar chain has 9 million tokens).
#[derive(Clone, Debug)]
pub(crate) struct Token {
    /// The token.
    pub(crate) tok: Tok,
    line: u32,
    column: u32,
    index: u32,
}

impl Token {
    /// `tok` at `location` (whose token index is the token's own). A place beyond 32 bits
    /// is kept as `u32::MAX`: inputs are bounded far below (`MECHANISM_MAX_INPUT_BYTES`).
    pub(crate) fn new(tok: Tok, location: Location) -> Self {
        let narrow = |x: usize| u32::try_from(x).unwrap_or(u32::MAX);
        Self {
            tok,
            line: narrow(location.line),
            column: narrow(location.column),
            index: narrow(location.token.unwrap_or(usize::MAX)),
        }
    }

    /// Line, column and index.
    pub(crate) fn location(&self) -> Location {
        Location {
            line: self.line as usize,
            column: self.column as usize,
            token: Some(self.index as usize),
        }
    }
}

/// The flat token list of an input, always ending with [`Tok::End`].
#[derive(Clone, Debug)]
pub(crate) struct Tokens {
    /// The tokens.
    pub(crate) list: Vec<Token>,
    /// The span of each token, by index (token-stream route only: empty for text, whose
    /// spans a macro could not use).
    pub(crate) spans: Vec<Span>,
}

impl Tokens {
    /// The spans of all tokens, by index (empty for the text route).
    pub(crate) fn spans(&self) -> Vec<Span> {
        self.spans.clone()
    }
}

/// One shared string per distinct name: the names of a large declaration repeat (`th12`,
/// `cos`, `der`), so each token holds a reference, not a copy.
#[derive(Debug, Default)]
pub(crate) struct Names(FxHashSet<Rc<str>>);

impl Names {
    /// The shared string equal to `text`.
    pub(crate) fn get(&mut self, text: &str) -> Rc<str> {
        if let Some(k) = self.0.get(text) {
            return Rc::clone(k);
        }
        let k: Rc<str> = Rc::from(text);
        self.0.insert(Rc::clone(&k));
        k
    }
}

fn location_of(span: Span, index: usize) -> Location {
    let lc = span.start();
    Location {
        line: lc.line,
        column: lc.column + 1,
        token: Some(index),
    }
}

fn location_after(span: Span, index: usize) -> Location {
    let lc = span.end();
    Location {
        line: lc.line,
        column: lc.column + 1,
        token: Some(index),
    }
}

/// Flattens a token stream (iteratively: deep nesting cannot overflow the stack).
fn flatten(stream: TokenStream, keep_spans: bool) -> Tokens {
    let mut list: Vec<Token> = Vec::new();
    let mut spans: Vec<Span> = Vec::new();
    let mut names = Names::default();
    let mut push = |list: &mut Vec<Token>, tok: Tok, span: Span| {
        let location = location_of(span, list.len());
        list.push(Token::new(tok, location));
        if keep_spans {
            spans.push(span);
        }
    };
    // Each frame: the remaining trees of a group, and the group's close token (if any).
    let mut stack: Vec<(proc_macro2::token_stream::IntoIter, Option<(Delim, Span)>)> =
        vec![(stream.into_iter(), None)];
    let mut last_span: Option<Span> = None;
    while let Some((iter, _)) = stack.last_mut() {
        match iter.next() {
            Some(TokenTree::Group(g)) => {
                let d = match g.delimiter() {
                    Delimiter::Parenthesis | Delimiter::None => Delim::Paren,
                    Delimiter::Bracket => Delim::Bracket,
                    Delimiter::Brace => Delim::Brace,
                };
                push(&mut list, Tok::Open(d), g.span_open());
                stack.push((g.stream().into_iter(), Some((d, g.span_close()))));
            }
            Some(TokenTree::Ident(i)) => {
                last_span = Some(i.span());
                push(&mut list, Tok::Ident(names.get(&i.to_string())), i.span());
            }
            Some(TokenTree::Punct(p)) => {
                last_span = Some(p.span());
                push(&mut list, Tok::Punct(p.as_char()), p.span());
            }
            Some(TokenTree::Literal(l)) => {
                last_span = Some(l.span());
                push(&mut list, Tok::Literal(l.to_string().into()), l.span());
            }
            None => {
                if let Some((_, Some((d, span)))) = stack.pop() {
                    last_span = Some(span);
                    push(&mut list, Tok::Close(d), span);
                }
            }
        }
    }
    let index = list.len();
    let location = match last_span {
        Some(s) => location_after(s, index),
        None => Location {
            line: 1,
            column: 1,
            token: Some(index),
        },
    };
    if keep_spans {
        spans.push(last_span.unwrap_or_else(Span::call_site));
    }
    list.push(Token::new(Tok::End, location));
    Tokens { list, spans }
}

/// The tokens of macro input (spans kept, so errors can point at the user's token).
pub(crate) fn tokens_from_stream(stream: TokenStream) -> Tokens {
    flatten(stream, true)
}

/// The tokens of any text by proc_macro2's own (fallback) lexer, even inside a procedural
/// macro, because the compiler's lexer gives text no line/column information; the fallback
/// spans are used for their locations only and are not kept. Unbalanced brackets or a
/// stray character are a parse error at the line and column where the lexer stopped.
/// (`plain_lex::tokens_from_str` is the entry: plain text does not come here.)
pub(crate) fn general_tokens(text: &str) -> Result<Tokens> {
    proc_macro2::fallback::force();
    let lexed = TokenStream::from_str(text).map(|s| flatten(s, false));
    let result = match lexed {
        Ok(tokens) => Ok(tokens),
        Err(e) => {
            let lc = e.span().start();
            let (line, column) = if lc.line == 0 {
                (1, 1)
            } else {
                (lc.line, lc.column + 1)
            };
            Err(Error::parse(
                ParseError::Unreadable {
                    reason: e.to_string(),
                },
                Location {
                    line,
                    column,
                    token: None,
                },
            ))
        }
    };
    proc_macro2::fallback::unforce();
    result
}

/// A cursor over a token list.
pub(crate) struct Cursor<'a> {
    tokens: &'a [Token],
    pos: usize,
}

impl<'a> Cursor<'a> {
    /// A cursor at the first token of `tokens` (which must end with [`Tok::End`]).
    pub(crate) fn new(tokens: &'a Tokens) -> Self {
        Self {
            tokens: &tokens.list,
            pos: 0,
        }
    }

    /// The current token (the end token once past the end).
    pub(crate) fn peek(&self) -> &'a Token {
        let last = self.tokens.len().saturating_sub(1);
        &self.tokens[self.pos.min(last)]
    }

    /// Consumes and returns the current token.
    pub(crate) fn next(&mut self) -> &'a Token {
        let t = self.peek();
        if t.tok != Tok::End {
            self.pos += 1;
        }
        t
    }

    /// True when the current token is `tok`.
    pub(crate) fn at(&self, tok: &Tok) -> bool {
        &self.peek().tok == tok
    }

    /// True when the current token is the punctuation `c`.
    pub(crate) fn at_punct(&self, c: char) -> bool {
        self.at(&Tok::Punct(c))
    }

    /// Consumes the current token if it is `tok`.
    pub(crate) fn eat(&mut self, tok: &Tok) -> bool {
        let hit = self.at(tok);
        if hit {
            self.next();
        }
        hit
    }

    /// Consumes `tok` or fails with "expected {expected}, found ...".
    pub(crate) fn expect(&mut self, tok: &Tok, expected: Expected) -> Result<&'a Token> {
        if self.at(tok) {
            return Ok(self.next());
        }
        Err(self.expected(expected))
    }

    /// How the current token reads in a message.
    pub(crate) fn found(&self) -> String {
        self.peek().tok.describe()
    }

    /// A parse error of `kind` at the current token.
    pub(crate) fn error_here(&self, kind: ParseError) -> Error {
        Error::parse(kind, self.peek().location())
    }

    /// "expected {expected}, found {the current token}", at the current token.
    pub(crate) fn expected(&self, expected: Expected) -> Error {
        self.error_here(ParseError::Expected {
            expected,
            found: self.found(),
        })
    }
}

/// A name at the cursor (`section` names where, for the error).
pub(crate) fn name(c: &mut Cursor<'_>, section: &str) -> Result<(String, Location)> {
    let t = c.peek();
    match &t.tok {
        Tok::Ident(s) => {
            c.next();
            Ok((s.to_string(), t.location()))
        }
        _ => Err(c.expected(Expected::Name {
            section: section.to_string(),
        })),
    }
}

/// `{ item; item; ... }`: every item ends with `;`, the last one too (a missing `;` is
/// reported at the token where it was expected, so a dropped statement cannot go unnoticed).
pub(crate) fn block<T>(
    c: &mut Cursor<'_>,
    mut item: impl FnMut(&mut Cursor<'_>) -> Result<T>,
) -> Result<Vec<T>> {
    c.expect(&Tok::Open(Delim::Brace), Expected::OpenBrace)?;
    let mut out = Vec::new();
    while !c.at(&Tok::Close(Delim::Brace)) {
        out.push(item(c)?);
        if c.at(&Tok::Close(Delim::Brace)) {
            return Err(c.expected(Expected::LastSemicolon));
        }
        if !c.eat(&Tok::Punct(';')) {
            return Err(c.expected(Expected::Semicolon));
        }
    }
    c.next();
    Ok(out)
}
