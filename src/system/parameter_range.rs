//! The range a declaration gives a parameter (`parameters { r = 0.1 positive; }`) and the
//! error of a parameter set outside it (or by an index no parameter has).
//!
//! `Mechanism::set_parameter` and `System::set_parameter` refuse such a value and keep the
//! old one; a parameter written through a field of the generated struct (`model.r = -0.1`)
//! is not checked (a field is plain data).

use core::fmt;

/// The values a parameter may take, as its declaration says.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ParameterRange {
    /// Any value (no annotation).
    #[default]
    Any,
    /// Greater than zero (`positive`): a length, a radius, a mass that carries all the
    /// inertia of its coordinates.
    Positive,
    /// Zero or more (`nonnegative`): a mass or a stiffness that may vanish.
    NonNegative,
}

impl ParameterRange {
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

    /// The range in words: `greater than 0`, `0 or more`, `any value`.
    pub fn describe(self) -> &'static str {
        match self {
            ParameterRange::Any => "any value",
            ParameterRange::Positive => "greater than 0",
            ParameterRange::NonNegative => "0 or more",
        }
    }
}

/// Why a parameter was not set (its old value is kept).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ParameterError {
    /// No parameter has this index.
    NoSuchParameter {
        /// The index asked for.
        index: usize,
        /// How many parameters the mechanism has.
        count: usize,
    },
    /// The value lies outside the range the declaration gives the parameter.
    OutOfRange {
        /// The parameter's index (declaration order).
        index: usize,
        /// The value refused.
        value: f64,
        /// The declared range.
        range: ParameterRange,
    },
}

impl fmt::Display for ParameterError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ParameterError::NoSuchParameter { index, count } => write!(
                f,
                "no parameter has index {index}: the mechanism has {count} (0 to {})",
                count.saturating_sub(1)
            ),
            ParameterError::OutOfRange {
                index,
                value,
                range,
            } => write!(
                f,
                "parameter {index} must be {} (declared `{}`), got {value}",
                range.describe(),
                range.keyword()
            ),
        }
    }
}

#[cfg(feature = "std")]
impl std::error::Error for ParameterError {}

/// Checks `value` for parameter `index` of a mechanism with `count` parameters whose
/// declared ranges are `ranges` (empty: all [`ParameterRange::Any`]), as `set_parameter`
/// does before it writes.
///
/// # Errors
/// [`ParameterError::NoSuchParameter`] for `index >= count`;
/// [`ParameterError::OutOfRange`] for a value the range does not admit.
pub fn check_parameter(
    index: usize,
    value: f64,
    count: usize,
    ranges: &[ParameterRange],
) -> Result<(), ParameterError> {
    if index >= count {
        return Err(ParameterError::NoSuchParameter { index, count });
    }
    let range = ranges.get(index).copied().unwrap_or_default();
    if range.admits(value) {
        Ok(())
    } else {
        Err(ParameterError::OutOfRange {
            index,
            value,
            range,
        })
    }
}
