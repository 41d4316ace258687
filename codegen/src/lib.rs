//! # mechanism-codegen
//!
//! The computer-algebra core of `mechanism`. A declaration of a mechanism (coordinates q,
//! parameters, kinetic energy T or rigid bodies, potential Pi, constraints Phi(q, t) = 0,
//! forces tau) becomes its Lagrange equations with multipliers
//!
//! ```text
//! M(q) q'' + C(q, q') q' + g(q) + Phi_q^T lambda = tau(t, q, q'),   Phi_q q'' = gamma
//! ```
//!
//! derived symbolically (Van Khang's matrix calculus with Kronecker products), then compiled
//! into one straight-line program per routine (common subexpressions shared, parameter-only
//! values cached), which is emitted as Rust or interpreted; the equations print as text or
//! LaTeX.
//!
//! ## Example
//!
//! ```
//! use mechanism_codegen::{derive, parse_model_str, to_text};
//!
//! let mut model = parse_model_str(
//!     "pub struct Pendulum;
//!      parameters { m = 1.0; l = 0.5; g = 9.81; }
//!      coordinates { phi = 0.1; }
//!      independent { phi = 0.1; der(phi) = 0.0; }
//!      kinetic = 1/2*m*l^2*der(phi)^2;
//!      potential = -m*g*l*cos(phi);",
//! )?;
//! let eqs = derive(&mut model)?;
//! // M = d2T/dphi'^2 and g = dPi/dphi.
//! assert_eq!(to_text(&model.arena, eqs.mass.get(0, 0)), "m*l^2");
//! assert_eq!(to_text(&model.arena, eqs.gravity.get(0, 0)), "m*l*g*sin(phi)");
//! # Ok::<(), mechanism_codegen::Error>(())
//! ```
//!
//! ## The stages
//!
//! Each stage is a folder and imports only the stages above it in this list; `syntax/` and
//! `algebra/` are leaves that share only [`Error`] and [`Number`]:
//!
//! - `algebra/`: the expression arena ([`Arena`], [`Id`]), differentiation
//!   ([`Differentiator`]), symbolic [`Matrix`] values with Khang's derivative, rotations,
//!   numeric evaluation ([`eval`]).
//! - `syntax/`: tokens and the declaration grammar; syntax trees only.
//! - `mechanics/`: names resolved into the arena, the checked [`Model`], bodies and joints,
//!   [`derive()`] ([`Equations`]) and the implicit integrators' tangent
//!   ([`residual_tangent`]).
//! - `program/`: the [`Program`] and its passes (instruction selection with
//!   common-subexpression elimination, factoring, scaling, fusion, scheduling, hoisting),
//!   and the [`Tape`] interpreter.
//! - `compile/`: [`compile()`] runs the passes in one order and turns [`Equations`] into
//!   [`Routines`]: a program per [`Role`], the parameter cache, and the [`Sources`] table of
//!   where each symbol's value comes from. The macro emits and the interpreter runs these.
//! - `emit/`: a program as Rust tokens ([`emit_body`]).
//! - `print/`: text ([`to_text`], [`equations_text`]) and LaTeX ([`equations_latex`]).
//! - `urdf/`: a front end before `syntax/`, importing nothing of the others: a URDF robot
//!   description as declaration text ([`urdf_to_mech`]).
//!
//! [`parse_declaration`] and [`parse_model_str`] run syntax, checks and model building in
//! order, reporting every mistake in a declaration at once; [`error`] holds what each
//! mistake carries.
//!
//! The handles ([`Id`], [`SymbolId`]) and [`Matrix`] are opaque: indices and entries are
//! read through methods, so a matrix always has rows x cols entries.
#![warn(missing_docs)]

mod algebra;
mod compile;
mod emit;
pub mod error;
#[cfg(any(test, feature = "fixtures"))]
pub mod fixtures;
mod mechanics;
mod number;
mod pipeline;
mod print;
mod program;
mod syntax;
mod urdf;

