//! The tokens of a text (a `.mech` file): a direct lexer for the plain text most files are
//! (ASCII names, numbers, punctuation, brackets and `//` comments), else proc_macro2's
//! ([`general_tokens`]). The direct lexer gives exactly the tokens and locations of
//! proc_macro2's and declines (returns `None`) at the first thing it does not cover (a string, a
//! doc or block comment, a character outside
//! ASCII, a carriage return, a number with a suffix, an unbalanced bracket), so the caller
//! lexes that text the general way, with its error messages.
//!
//! Why it exists: proc_macro2 builds a tree of reference-counted groups that is then
//! flattened, about 4 MB/s and 30 bytes of memory per byte of text; a generated declaration
//! of a 400-bar chain is 4.7 MB.

use crate::error::{Location, Result};
use crate::syntax::lex::{Delim, Names, Tok, Token, Tokens, general_tokens};

/// The punctuation characters proc_macro2 lexes as one `Punct` each (`'` starts a
/// lifetime or a character literal there, and is declined here).
const PUNCT: &[u8] = b"!#$%&*+,-./:;<=>?@^|~";

/// The tokens of a text: directly when it is plain, else by proc_macro2's lexer (whose
/// errors name the line and column where it stopped).
///
/// # Errors
/// [`general_tokens`]'s: unbalanced brackets or a stray character.
pub(crate) fn tokens_from_str(text: &str) -> Result<Tokens> {
    match plain_tokens(text) {
        Some(tokens) => Ok(tokens),
        None => general_tokens(text),
    }
}

/// The tokens of `text`, or `None` when the text holds something this lexer declines.
pub(crate) fn plain_tokens(text: &str) -> Option<Tokens> {
    let bytes = text.as_bytes();
    let mut lexer = Lexer {
        bytes,
        pos: 0,
        line: 1,
        line_start: 0,
        list: Vec::with_capacity(count_hint(bytes)),
        open: Vec::new(),
        last_end: None,
        names: Names::default(),
    };
    lexer.run()?;
    if !lexer.open.is_empty() {
        return None;
    }
    let index = lexer.list.len();
    let location = match lexer.last_end {
        Some((line, column)) => Location {
            line,
            column,
            token: Some(index),
        },
        None => Location {
            line: 1,
            column: 1,
            token: Some(index),
        },
    };
    lexer.list.push(Token::new(Tok::End, location));
    Some(Tokens {
        list: lexer.list,
        spans: Vec::new(),
    })
}

/// An upper bound of the number of tokens that is close for generated text (each token
/// starts with a non-space byte), so the list is allocated once.
fn count_hint(bytes: &[u8]) -> usize {
    let mut n = 1;
    let mut in_word = false;
    for &b in bytes {
        let word = b.is_ascii_alphanumeric() || b == b'_' || b == b'.';
        if !word || !in_word {
            n += usize::from(!b.is_ascii_whitespace());
        }
        in_word = word;
    }
    n
}

struct Lexer<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
    line_start: usize,
    list: Vec<Token>,
    open: Vec<Delim>,
    /// Line and column just after the last token that is not an opening bracket.
    last_end: Option<(usize, usize)>,
    names: Names,
}

impl<'a> Lexer<'a> {
    fn peek(&self, ahead: usize) -> Option<u8> {
        self.bytes.get(self.pos + ahead).copied()
    }

    /// Pushes `tok` starting at byte `start` and ending at the current position.
    fn push(&mut self, tok: Tok, start: usize) {
        let is_open = matches!(tok, Tok::Open(_));
        let location = Location {
            line: self.line,
            column: start - self.line_start + 1,
            token: Some(self.list.len()),
        };
        self.list.push(Token::new(tok, location));
        if !is_open {
            self.last_end = Some((self.line, self.pos - self.line_start + 1));
        }
    }

    fn run(&mut self) -> Option<()> {
        while let Some(b) = self.peek(0) {
            let start = self.pos;
            match b {
                b'\n' => {
                    self.pos += 1;
                    self.line += 1;
                    self.line_start = self.pos;
                }
                b' ' | b'\t' => self.pos += 1,
                b'/' if self.peek(1) == Some(b'/') => self.comment()?,
                b'/' if self.peek(1) == Some(b'*') => return None,
                b'(' | b'[' | b'{' => {
                    let d = delim(b);
                    self.pos += 1;
                    self.open.push(d);
                    self.push(Tok::Open(d), start);
                }
                b')' | b']' | b'}' => {
                    let d = delim(b);
                    if self.open.pop() != Some(d) {
                        return None;
                    }
                    self.pos += 1;
                    self.push(Tok::Close(d), start);
                }
                b'0'..=b'9' => {
                    self.number()?;
                    let text = self.text(start).into();
                    self.push(Tok::Literal(text), start);
                }
                b'a'..=b'z' | b'A'..=b'Z' | b'_' => {
                    while self
                        .peek(0)
                        .is_some_and(|c| c.is_ascii_alphanumeric() || c == b'_')
                    {
                        self.pos += 1;
                    }
                    // r#raw identifiers, b"byte strings", c"C strings" and the like.
                    if matches!(self.peek(0), Some(b'#' | b'"' | b'\'')) {
                        return None;
                    }
                    let text = self.text(start);
                    let text = self.names.get(text);
                    self.push(Tok::Ident(text), start);
                }
                _ if PUNCT.contains(&b) => {
                    self.pos += 1;
                    self.push(Tok::Punct(b as char), start);
                }
                _ => return None,
            }
        }
        Some(())
    }

