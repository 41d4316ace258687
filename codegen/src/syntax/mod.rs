//! Syntax: from source text or a macro's token stream to syntax trees, and nothing else.
//!
//! Enters: a `proc_macro2::TokenStream` (the `mechanism!` input) or the text of a `.mech`
//! file. Leaves: a [`declaration::Declaration`] whose expressions are syntax trees
//! ([`ast::Ast`], scalar or, in the body sections, vector expressions), every node with its
//! [`Location`](crate::Location). No symbol is resolved
//! and no arena node is built here (that is the job of [`crate::mechanics`]): this stage
//! imports nothing of the others, only the shared `error` and `number` leaves.
//!
//! The algorithm is recursive descent over one flat token list ([`lex`]): both routes use
//! proc_macro2's tokenizer (plain text gets the same tokens from a direct lexer,
//! [`plain_lex`]), so a macro and a file have one grammar. Expressions bind, loosest
//! first, `+ -`, `* /`, unary `-`, `^` (right-associative, tighter than unary minus:
//! `-x^2 = -(x^2)`), parsed by one precedence-climbing parser for both expression languages
//! ([`expression`]); nesting deeper than [`MAX_DEPTH`] is an error, not a stack overflow.

/// Deepest nesting the expression parser accepts (parentheses, signs, exponents and the
/// operands of a chain together); deeper input is a parse error instead of a stack overflow.
pub(crate) const MAX_DEPTH: usize = 160;

pub(crate) mod ast;
pub(crate) mod bodies;
pub(crate) mod declaration;
pub(crate) mod draw;
pub(crate) mod expression;
pub(crate) mod lex;
pub(crate) mod links;
pub(crate) mod parameter_range;
pub(crate) mod plain_lex;
pub(crate) mod spelling;
pub(crate) mod unconstrained;
