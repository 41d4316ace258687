//! # mechanism-codegen
//!
//! The computer-algebra core of `mechanism`: a hash-consed expression DAG with canonical
//! forms, a parser, differentiation (including Van Khang's matrix derivative and its
//! Theorems 1-2 with Kronecker products), Lagrange assembly with multipliers, common
//! subexpression elimination, Rust emission, an interpreter and a pretty printer.
#![warn(missing_docs)]

mod algebra;
mod emit;
mod error;
#[cfg(any(test, feature = "fixtures"))]
pub mod fixtures;
mod mechanics;
mod pipeline;
mod print;
mod program;
mod syntax;

pub use algebra::diff::Differentiator;
pub use algebra::eval::{eval, eval_many, eval_matrix};
pub use algebra::expr::{Arena, Func, FxHashMap, FxHasher, Id, Node, Symbol, SymbolId, SymbolKind};
pub use algebra::matrix::Matrix;
pub use algebra::number::Number;
pub use algebra::rotation::{Axis, Orientation, RotationFactor, elementary_rotation};
pub use algebra::trig;
pub use emit::body::{
    BLOCK_LETS_ABOVE, EmitBindings, EmittedBody, OutputTarget, emit_body, f64_tokens,
};
pub use error::{Error, Location, Result};
pub use mechanics::bodies::{
    Body, BodySystem, BodyTerms, Damper, Spring, Vec3, add_body_terms, body_terms,
};
pub use mechanics::build::{ModelSpans, ParsedModel};
pub use mechanics::equations::{Equations, EvaluationOutput};
pub use mechanics::joints::{AxisFrame, distance, parallel, prismatic, revolute, spherical};
pub use mechanics::lagrange::{christoffel_coriolis_forces, christoffel_coriolis_matrix, derive};
pub use mechanics::model::{Constraint, Coordinate, IndependentSpec, Model, Parameter};
pub use mechanics::resolve::parse_expr;
pub use mechanics::tangent::{ResidualTangent, lambda_symbol_name, residual_tangent};
pub use pipeline::{
    SpannedError, parse_declaration, parse_declaration_str, parse_model, parse_model_str,
};
pub use print::latex::{equations_latex, matrix_to_latex, to_latex};
pub use print::text::{equations_text, matrix_to_text, to_text};
pub use program::cse::{Output, Program};
pub use program::instructions::{BinOp, Instr, OpCounts, Operand, Reg, UnOp};
pub use program::tape::Tape;
