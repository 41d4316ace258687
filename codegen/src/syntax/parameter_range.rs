//! The range a parameter's declaration allows it: `parameters { r = 0.1 positive; }`.
//!
//! ```text
//! parameter := NAME "=" expr [range] ";"
//! range     := "positive"        (value > 0: a length, a radius, a mass that carries all the inertia)
//!            | "nonnegative"     (value >= 0: a mass or a stiffness that may vanish)
//! ```
//!
//! The default must lie in the range (checked where the defaults are evaluated), and so must
//! every value set later: `--set`, `set_parameter` (which refuses it with the reason).

use crate::syntax::lex::{Cursor, Tok};

/// The values a parameter may take, as its declaration says.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ParameterRange {
    /// Any finite value (no annotation).
    #[default]
    Any,
    /// Greater than zero (`positive`).
    Positive,
    /// Zero or more (`nonnegative`).
    NonNegative,
}

impl ParameterRange {
    /// The annotations, as written after a parameter's default.
    pub const KEYWORDS: [&'static str; 2] = ["positive", "nonnegative"];

    /// Whether `value` lies in the range (NaN lies in none but [`ParameterRange::Any`]).
    pub fn admits(self, value: f64) -> bool {
        match self {
            ParameterRange::Any => true,
            ParameterRange::Positive => value > 0.0,
            ParameterRange::NonNegative => value >= 0.0,
        }
    }

    /// The annotation as written (`positive`, `nonnegative`); empty for
    /// [`ParameterRange::Any`].
    pub fn keyword(self) -> &'static str {
        match self {
            ParameterRange::Any => "",
            ParameterRange::Positive => "positive",
            ParameterRange::NonNegative => "nonnegative",
        }
    }

    /// The range in words, for messages: `greater than 0`, `0 or more`, `any value`.
    pub fn describe(self) -> &'static str {
        match self {
            ParameterRange::Any => "any value",
            ParameterRange::Positive => "greater than 0",
            ParameterRange::NonNegative => "0 or more",
        }
    }

    /// The range named by `word`, if it is one of [`ParameterRange::KEYWORDS`].
    fn from_keyword(word: &str) -> Option<Self> {
        match word {
            "positive" => Some(ParameterRange::Positive),
            "nonnegative" => Some(ParameterRange::NonNegative),
            _ => None,
        }
    }
}

/// The range annotation at the cursor, consumed; [`ParameterRange::Any`] when the next
/// token is not one (the caller then expects the `;`).
pub(crate) fn parameter_range(c: &mut Cursor<'_>) -> ParameterRange {
    let Tok::Ident(word) = &c.peek().tok else {
        return ParameterRange::Any;
    };
    match ParameterRange::from_keyword(word) {
        Some(range) => {
            c.next();
            range
        }
        None => ParameterRange::Any,
    }
}