// The public surface: what the macro, the runtime, the benches and emit-check use, and the
// types their signatures name. Everything else is crate-private or, for codegen's own tests,
// in the hidden `internals`.
pub use algebra::budget::{
    BUDGET_VARIABLES, Budget, Effort, MAX_ENTRIES, MAX_SIZE, MAX_WORK, PROGRESS_EVERY,
};
pub use algebra::diff::Differentiator;
pub use algebra::eval::{eval, eval_matrix};
pub use algebra::expr::{Arena, Func, Id, Node, Operands, Symbol, SymbolId, SymbolKind};
pub use algebra::matrix::Matrix;
pub use compile::{
    Role, Routines, Source, Sources, Sparsity, Tangents, compile, compile_constraints,
    compile_floating, compile_floating_with_derivatives, compile_forward_dynamics,
    compile_interpreted, compile_robotics, dense_kkt_operations,
};
pub use emit::body::{EmitBindings, EmittedBody, LEAN_ABOVE, OutputTarget, emit_body, f64_tokens};
pub use error::{Error, Location, Result};
pub use mechanics::build::{ModelSpans, ParsedModel};
pub use mechanics::derivation::{derive, derive_with};
pub use mechanics::drawing::{Drawing, DrawnPoint};
pub use mechanics::dynamics_derivatives::{
    InverseDynamicsDerivatives, inverse_dynamics_derivative_forms,
};
pub use mechanics::equations::{Equations, EvaluationOutput, FrameEquations};
pub use mechanics::floating::FloatingRoot;
pub use mechanics::lagrange::Route;
pub use mechanics::model::{
    Constraint, Coordinate, IndependentSpec, Model, Parameter, ParameterRange, RotationSequence,
};
pub use mechanics::resolve::parse_expr;
pub use mechanics::tangent::{
    ConstraintTangent, ResidualTangent, constraint_tangent, full_tangent, residual_tangent,
};
pub use mechanics::tree::{DeclaredLimits, Link, LinkJoint, declared_limits};
pub use number::Number;
pub use pipeline::{
    SpannedError, check_parameter_values, parse_declaration, parse_declaration_str,
    parse_declaration_str_with, parse_declaration_with, parse_model_str, parse_model_str_at,
    parse_model_str_with,
};
pub use print::latex::equations_latex;
pub use print::text::{equations_text, to_text};
pub use program::cse::Program;
pub use program::hoist::{Hoisted, hoist_parameters};
pub use program::instructions::{OpCounts, Operand, Output};
pub use program::tape::Tape;
pub use syntax::spelling::closest;
pub use urdf::{
    MAX_SNAP_ANGLES, SnappedAngles, UrdfError, UrdfImport, UrdfOptions, urdf_import, urdf_to_mech,
};

/// The parts of the stages that no dependent needs, reached only by codegen's own tests (the
/// second routes they check against, the printers of single matrices, the instructions of a
/// program): hidden, not part of the API, free to change.
#[doc(hidden)]
pub mod internals {
    pub use crate::algebra::eval::eval_many;
    pub use crate::algebra::expr::Vec3;
    pub use crate::algebra::rotation::{Axis, Orientation, RotationFactor, elementary_rotation};
    pub use crate::emit::body::BLOCK_LETS_ABOVE;
    pub use crate::mechanics::bodies::{
        Body, BodySystem, BodyTerms, Damper, Spring, add_body_terms, body_terms,
    };
    pub use crate::mechanics::joints::{
        AxisFrame, distance, parallel, prismatic, revolute, spherical,
    };
    pub use crate::mechanics::lagrange::{
        christoffel_coriolis_forces, christoffel_coriolis_matrix,
    };
    pub use crate::mechanics::recursive::frame_jacobian;
    pub use crate::mechanics::tangent::lambda_symbol_name;
    pub use crate::pipeline::parse_model;
    pub use crate::print::latex::{matrix_to_latex, to_latex};
    pub use crate::print::text::matrix_to_text;
    pub use crate::program::instructions::{BinOp, Instr, Reg, UnOp};
}
