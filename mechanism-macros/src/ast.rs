//! The macro's input: the declaration's tokens or a `.mech` file, parsed into a
//! [`Model`], with every error mapped to a span the user can click.

use std::path::PathBuf;

use mechanism_codegen::{Error, Location, Model, ModelSpans, SpannedError};
use proc_macro2::{Span, TokenStream, TokenTree};
use syn::LitStr;

/// Where the declaration came from.
pub enum Source {
    /// Written inline: errors point at the offending token.
    Inline,
    /// `file = "mechanisms/x.mech"`: errors point at the literal and quote `file:line:column`.
    File {
        /// The string literal as written (its span receives every error).
        literal: LitStr,
        /// The absolute path that was read (for `include_str!`, so edits trigger a rebuild).
        path: PathBuf,
    },
}

/// A parsed declaration: the codegen model and where it came from.
pub struct Declaration {
    /// The model (expressions in its arena, locations of every declared item).
    pub model: Model,
    /// Where the parts of the declaration are (token spans for inline input).
    pub spans: ModelSpans,
    /// Inline tokens or a file.
    pub source: Source,
    /// The path of the runtime crate in the generated code: `::mechanism` unless the input
    /// starts with `crate = path,` (the root crate itself uses `crate = crate`).
    pub krate: TokenStream,
}

impl Declaration {
    /// The compile error for a codegen error at `location`, pointing at the user's token
    /// (inline) or at the file literal with `file:line:column` (file form).
    pub fn error_at(&self, location: Option<Location>, message: &str) -> syn::Error {
        match &self.source {
            Source::Inline => {
                let span = location.map_or_else(Span::call_site, |l| self.spans.span(l));
                syn::Error::new(span, message)
            }
            Source::File { literal, .. } => file_error(literal, location, message),
        }
    }
}

/// `file = "..."`, recognised token by token so that any other input is a declaration.
fn file_literal(tokens: &TokenStream) -> Option<syn::Result<LitStr>> {
    let trees: Vec<TokenTree> = tokens.clone().into_iter().collect();
    match trees.as_slice() {
        [TokenTree::Ident(kw), TokenTree::Punct(eq), rest @ ..]
            if kw == "file" && eq.as_char() == '=' =>
        {
            let rest: TokenStream = rest.iter().cloned().collect();
            Some(syn::parse2::<LitStr>(rest))
        }
        _ => None,
    }
}

/// Splits an optional leading `crate = path,` off the input (serde's `crate = "..."`
/// idea: for a crate that re-exports `mechanism`, or for the runtime crate itself).
fn crate_path(tokens: TokenStream) -> syn::Result<(TokenStream, TokenStream)> {
    let trees: Vec<TokenTree> = tokens.clone().into_iter().collect();
    let [TokenTree::Ident(kw), TokenTree::Punct(eq), rest @ ..] = trees.as_slice() else {
        return Ok((quote::quote!(::mechanism), tokens));
    };
    if kw != "crate" || eq.as_char() != '=' {
        return Ok((quote::quote!(::mechanism), tokens));
    }
    let comma = rest
        .iter()
        .position(|t| matches!(t, TokenTree::Punct(p) if p.as_char() == ','))
        .ok_or_else(|| {
            syn::Error::new(eq.span(), "expected `crate = path,` before the declaration")
        })?;
    let path: TokenStream = rest[..comma].iter().cloned().collect();
    if path.is_empty() {
        return Err(syn::Error::new(
            eq.span(),
            "expected a path after `crate =`",
        ));
    }
    Ok((path, rest[comma + 1..].iter().cloned().collect()))
}

/// Parses the macro input.
pub fn parse(tokens: TokenStream) -> syn::Result<Declaration> {
    let (krate, tokens) = crate_path(tokens)?;
    let mut decl = match file_literal(&tokens) {
        Some(literal) => parse_file(literal?)?,
        None => parse_inline(tokens)?,
    };
    decl.krate = krate;
    Ok(decl)
}

/// The declaration written inline: every error of the parser's checks, combined.
fn parse_inline(tokens: TokenStream) -> syn::Result<Declaration> {
    match mechanism_codegen::parse_declaration(tokens) {
        Ok(parsed) => Ok(Declaration {
            model: parsed.model,
            spans: parsed.spans,
            source: Source::Inline,
            krate: TokenStream::new(),
        }),
        Err(errors) => Err(combine(
            errors.iter().map(|e| syn::Error::new(e.span, e.message())),
        )),
    }
}

/// One error holding all of `errors` (the user sees every mistake at once).
pub fn combine(errors: impl IntoIterator<Item = syn::Error>) -> syn::Error {
    let mut errors = errors.into_iter();
    let mut first = errors
        .next()
        .unwrap_or_else(|| syn::Error::new(Span::call_site(), "the declaration could not be read"));
    for e in errors {
        first.combine(e);
    }
    first
}

/// The declaration read from a file: relative to `CARGO_MANIFEST_DIR` (the documented
/// rule), or else relative to the directory of the source file holding the invocation (as
/// `include_str!` resolves; it lets a test case sit next to its `.mech` file).
fn parse_file(literal: LitStr) -> syn::Result<Declaration> {
    let relative = literal.value();
    let root = std::env::var_os("CARGO_MANIFEST_DIR")
        .map(PathBuf::from)
        .unwrap_or_default();
    // The invoking file's path may be relative to rustc's working directory (cargo passes
    // `src/lib.rs`): make it absolute, or `include_str!` in the expansion would resolve it
    // against the invoking file's directory a second time (`src/src/...`).
    let cwd = std::env::current_dir().unwrap_or_default();
    let beside = literal
        .span()
        .local_file()
        .and_then(|f| f.parent().map(|d| cwd.join(d).join(&relative)));
    let candidates = std::iter::once(root.join(&relative)).chain(beside);
    let mut first_error = None;
    for path in candidates {
        match std::fs::read_to_string(&path) {
            Ok(text) => {
                let path = std::fs::canonicalize(&path).unwrap_or(path);
                return parse_text(literal, path, &text);
            }
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    let reason = first_error.map(|e| e.to_string()).unwrap_or_default();
    Err(syn::Error::new(
        literal.span(),
        format!(
            "cannot read mechanism file `{relative}` (paths are relative to CARGO_MANIFEST_DIR): {reason}"
        ),
    ))
}

/// Parses the text of a mechanism file read from `path`.
fn parse_text(literal: LitStr, path: PathBuf, text: &str) -> syn::Result<Declaration> {
    match mechanism_codegen::parse_declaration_str(text) {
        Ok(parsed) => Ok(Declaration {
            model: parsed.model,
            spans: parsed.spans,
            source: Source::File { literal, path },
            krate: TokenStream::new(),
        }),
        Err(errors) => Err(combine(
            errors
                .iter()
                .map(|e| file_error(&literal, e.location(), &message(e))),
        )),
    }
}

/// An error in a file: at the literal, prefixed with `file:line:column:`.
fn file_error(literal: &LitStr, location: Option<Location>, message: &str) -> syn::Error {
    let file = literal.value();
    let text = match location {
        Some(l) => format!("{file}:{}:{}: {message}", l.line, l.column),
        None => format!("{file}: {message}"),
    };
    syn::Error::new(literal.span(), text)
}

/// The location a codegen error carries, if any.
pub fn location(error: &Error) -> Option<Location> {
    error.location()
}

/// The error's message without its `at line .., column ..` (the span or the
/// `file:line:column:` prefix says where).
pub fn message(error: &Error) -> String {
    SpannedError::from(error.clone()).message()
}
