//! The first-order rounding-error bound of codegen's eval tests (one file, shared).
#[path = "../../../codegen/tests/derivation/rounding.rs"]
mod rounding;
pub use rounding::*;
