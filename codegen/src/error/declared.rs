//! The parts of a declaration that [`DeclarationError`](super::DeclarationError)'s messages
//! name: what a name is, where a coordinate or a constant stands, which quantity is
//! meant, and what a statement needs.

/// What a declared name is.
#[derive(Clone, Copy, Debug, thiserror::Error, PartialEq, Eq)]
pub enum NameKind {
    /// In `parameters`.
    #[error("parameter")]
    Parameter,
    /// In `coordinates`.
    #[error("coordinate")]
    Coordinate,
}

/// Where only a coordinate may be named.
#[derive(Clone, Copy, Debug, thiserror::Error, PartialEq, Eq)]
pub enum CoordinatePlace {
    /// `forces { name: ..; }`.
    #[error("a force acts along a coordinate")]
    Force,
    /// `independent { name = ..; }`.
    #[error("`independent` sets initial values of coordinates")]
    Independent,
}

/// Where only constants are allowed.
#[derive(Clone, Copy, Debug, thiserror::Error, PartialEq, Eq)]
pub enum ConstantPlace {
    /// A parameter's default.
    #[error("a parameter default must be a constant")]
    Default,
    /// An initial guess or initial value.
    #[error("an initial value must be a constant")]
    Initial,
}

/// What a name stands for, where it is not what a rule needs.
#[derive(Clone, Copy, Debug, thiserror::Error, PartialEq, Eq)]
pub enum SymbolRole {
    /// A parameter.
    #[error("a parameter")]
    Parameter,
    /// A coordinate.
    #[error("a coordinate")]
    Coordinate,
    /// A coordinate whose rate is not declared.
    #[error("a coordinate without a declared rate")]
    CoordinateWithoutRate,
    /// A rate der(x).
    #[error("a rate")]
    Rate,
    /// An acceleration der2(x).
    #[error("an acceleration")]
    Acceleration,
    /// Time `t`.
    #[error("time")]
    Time,
    /// A free symbol of a hand-built arena.
    #[error("not a coordinate")]
    NotACoordinate,
    /// A name that is not declared.
    #[error("not declared")]
    Undeclared,
}

/// A constant of the declaration that is evaluated when the model is built.
#[derive(Clone, Debug, thiserror::Error, PartialEq, Eq)]
pub enum Constant {
    /// A parameter's default.
    #[error("the default of `{0}`")]
    Default(String),
    /// A coordinate's initial guess.
    #[error("the initial guess of `{0}`")]
    Guess(String),
    /// An independent coordinate's initial value.
    #[error("the initial value of `{0}`")]
    Position(String),
    /// An independent coordinate's initial rate.
    #[error("the initial rate of `{0}`")]
    Rate(String),
}

/// The role of a value in a body section, for shape errors.
#[derive(Clone, Debug, thiserror::Error, PartialEq, Eq)]
#[non_exhaustive]
pub enum Quantity {
    /// `a` in `a.x`.
    #[error("the value before `.x`, `.y` or `.z`")]
    MemberBase,
    /// An entry of `[..]`.
    #[error("an entry of a vector `[..]`")]
    VectorEntry,
    /// The right side of `/`.
    #[error("a divisor")]
    Divisor,
    /// The left side of `^`.
    #[error("the base of `^`")]
    PowerBase,
    /// The right side of `^`.
    #[error("an exponent")]
    Exponent,
    /// An argument of a function.
    #[error("the argument of `{0}`")]
    Argument(String),
    /// An argument of a joint helper (1-based).
    #[error("argument {index} of `{helper}`")]
    HelperArgument {
        /// The helper.
        helper: String,
        /// The argument, 1-based.
        index: usize,
    },
    /// The angle of `rot_x/y/z`.
    #[error("a rotation angle")]
    RotationAngle,
    /// A body's mass.
    #[error("the mass")]
    Mass,
    /// A body's position.
    #[error("the position")]
    Position,
    /// The length of `distance`.
    #[error("the distance")]
    Distance,
    /// `gravity`.
    #[error("the gravity vector")]
    Gravity,
    /// A named point.
    #[error("the point `{0}`")]
    Point(String),
    /// A named axis.
    #[error("the axis `{0}`")]
    Axis(String),
    /// An end of a spring or damper.
    #[error("an end of `{0}`")]
    End(String),
    /// A spring's or damper's scalar entry (`stiffness`, ...).
    #[error("`{0}`")]
    Entry(String),
}

/// An entry a block needs.
#[derive(Clone, Copy, Debug, thiserror::Error, PartialEq, Eq)]
pub enum Needed {
    /// A body's mass.
    #[error("`mass = m;` (kg; `mass = 0;` for a massless frame)")]
    Mass,
    /// A body's centre of mass.
    #[error("`position = [x, y, z];` (its centre of mass)")]
    Position,
    /// A spring's or damper's ends.
    #[error("`between = P, Q;`")]
    Between,
    /// A spring's stiffness.
    #[error("`stiffness = k;`")]
    Stiffness,
    /// A damper's coefficient.
    #[error("`coefficient = c;`")]
    Coefficient,
}
