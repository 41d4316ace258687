//! The first-order rounding-error bound of codegen's eval tests (one file, shared).
#[path = "../../../codegen/tests/eval_support/rounding.rs"]
mod rounding;
pub use rounding::*;
