//! What can be wrong with the text of a declaration or an expression (the `syntax` stage):
//! the kinds of [`Error::Parse`](super::Error::Parse).

use thiserror::Error;

/// Why a text does not follow the grammar. `found` fields describe the offending token as
/// it reads in a message (`` `}` ``, `the end of the input`).
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[non_exhaustive]
pub enum ParseError {
    /// A token other than one the grammar allows here.
    #[error("expected {expected}, found {found}")]
    Expected {
        /// What the grammar allows.
        expected: Expected,
        /// The token found.
        found: String,
    },
    /// The lexer stopped: an unbalanced bracket, an unterminated string, a stray character.
    #[error(
        "the text cannot be read from here on ({reason}): look for a bracket that is not closed or not opened, an unterminated string, or a character the language does not use"
    )]
    Unreadable {
        /// The lexer's own words.
        reason: String,
    },
    /// Parentheses, signs or exponents nested deeper than the parser's limit.
    #[error("the expression is nested too deeply, found {found}")]
    TooDeep {
        /// The token where the limit was reached.
        found: String,
    },
    /// `x**2`.
    #[error("powers are written `x^2` (not `x**2`), found `*`")]
    DoubleStar,
    /// `^` with nothing on its left.
    #[error("`^` needs a base on its left, found `^`")]
    CaretWithoutBase,
    /// A string or character literal where a number belongs.
    #[error("expected a number, found the literal {literal}")]
    NotANumber {
        /// The literal as written.
        literal: String,
    },
    /// A literal that is not a number of the language (a type suffix, hex, ...).
    #[error(
        "`{literal}` is not a number of the language (write e.g. 2, 0.04 or 1e-4, without a type suffix)"
    )]
    BadNumber {
        /// The literal as written.
        literal: String,
    },
    /// A number beyond the range of f64.
    #[error("`{literal}` is too large for a 64-bit float")]
    NumberTooLarge {
        /// The literal as written.
        literal: String,
    },
    /// A call with the wrong number of arguments.
    #[error("`{function}` takes {expected} argument{}, found {found}", if *.expected == 1 { "" } else { "s" })]
    Arity {
        /// The function.
        function: String,
        /// Its arity.
        expected: usize,
        /// Arguments written.
        found: usize,
    },
    /// `[]`.
    #[error("a vector needs at least one entry")]
    EmptyVector,
    /// `[]` as a constraint statement (`found` is the token after it).
    #[error("a vector constraint needs at least one entry, found {found}")]
    EmptyVectorConstraint {
        /// The token after `[]`.
        found: String,
    },
    /// `[a, b] = c`.
    #[error("a vector constraint `[a, b, c] = [..]` needs a vector on the right, found {found}")]
    ScalarRightOfVector {
        /// The token after `=`.
        found: String,
    },
    /// `[a, b] = [c, d, e]`.
    #[error(
        "the two sides of a vector constraint differ in length: {left} on the left, {right} on the right"
    )]
    VectorLengths {
        /// Entries on the left.
        left: usize,
        /// Entries on the right.
        right: usize,
    },
    /// A vector form (`[..]`, `.x`) inside a scalar expression.
    #[error("a vector form (`[..]` or `.x`) in a scalar expression")]
    VectorInScalar,
    /// An attribute other than a doc comment before the struct line.
    #[error(
        "only doc comments (`/// text`) may come before the struct line; expected `doc`, found {found}"
    )]
    NotADocComment {
        /// The token where `doc` was expected.
        found: String,
    },
    /// `#[doc = ]` without its text.
    #[error("expected the doc text")]
    MissingDocText,
    /// `#[doc = 2]`.
    #[error("expected a string as the doc text")]
    DocNotAString,
    /// A declaration that does not start with `pub struct Name;`.
    #[error("a declaration starts with `pub struct Name;` (after its doc comment), found {found}")]
    NoStruct {
        /// The first token after the doc comment.
        found: String,
    },
    /// `struct` without a name.
    #[error("expected the struct name after `struct`")]
    NoStructName,
    /// A keyword that is not a section.
    #[error("`{name}` is not a section; expected one of {}{}", .sections.join(", "), did_you_mean(.suggestion))]
    UnknownSection {
        /// The word written.
        name: String,
        /// The section keywords.
        sections: &'static [&'static str],
        /// The closest section keyword, when one is near.
        suggestion: Option<String>,
    },
    /// A section written twice.
    #[error("the section `{section}` appears twice; write all its entries in one block")]
    DuplicateSection {
        /// The section keyword.
        section: String,
    },
    /// A key a body, spring or damper block does not have.
    #[error("`{key}` is not an entry of a {block}; expected one of {}", .keys.join(", "))]
    UnknownEntry {
        /// The key written.
        key: String,
        /// `body`, `spring` or `damper`.
        block: String,
        /// The keys the block has.
        keys: &'static [&'static str],
    },
    /// A link's joint of a kind the language does not have.
    #[error(
        "unknown joint `{found}`: a link's joint is `fixed`, `revolute`, `continuous` or `prismatic` as `KIND(COORDINATE, [ax, ay, az])`, or `floating(NAME)` on a root link"
    )]
    UnknownJoint {
        /// The word written.
        found: String,
    },
    /// A statement of `draw` that is neither `line` nor `trace`.
    #[error("`{found}` is not a statement of `draw`; expected `line A, B, ..;` or `trace A, ..;`")]
    NotADrawStatement {
        /// The word written.
        found: String,
    },
    /// `line A;`: a line through one point.
    #[error("a `line` joins at least two points: `line A, B;`")]
    ShortLine,
    /// A word after a parameter's default that is not a range (`l = 0.3 m;`).
    #[error(
        "`{word}` after the default of `{name}` is not a range: a parameter's value may be followed by `positive` or `nonnegative`, then `;`{}",
        did_you_mean(suggestion)
    )]
    NotARange {
        /// The word written.
        word: String,
        /// The parameter.
        name: String,
        /// The range the word most likely misspells.
        suggestion: Option<String>,
    },
}

