//! The declaration language: expression and model parsing (with the library and the seed),
//! the errors a user sees, and the text and LaTeX printers (round trip included).

mod parse_support;

mod declared_physics;
mod parse_expr_table;
mod parse_model_errors;
mod parse_model_library;
mod parse_model_seed;
mod pretty_equations;
mod pretty_latex;
mod pretty_roundtrip;
mod unconstrained;
