//! Print: expressions, matrices and derived equations as text and LaTeX.
//!
//! Enters: arena expressions, a [`Model`](crate::Model) and its
//! [`Equations`](crate::Equations). Leaves: strings. [`render`] walks the reachable sub-DAG
//! bottom-up in id order, so each shared node is rendered once; it puts the positive terms
//! of a sum first, a product's coefficient first and negative powers below one fraction bar.
//! [`text`] spells that in the expression language itself, so that
//! `parse_expr(arena, &to_text(arena, e)) == e`; [`latex`] spells it for LaTeX.

pub(crate) mod latex;
pub(crate) mod render;
pub(crate) mod text;