/// What the grammar allows where a [`ParseError::Expected`] was raised.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
#[non_exhaustive]
pub enum Expected {
    /// The start of an operand of the scalar language.
    #[error("a number, a name or `(`")]
    Operand,
    /// The start of an operand of the vector language.
    #[error("a number, a name, `(` or `[`")]
    VectorOperand,
    /// `)` closing a parenthesis.
    #[error("`)` or an operator")]
    CloseParen,
    /// The rest of a function's argument list.
    #[error("`,` or `)` after a function argument")]
    ArgumentSeparator,
    /// The rest of a vector.
    #[error("`,` or `]` in a vector")]
    VectorSeparator,
    /// A component after `.`.
    #[error("`x`, `y` or `z` after `.`")]
    Component,
    /// The end of a lone expression.
    #[error("an operator or the end of the expression")]
    EndOfExpression,
    /// The `;` ending a statement.
    #[error("`;` or an operator")]
    Semicolon,
    /// The `;` ending the last statement of a block.
    #[error("`;` after the last statement of the block")]
    LastSemicolon,
    /// The `;` ending an energy.
    #[error("`;` or an operator after the {energy} energy")]
    EnergySemicolon {
        /// `kinetic` or `potential`.
        energy: String,
    },
    /// The `;` after `gravity = ..`.
    #[error("`;` after the gravity vector")]
    GravitySemicolon,
    /// The `;` after the struct name.
    #[error("`;` after the struct name")]
    StructSemicolon,
    /// `{` opening a section.
    #[error("`{{` opening the section")]
    OpenBrace,
    /// A section keyword.
    #[error("a section ({})", .sections.join(", "))]
    Section {
        /// The section keywords.
        sections: &'static [&'static str],
    },
    /// A name in a section.
    #[error("a name in `{section}`")]
    Name {
        /// The section (or entry) keyword.
        section: String,
    },
    /// `=` and a value after a declared name.
    #[error("`=` and a value after `{name}`")]
    Value {
        /// The name.
        name: String,
    },
    /// `=` and a value in `independent`.
    #[error("`=` and an initial value")]
    InitialValue,
    /// `=` after the words written.
    #[error("`=` after `{written}`")]
    EqualsAfter {
        /// What precedes `=` (`kinetic`, `point P`, `mass`, ...).
        written: String,
    },
    /// `:` after a force's coordinate.
    #[error("`:` after `{name}` (forces are written `coordinate: expression;`)")]
    ForceColon {
        /// The coordinate.
        name: String,
    },
    /// `)` after `der(name`.
    #[error("`)` after the coordinate")]
    CoordinateClose,
    /// `,` between the two ends of a spring or damper.
    #[error("`,` between the two points")]
    BetweenComma,
    /// `[` of an attribute.
    #[error("`[` of an attribute")]
    AttributeOpen,
    /// `=` in a doc attribute.
    #[error("`=` in a doc attribute")]
    DocEquals,
    /// `]` closing a doc attribute.
    #[error("`]` closing the doc attribute")]
    AttributeClose,
}

/// `"; did you mean `x`?"`, or nothing.
pub(crate) fn did_you_mean(suggestion: &Option<String>) -> String {
    match suggestion {
        Some(s) => format!("; did you mean `{s}`?"),
        None => String::new(),
    }
}
