//! How emitted code reads each symbol of a program (`self.l1`, `q[2]`), which math module
//! computes its real functions, and how its registers are named.

use proc_macro2::TokenStream;

use crate::algebra::expr::{FxHashMap, SymbolId};

/// How the emitted code reads each symbol, and how it names its registers.
#[derive(Clone, Debug)]
pub struct EmitBindings {
    pub(super) reads: FxHashMap<SymbolId, TokenStream>,
    pub(super) prefix: String,
    /// The path of the math module (`::mechanism::math`); `None`: the f64 methods.
    pub(super) math: Option<TokenStream>,
    /// The value whose `sin_cos_lanes` method computes grouped sines and cosines (`isa`, a
    /// `mechanism_math::Isa`); `None`: the math module's `sin_cos_lanes`.
    pub(super) isa: Option<TokenStream>,
}

impl Default for EmitBindings {
    fn default() -> Self {
        Self::new()
    }
}

impl EmitBindings {
    /// No bindings; registers are named `x0, x1, ...`.
    pub fn new() -> Self {
        Self {
            reads: FxHashMap::default(),
            prefix: "x".to_string(),
            math: None,
            isa: None,
        }
    }

    /// Reads symbol `s` with `tokens` (a postfix expression of type f64: `self.l1`, `q[2]`, `t`).
    pub fn bind(&mut self, s: SymbolId, tokens: TokenStream) -> &mut Self {
        self.reads.insert(s, tokens);
        self
    }

    /// Names registers `{prefix}0, {prefix}1, ...` (default `x`); the prefix must be an
    /// identifier.
    pub fn set_prefix(&mut self, prefix: &str) -> &mut Self {
        self.prefix = prefix.to_string();
        self
    }

    /// Calls the real functions of the module at `path` (such as `::mechanism::math`, the
    /// `mechanism-math` crate): `path::sin_cos(x)` for a (sin, cos) pair, `path::sin_cos(x).0`
    /// for a lone sine and `.1` for a lone cosine, so every value is rounded as that
    /// function rounds it (the [`crate::Tape`] calls the same `sin_cos`), and
    /// `path::sqrt(x)`, `tan`, `exp`, `ln`, `abs`, `atan2(y, x)`, `powf(x, y)`,
    /// `powi(x, k)`. Without it the code calls the f64 methods (`x.sin_cos()`, `x.sqrt()`),
    /// which need std.
    pub fn set_math(&mut self, path: TokenStream) -> &mut Self {
        self.math = Some(path);
        self
    }

    /// Computes grouped sines and cosines with `isa.sin_cos_lanes([..])`, where the
    /// expression `isa` is a `mechanism_math::Isa` in scope (a generic body compiled once per
    /// instruction set), instead of the math module's `sin_cos_lanes`. Only with a math
    /// module ([`EmitBindings::set_math`]): without one nothing is grouped.
    pub fn set_isa(&mut self, isa: TokenStream) -> &mut Self {
        self.isa = Some(isa);
        self
    }

    /// The tokens reading `s`, if bound.
    pub fn get(&self, s: SymbolId) -> Option<&TokenStream> {
        self.reads.get(&s)
    }
}