    /// A `//` comment up to the end of its line; doc comments (`///`, `//!`) are declined.
    fn comment(&mut self) -> Option<()> {
        if matches!(self.peek(2), Some(b'/' | b'!')) {
            return None;
        }
        while let Some(b) = self.peek(0) {
            if b == b'\n' {
                break;
            }
            if !b.is_ascii() || b == b'\r' {
                return None;
            }
            self.pos += 1;
        }
        Some(())
    }

    /// A decimal number: digits, an optional fraction `.digits`, an optional exponent
    /// `e[+-]digits`. Anything that would make it another literal (a suffix, `1.`, `0x`)
    /// is declined.
    fn number(&mut self) -> Option<()> {
        self.digits();
        if self.peek(0) == Some(b'.') {
            if !self.peek(1).is_some_and(|c| c.is_ascii_digit()) {
                return None;
            }
            self.pos += 1;
            self.digits();
        }
        if matches!(self.peek(0), Some(b'e' | b'E')) {
            let sign = usize::from(matches!(self.peek(1), Some(b'+' | b'-')));
            if !self.peek(1 + sign).is_some_and(|c| c.is_ascii_digit()) {
                return None;
            }
            self.pos += 1 + sign;
            self.digits();
        }
        match self.peek(0) {
            Some(c) if c.is_ascii_alphanumeric() || c == b'_' || c == b'.' => None,
            _ => Some(()),
        }
    }

    fn digits(&mut self) {
        while self.peek(0).is_some_and(|c| c.is_ascii_digit()) {
            self.pos += 1;
        }
    }

    /// The text from byte `start` to the current position (ASCII: the lexer declines the
    /// rest).
    fn text(&self, start: usize) -> &'a str {
        let bytes: &'a [u8] = self.bytes;
        std::str::from_utf8(&bytes[start..self.pos]).unwrap_or_default()
    }
}

fn delim(b: u8) -> Delim {
    match b {
        b'(' | b')' => Delim::Paren,
        b'[' | b']' => Delim::Bracket,
        _ => Delim::Brace,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tokens and locations proc_macro2's route gives (kinds, text, line, column, index).
    fn general(text: &str) -> Vec<(Tok, Location)> {
        general_tokens(text)
            .unwrap()
            .list
            .into_iter()
            .map(|t| {
                let at = t.location();
                (t.tok, at)
            })
            .collect()
    }

    fn plain(text: &str) -> Option<Vec<(Tok, Location)>> {
        plain_tokens(text).map(|t| {
            t.list
                .into_iter()
                .map(|t| {
                    let at = t.location();
                    (t.tok, at)
                })
                .collect()
        })
    }

    /// Wherever the direct lexer accepts a text, its tokens are proc_macro2's: on every
    /// library declaration (as written, and without its doc comments) and snippets of every
    /// token kind.
    #[test]
    fn accepted_texts_lex_as_proc_macro2_lexes_them() {
        let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../mechanisms");
        let mut texts: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "mech"))
            .map(|p| std::fs::read_to_string(p).unwrap())
            .collect();
        // The library's declarations without their doc comments (which are declined).
        let undocumented: Vec<String> = texts
            .iter()
            .map(|t| {
                t.lines()
                    .map(|l| {
                        if l.trim_start().starts_with("///") {
                            ""
                        } else {
                            l
                        }
                    })
                    .collect::<Vec<_>>()
                    .join("\n")
            })
            .collect();
        texts.extend(undocumented);
        for snippet in [
            "",
            "// only a comment",
            "x = 1e-4 + 0.04*y^2 - 2 / 1E5 + 2.5e+3;",
            "a-b -1 - -2.0",
            "f(g[h{ }]) ()",
            "!#$%&*+,-./:;<=>?@^|~",
            "th_1 = 0.1; der(th_1) = 0;\n\t// note\n  k2 = 3;\n",
            "  trailing  \n\n",
            "x//y\nz",
            "_ + _x * a__b - x.0.1 + a.5 // a // b\n",
            "k1e3 = 1e3; e = 2.5E-7;",
        ] {
            texts.push(snippet.to_string());
        }
        let mut accepted = 0;
        for text in &texts {
            if let Some(tokens) = plain(text) {
                assert_eq!(tokens, general(text), "{text}");
                accepted += 1;
            }
        }
        // Every declaration without its doc comments, and every snippet, is plain text.
        assert!(accepted >= 16 + 11, "{accepted} accepted");
    }

    /// What the direct lexer declines, proc_macro2 lexes (or reports) its own way.
    #[test]
    fn other_texts_are_declined() {
        for text in [
            "\"a string\"",
            "/* block */ x",
            "/// doc\nx",
            "//! inner doc\nx",
            "1.",
            "1f64",
            "0x1f",
            "1_000",
            "2x",
            "é = 1",
            "a\r\nb",
            "(]",
            "(",
            ")",
            "'a",
            "r#x",
            "b'a'",
            "x \\ y",
        ] {
            assert!(plain(text).is_none(), "{text}");
        }
    }
}
