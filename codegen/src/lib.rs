//! # mechanism-codegen
//!
//! The computer-algebra core of `mechanism`: a hash-consed expression DAG with canonical
//! forms, a parser, differentiation (including Van Khang's matrix derivative and its
//! Theorems 1-2 with Kronecker products), Lagrange assembly with multipliers, common
//! subexpression elimination, Rust emission, an interpreter and a pretty printer.
#![warn(missing_docs)]

mod equations;
mod error;
mod expr;
mod matrix;
mod model;
mod number;

pub use equations::Equations;
pub use error::{Error, Location, Result};
pub use expr::{Arena, Func, FxHashMap, FxHasher, Id, Node, Symbol, SymbolId, SymbolKind};
pub use number::Number;
pub use matrix::Matrix;
pub use model::{Constraint, Coordinate, IndependentSpec, Model, Parameter};
