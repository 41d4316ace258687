//! The macro's input: the declaration's tokens, a `.mech` file, or a URDF file imported
//! as declaration text, parsed into a [`Model`], with every error mapped to a span the
//! user can click.

use std::path::PathBuf;

use mechanism_codegen::{Error, Location, Model, ModelSpans, SpannedError, UrdfOptions};
use proc_macro2::{Span, TokenStream, TokenTree};
use syn::parse::{ParseStream, Parser};
use syn::punctuated::Punctuated;
use syn::{Ident, LitStr, Token};

/// Where the declaration came from.
pub enum Source {
    /// Written inline: errors point at the offending token.
    Inline,
    /// `file = "mechanisms/x.mech"`: errors point at the literal and quote `file:line:column`.
    /// `urdf = "robot.urdf"`: the same, the line and column being those of the imported
    /// declaration text.
    File {
        /// The string literal as written (its span receives every error).
        literal: LitStr,
        /// The absolute path that was read (for `include_str!`, so edits trigger a rebuild).
        path: PathBuf,
        /// Whether the file is a URDF, whose declaration text was written by the importer.
        urdf: bool,
        /// The declaration text (the file's, or the importer's for a URDF): an error quotes
        /// its line.
        text: String,
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
            Source::File {
                literal,
                urdf,
                text,
                ..
            } => file_error(literal, (*urdf, text), location, message),
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

/// `urdf = "robot.urdf"`, with an optional `lock = ["joint", ...]`, `name = Struct`,
/// `damping = true`, `snap_angles = 1e-9` and `floating = true` after it.
struct UrdfInput {
    /// The path as written.
    literal: LitStr,
    /// The URDF joints locked at q = 0.
    lock: Vec<String>,
    /// The struct name, when given.
    name: Option<Ident>,
    /// `damping = true`: the joints' `<dynamics damping>` as forces.
    damping: bool,
    /// `snap_angles = 1e-9`: angles within this many rad of a multiple of pi/2 written as
    /// one.
    snap_angles: Option<f64>,
    /// `floating = true`: the root link on a free-flyer joint.
    floating: bool,
}

/// `urdf = "..."` and its options, recognised by its first two tokens.
fn urdf_input(tokens: &TokenStream) -> Option<syn::Result<UrdfInput>> {
    let trees: Vec<TokenTree> = tokens.clone().into_iter().collect();
    match trees.as_slice() {
        [TokenTree::Ident(kw), TokenTree::Punct(eq), rest @ ..]
            if kw == "urdf" && eq.as_char() == '=' =>
        {
            let rest: TokenStream = rest.iter().cloned().collect();
            Some(parse_urdf_options.parse2(rest))
        }
        _ => None,
    }
}

/// `"robot.urdf" [, lock = ["a", "b"]] [, name = Struct] [, damping = true]
/// [, snap_angles = 1e-9] [, floating = true] [,]`.
fn parse_urdf_options(input: ParseStream) -> syn::Result<UrdfInput> {
    let mut urdf = UrdfInput {
        literal: input.parse()?,
        lock: Vec::new(),
        name: None,
        damping: false,
        snap_angles: None,
        floating: false,
    };
    while !input.is_empty() {
        input.parse::<Token![,]>()?;
        if input.is_empty() {
            break;
        }
        let key: Ident = input.parse()?;
        input.parse::<Token![=]>()?;
        if key == "lock" {
            let content;
            syn::bracketed!(content in input);
            let joints = Punctuated::<LitStr, Token![,]>::parse_terminated(&content)?;
            urdf.lock.extend(joints.iter().map(LitStr::value));
        } else if key == "name" {
            urdf.name = Some(input.parse()?);
        } else if key == "damping" {
            urdf.damping = input.parse::<syn::LitBool>()?.value;
        } else if key == "snap_angles" {
            urdf.snap_angles = Some(snap_tolerance(input)?);
        } else if key == "floating" {
            urdf.floating = input.parse::<syn::LitBool>()?.value;
        } else {
            return Err(syn::Error::new(
                key.span(),
                "expected `lock = [\"joint\", ...]`, `name = Struct`, `damping = true`, \
                 `snap_angles = 1e-9` or `floating = true` after the URDF path",
            ));
        }
    }
    Ok(urdf)
}

/// The tolerance of `snap_angles = ...`: a number literal from 0 to
/// [`mechanism_codegen::MAX_SNAP_ANGLES`] rad, refused at the literal otherwise.
fn snap_tolerance(input: ParseStream) -> syn::Result<f64> {
    let lit: syn::Lit = input.parse()?;
    let value = match &lit {
        syn::Lit::Float(f) => f.base10_parse::<f64>()?,
        syn::Lit::Int(i) => i.base10_parse::<f64>()?,
        _ => {
            return Err(syn::Error::new(
                lit.span(),
                "expected a tolerance in rad, such as `snap_angles = 1e-9`",
            ));
        }
    };
    let max = mechanism_codegen::MAX_SNAP_ANGLES;
    if !(0.0..=max).contains(&value) {
        return Err(syn::Error::new(
            lit.span(),
            format!("the angle snapping tolerance must be between 0 and {max} rad"),
        ));
    }
    Ok(value)
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
    let mut decl = match (file_literal(&tokens), urdf_input(&tokens)) {
        (Some(literal), _) => parse_file(literal?)?,
        (None, Some(urdf)) => parse_urdf(urdf?)?,
        (None, None) => parse_inline(tokens)?,
    };
    decl.krate = krate;
    Ok(decl)
}

/// The declaration written inline: every error of the parser's checks, combined.
fn parse_inline(tokens: TokenStream) -> syn::Result<Declaration> {
    match mechanism_codegen::parse_declaration_with(tokens, budget()?) {
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

/// The derivation's budget: the defaults, or the environment variables
/// `MECHANISM_MAX_SIZE`, `MECHANISM_MAX_ENTRIES` and `MECHANISM_MAX_WORK` of the build (the
/// macro is the boundary that reads them; codegen takes the value).
fn budget() -> syn::Result<mechanism_codegen::Budget> {
    mechanism_codegen::Budget::from_lookup(|name| std::env::var(name).ok())
        .map_err(|e| syn::Error::new(Span::call_site(), e))
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

/// The declaration read from a file: see [`read_relative`].
fn parse_file(literal: LitStr) -> syn::Result<Declaration> {
    let (path, text) = read_relative(&literal, "mechanism")?;
    parse_text(literal, path, &text, false)
}

/// The declaration imported from a URDF file ([`read_relative`]) by
/// [`mechanism_codegen::urdf_to_mech`]; a refused URDF is one error at the literal, its
/// message the importer's one line (`robot.urdf:12:3: <joint name="x">: ...`).
fn parse_urdf(urdf: UrdfInput) -> syn::Result<Declaration> {
    let (path, xml) = read_relative(&urdf.literal, "URDF")?;
    let options = UrdfOptions {
        file_name: urdf.literal.value(),
        struct_name: urdf.name.map(|n| n.to_string()),
        lock: urdf.lock,
        damping: urdf.damping,
        snap_angles: urdf.snap_angles,
        floating: urdf.floating,
    };
    let text = mechanism_codegen::urdf_to_mech(&xml, &options)
        .map_err(|e| syn::Error::new(urdf.literal.span(), e.to_string()))?;
    parse_text(urdf.literal, path, &text, true)
}

/// The text of the file `literal` names (a `kind` file: mechanism or URDF), relative to
/// `CARGO_MANIFEST_DIR` (the documented rule), or else relative to the directory of the
/// source file holding the invocation (as `include_str!` resolves; it lets a test case sit
/// next to its file). Returns the canonical path read and the text.
fn read_relative(literal: &LitStr, kind: &str) -> syn::Result<(PathBuf, String)> {
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
                return Ok((path, text));
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
            "cannot read {kind} file `{relative}` (paths are relative to CARGO_MANIFEST_DIR): {reason}"
        ),
    ))
}

/// Parses the declaration text of a file read from `path` (imported from a URDF when
/// `urdf`).
fn parse_text(literal: LitStr, path: PathBuf, text: &str, urdf: bool) -> syn::Result<Declaration> {
    match mechanism_codegen::parse_declaration_str_with(text, budget()?) {
        Ok(parsed) => Ok(Declaration {
            model: parsed.model,
            spans: parsed.spans,
            source: Source::File {
                literal,
                path,
                urdf,
                text: text.to_string(),
            },
            krate: TokenStream::new(),
        }),
        Err(errors) => {
            Err(combine(errors.iter().map(|e| {
                file_error(&literal, (urdf, text), e.location(), &message(e))
            })))
        }
    }
}

/// An error in a file: at the literal, prefixed with `file:line:column:`, or for a URDF
/// (whose declaration text the importer wrote, so the URDF's lines do not apply) with
/// `file: in the imported declaration, line L, column C:` (`mechanism import` writes that
/// text to read); then the line of `text` it is in, with a caret under the column, as
/// rustc quotes a line:
///
/// ```text
/// broken.mech:8:20: parse error: expected a number, a name or `(`, found `;`
/// 8 | potential = m*g*y +;
///   |                    ^
/// ```
fn file_error(
    literal: &LitStr,
    (urdf, text): (bool, &str),
    location: Option<Location>,
    message: &str,
) -> syn::Error {
    let file = literal.value();
    let mut out = match (location, urdf) {
        (Some(l), false) => format!("{file}:{}:{}: {message}", l.line, l.column),
        (Some(l), true) => format!(
            "{file}: in the imported declaration (`mechanism import {file}`), line {}, column {}: {message}",
            l.line, l.column
        ),
        (None, _) => format!("{file}: {message}"),
    };
    if let Some(quote) = location.and_then(|l| quote_line(text, l)) {
        out.push('\n');
        out.push_str(&quote);
    }
    syn::Error::new(literal.span(), out)
}

/// Line `l.line` of `text` (1-based) after its number, and a caret under column `l.column`
/// (1-based, in characters; tabs kept so the caret lines up); `None` past the text's end.
fn quote_line(text: &str, l: Location) -> Option<String> {
    let line = text.lines().nth(l.line.checked_sub(1)?)?.trim_end();
    let number = l.line.to_string();
    let pad = " ".repeat(number.len());
    let indent: String = line
        .chars()
        .take(l.column.saturating_sub(1))
        .map(|c| if c == '\t' { '\t' } else { ' ' })
        .collect();
    Some(format!("{number} | {line}\n{pad} | {indent}^"))
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_error_quotes_its_line_with_a_caret_under_the_column() {
        let text = "parameters { g = 9.81; }\n\tpotential = m*g*;\n";
        let at = |line, column| Location {
            line,
            column,
            token: None,
        };
        // Column 17 is the `;` (the tab is one character).
        assert_eq!(
            quote_line(text, at(2, 17)).unwrap(),
            "2 | \tpotential = m*g*;\n  | \t               ^"
        );
        assert_eq!(quote_line(text, at(3, 1)), None);
        assert_eq!(quote_line(text, at(0, 1)), None);
    }

    /// The importer's test arm, from this crate's manifest folder.
    const ARM: &str = "../codegen/tests/urdf/arm.urdf";

    #[test]
    fn urdf_options_are_read() {
        let tokens: TokenStream =
            format!(r#"urdf = "{ARM}", lock = ["slide", "shoulder"], name = Arm, damping = true,"#)
                .parse()
                .unwrap();
        let urdf = urdf_input(&tokens).expect("recognised").expect("parsed");
        assert_eq!(urdf.literal.value(), ARM);
        assert_eq!(urdf.lock, ["slide", "shoulder"]);
        assert_eq!(urdf.name.map(|n| n.to_string()).as_deref(), Some("Arm"));
        assert!(urdf.damping);
        let tokens: TokenStream = format!(r#"urdf = "{ARM}""#).parse().unwrap();
        assert!(!urdf_input(&tokens).unwrap().unwrap().damping);
        let tokens: TokenStream = format!(r#"urdf = "{ARM}", damping = 1"#).parse().unwrap();
        let e = urdf_input(&tokens).unwrap().err().expect("refused");
        assert!(e.to_string().contains("expected boolean literal"), "{e}");
        let tokens: TokenStream = format!(r#"urdf = "{ARM}", locked = []"#).parse().unwrap();
        let e = urdf_input(&tokens)
            .expect("recognised")
            .err()
            .expect("refused");
        assert!(e.to_string().contains("expected `lock = "), "{e}");
        let tokens: TokenStream = "pub struct X;".parse().unwrap();
        assert!(urdf_input(&tokens).is_none());
    }

    #[test]
    fn a_snap_tolerance_is_read_and_checked_at_its_literal() {
        let read = |option: &str| {
            let tokens: TokenStream = format!(r#"urdf = "{ARM}", {option}"#).parse().unwrap();
            urdf_input(&tokens).expect("recognised")
        };
        assert_eq!(read("snap_angles = 1e-9").unwrap().snap_angles, Some(1e-9));
        assert_eq!(read("snap_angles = 0").unwrap().snap_angles, Some(0.0));
        assert_eq!(read("damping = true").unwrap().snap_angles, None);
        for (option, message) in [
            ("snap_angles = 0.5", "between 0 and 0.001 rad"),
            ("snap_angles = \"1e-9\"", "expected a tolerance in rad"),
        ] {
            let e = read(option).err().expect("refused");
            assert!(e.to_string().contains(message), "{option}: {e}");
        }
    }

    #[test]
    fn a_refused_urdf_is_the_importers_line_at_the_path() {
        let tokens: TokenStream = format!(r#"urdf = "{ARM}", lock = ["elbow"]"#)
            .parse()
            .unwrap();
        let e = parse(tokens).err().expect("refused");
        let text = e.to_string();
        assert!(
            text.starts_with(&format!(
                "{ARM}:5:1: <robot name=\"test_arm\">: cannot lock \"elbow\""
            )),
            "{text}"
        );
        let tokens: TokenStream = r#"urdf = "no/such.urdf""#.parse().unwrap();
        let e = parse(tokens).err().expect("refused");
        assert!(
            e.to_string()
                .contains("cannot read URDF file `no/such.urdf`"),
            "{e}"
        );
    }
}
