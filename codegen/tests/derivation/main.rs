//! The calculus: differentiation rules and properties, evaluation against direct f64,
//! canonical forms, Van Khang's Theorems 1-2 and C, the Lagrange assembly on closed forms
//! and chains, CSE'd programs against the interpreter, and the emitter's calls of the real functions.

mod common;
mod eval_support;

mod chain_work_growth;
mod cse_props;
mod diff_props;
mod diff_rules;
mod emit_math;
mod eval_props;
mod expr_canonical;
mod khang_coriolis;
mod khang_theorems;
mod lagrange_chain;
mod lagrange_chain_timing;
mod lagrange_closed_forms;
