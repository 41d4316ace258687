//! Errors of [`derive`](crate::derive()) on a [`Model`](crate::Model): the preconditions a
//! parsed declaration meets by construction (its checks refuse the same mistakes with their
//! place, as [`DeclarationError`](super::DeclarationError)), which a model built by hand can
//! break, and the overflow of the derivation's own constants.

/// A model the derivation cannot take, or a derivation whose constants overflow.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum DerivationError {
    /// A model entry that must be a symbol (a coordinate, its rate or acceleration, a
    /// multiplier) is another expression.
    #[error("{role} is not a symbol of the model's arena")]
    NotASymbol {
        /// What the entry is, e.g. "the position of coordinate `x`".
        role: String,
    },
    /// The number of generalised forces differs from the number of coordinates.
    #[error("{forces} generalised forces given for {coordinates} coordinates")]
    ForceCount {
        /// Forces given.
        forces: usize,
        /// Coordinates.
        coordinates: usize,
    },
    /// An expression depends on a symbol it must not contain (a rate in the potential or a
    /// constraint, an acceleration in T or a force).
    #[error("the {what} must not depend on `{symbol}`")]
    ForbiddenDependence {
        /// The expression's role, e.g. "potential energy".
        what: String,
        /// The symbol it contains.
        symbol: String,
    },
    /// A body quantity (position, orientation, inertia, mass, stiffness) depends on a rate or
    /// an acceleration.
    #[error("the {what} must depend on the coordinates and t only; it contains `{symbol}`")]
    NotPositionLevel {
        /// The quantity, e.g. "mass of body `B1`".
        what: String,
        /// The rate or acceleration it contains.
        symbol: String,
    },
    /// A body's inertia that is not 3 x 3.
    #[error("the inertia of body `{body}` is {rows}x{cols}, not 3x3")]
    InertiaShape {
        /// The body.
        body: String,
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
    },
    /// The derivation (a derivative's or a product's constant factor) overflowed the range
    /// of f64; the declared expressions themselves were finite.
    #[error(
        "deriving the equations of `{mechanism}` multiplies or adds constants beyond the largest f64 (about 1.8e308): {operation}; rescale the declaration's constants (other units)"
    )]
    Overflow {
        /// The struct name.
        mechanism: String,
        /// The folding that overflowed, e.g. `2 * 1e308`.
        operation: String,
    },
    /// A floating-base model asked for a route written for q' = dq/dt (the interpreter,
    /// the `Mechanism` trait's routines, the residual's tangent).
    #[error(
        "`{mechanism}` has a floating base (q has {nq} entries, v {nv}), which {what} cannot take (written for q' = dq/dt); the macro's `FloatingBase` methods, `InterpretedFloating` and `mechanism simulate` take it, moving q on its manifold"
    )]
    FloatingBase {
        /// The struct name.
        mechanism: String,
        /// What was asked for.
        what: String,
        /// NQ.
        nq: usize,
        /// NV.
        nv: usize,
    },
}
