//! # mechanism-codegen
//!
//! The computer-algebra core of `mechanism`: a hash-consed expression DAG with canonical
//! forms, a parser, differentiation (including Van Khang's matrix derivative and its
//! Theorems 1-2 with Kronecker products), Lagrange assembly with multipliers, common
//! subexpression elimination, Rust emission, an interpreter and a pretty printer.
#![warn(missing_docs)]

mod bodies;
mod build_model;
mod chain;
mod check;
mod cse;
mod declaration;
mod diff;
mod emit;
mod equations;
mod error;
mod eval;
mod expr;
mod joints;
mod lagrange;
mod latex;
mod lex;
mod liveness;
mod lower;
mod lower_bodies;
mod matrix;
mod model;
mod number;
mod parse;
mod parse_bodies;
mod pretty;
mod render;
mod rotation;
mod tangent;
mod tape;
pub mod trig;
mod vexpr;

pub use bodies::{Body, BodySystem, BodyTerms, Damper, Spring, Vec3, add_body_terms, body_terms};
pub use build_model::{
    ModelSpans, ParsedModel, SpannedError, parse_declaration, parse_declaration_str, parse_model,
    parse_model_str,
};
pub use chain::{closed_chain_arch, closed_chain_model, closed_chain_source};
pub use cse::{BinOp, Instr, OpCounts, Operand, Output, Program, Reg, UnOp};
pub use diff::Differentiator;
pub use emit::{BLOCK_LETS_ABOVE, EmitBindings, EmittedBody, OutputTarget, emit_body, f64_tokens};
pub use equations::Equations;
pub use error::{Error, Location, Result};
pub use eval::{eval, eval_many, eval_matrix};
pub use expr::{Arena, Func, FxHashMap, FxHasher, Id, Node, Symbol, SymbolId, SymbolKind};
pub use joints::{AxisFrame, distance, parallel, prismatic, revolute, spherical};
pub use lagrange::{christoffel_coriolis_forces, christoffel_coriolis_matrix, derive};
pub use latex::{equations_latex, matrix_to_latex, to_latex};
pub use matrix::Matrix;
pub use model::{Constraint, Coordinate, IndependentSpec, Model, Parameter};
pub use number::Number;
pub use parse::parse_expr;
pub use pretty::{equations_text, matrix_to_text, to_text};
pub use rotation::{Axis, Orientation, RotationFactor, elementary_rotation};
pub use tangent::{ResidualTangent, lambda_symbol_name, residual_tangent};
pub use tape::Tape;
