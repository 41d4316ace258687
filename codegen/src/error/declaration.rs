//! The rules of the language a declaration can break (the `mechanics` stage: checks, model
//! building, body sections): the kinds of [`Error::Declaration`](super::Error::Declaration).

use super::declared::{
    Constant, ConstantPlace, CoordinatePlace, NameKind, Needed, Quantity, SymbolRole,
};
use super::parse::did_you_mean;
use super::{Error, Location};

/// Which rule a declaration breaks, with what it found. Names are as written.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum DeclarationError {
    /// No kinetic energy and no bodies: there is no mass matrix.
    #[error(
        "`{mechanism}` declares no kinetic energy: add `kinetic = ...;`, T as a function of the coordinates and their rates der(q)"
    )]
    NoKinetic {
        /// The struct name.
        mechanism: String,
    },
    /// No generalised coordinate: no `coordinates` section, an empty one (`coordinates { }`),
    /// or a model built by hand with none.
    #[error("{}", no_coordinates(.mechanism, *.empty_section))]
    NoCoordinates {
        /// The struct name.
        mechanism: String,
        /// True when the section is written but lists nothing.
        empty_section: bool,
    },
    /// Links are declared but none of their joints moves (each is `fixed`): no coordinate.
    #[error(
        "no link of `{mechanism}` moves: every link's joint is fixed, so there are no coordinates; give a link a moving joint (`joint = revolute(q, [0, 0, 1]);`, `continuous` or `prismatic`)"
    )]
    NoMovingJoint {
        /// The struct name.
        mechanism: String,
    },
    /// A name that is neither a coordinate, a parameter, nor `t` or `pi` (nor, in a body
    /// section, a body, point or axis).
    #[error("unknown symbol `{name}`{}", unknown_hint(.suggestion, .known))]
    UnknownSymbol {
        /// The name written.
        name: String,
        /// The closest declared name, when one is near (a likely typo).
        suggestion: Option<String>,
        /// The names that exist there, closest to `name` first (the message shows the
        /// first few).
        known: Vec<String>,
    },
    /// A call to a function the language does not have.
    #[error(
        "unknown function `{name}` (known: sin, cos, tan, exp, ln, sqrt, atan2, abs, pow, der; in body and link sections also rot_x, rot_y, rot_z, diag, dot, cross, norm)"
    )]
    UnknownFunction {
        /// The name written.
        name: String,
    },
    /// A division by (or a negative power of) an expression that is the constant 0 (`x/0`,
    /// `1/(2-2)`).
    #[error("division by zero: `{divisor}` is the constant 0")]
    ZeroDivisor {
        /// The divisor as written.
        divisor: String,
    },
    /// A parameter or coordinate declared twice.
    #[error("the {kind} `{name}` is declared twice (first at {first})")]
    DeclaredTwice {
        /// The name.
        name: String,
        /// Parameter or coordinate.
        kind: NameKind,
        /// Where it was declared first.
        first: Location,
    },
    /// A name declared as a parameter and as a coordinate.
    #[error("`{name}` is declared both as a {first_kind} (at {first}) and as a {kind}")]
    DeclaredAsBoth {
        /// The name.
        name: String,
        /// What it was declared as first.
        first_kind: NameKind,
        /// Where.
        first: Location,
        /// What it is declared as here.
        kind: NameKind,
    },
    /// A parameter or coordinate called `t` or `pi`.
    #[error(
        "a {kind} cannot be called `{name}`: that name is {}; pick another name",
        if .name == "t" { "time" } else { "the constant 3.14159..." }
    )]
    ReservedName {
        /// `t` or `pi`.
        name: String,
        /// Parameter or coordinate.
        kind: NameKind,
    },
    /// A default or initial value that uses something not constant.
    #[error("{place}; `{written}` is {role}")]
    NotConstant {
        /// A parameter default or an initial value.
        place: ConstantPlace,
        /// The name, or `der(x)`, as written.
        written: String,
        /// What it is.
        role: SymbolRole,
    },
    /// A parameter default that uses its own parameter.
    #[error("the default of `{name}` refers to `{name}` itself")]
    DefaultRefersToItself {
        /// The parameter.
        name: String,
    },
    /// A parameter default that uses a parameter declared after it.
    #[error(
        "a parameter default may use only parameters declared before it; `{name}` is declared later"
    )]
    DefaultUsesLater {
        /// The later parameter.
        name: String,
    },
    /// `der(x + y)`.
    #[error("{function}() takes the name of a coordinate, like {function}(phi); found `{found}`")]
    RateOfExpression {
        /// `der` or `der2`.
        function: String,
        /// The argument as written.
        found: String,
    },
    /// `der(m)` of a name that is not a coordinate with a rate.
    #[error("der() takes a coordinate; `{name}` is {role}")]
    RateOfNonCoordinate {
        /// The name.
        name: String,
        /// What it is.
        role: SymbolRole,
    },
    /// `der2(x)` in a declaration.
    #[error(
        "accelerations cannot appear in a declaration; `{written}` is one (energies and forces use q, der(q) and t)"
    )]
    Acceleration {
        /// `der2(x)` as written.
        written: String,
    },
    /// A rate in the potential energy.
    #[error(
        "the potential energy may depend on the coordinates and t only; `{written}` appears in it"
    )]
    RateInPotential {
        /// `der(x)` as written.
        written: String,
    },
    /// A rate in a constraint row.
    #[error(
        "constraints must be holonomic: {written} appears in constraint {row} (write position-level constraints Phi(q, t) = 0)"
    )]
    RateInConstraint {
        /// `der(x)` as written.
        written: String,
        /// The row, 1-based.
        row: usize,
    },
    /// A velocity constraint whose coefficient of a rate depends on the rates.
    #[error(
        "velocity constraint {row} is not linear in the rates: its coefficient of {rate} depends on the rates (write A(q, t) der(q) + a(q, t) = 0)"
    )]
    VelocityNotLinear {
        /// The row, 1-based, among the velocity constraints.
        row: usize,
        /// `der(x)` whose coefficient depends on the rates.
        rate: String,
    },
    /// `rolling(B, ..)` where B is not a body with an orientation.
    #[error(
        "argument 1 of `rolling` must be the name of a body with an orientation (the wheel); `{found}` is not one"
    )]
    RollingNeedsBody {
        /// The argument as written.
        found: String,
    },
    /// A wheel whose axis is vertical at the initial guesses.
    #[error(
        "the axis of the wheel `{body}` is vertical at the initial guesses: its contact point with the ground z = 0 is undefined (tilt the axis, or change the guesses)"
    )]
    RollingAxisVertical {
        /// The wheel body.
        body: String,
    },
    /// `der(..)` in a body section.
    #[error(
        "`{function}(..)` cannot appear in a body, point, spring or joint: they are position-level (functions of q and t)"
    )]
    RateInBody {
        /// `der` or `der2`.
        function: String,
    },
    /// A force or an `independent` entry on something that is not a coordinate.
    #[error(
        "{place}, but `{name}` is {role} (the coordinates are {}){}",
        .coordinates.join(", "),
        did_you_mean(.suggestion)
    )]
    NotACoordinate {
        /// Where the name stands.
        place: CoordinatePlace,
        /// The name written.
        name: String,
        /// What it is.
        role: SymbolRole,
        /// The coordinates.
        coordinates: Vec<String>,
        /// The closest coordinate, when one is near.
        suggestion: Option<String>,
    },
    /// Two forces on one coordinate.
    #[error("two forces on `{name}` (the first at {first}); write them as one sum")]
    TwoForces {
        /// The coordinate.
        name: String,
        /// Where the first is.
        first: Location,
    },
    /// A value set twice in `independent`.
    #[error("`{}` is set twice in `independent` (first at {first})", written(.name, *.rate))]
    SetTwice {
        /// The coordinate.
        name: String,
        /// True for `der(name)`.
        rate: bool,
        /// Where it was set first.
        first: Location,
    },
    /// Fewer independent coordinates than degrees of freedom n - m.
    #[error(
        "the mechanism has n - m = {n} - {m} = {} {} but `independent` sets {} ({}); set {} more of {} as `name = value;` (with `der(name) = value;` for its rate), so the other coordinates can be found from the constraints",
        .n - .m,
        if .n - .m == 1 { "degree of freedom" } else { "degrees of freedom" },
        .given.len(),
        if .given.is_empty() { "none".to_string() } else { listed(.given) },
        .n - .m - .given.len(),
        listed(.candidates)
    )]
    TooFewIndependent {
        /// Coordinates.
        n: usize,
        /// Constraint rows.
        m: usize,
        /// The coordinates `independent` sets.
        given: Vec<String>,
        /// The coordinates it could set.
        candidates: Vec<String>,
    },
    /// A constraint row without q or t.
    #[error(
        "constraint {row} does not depend on the coordinates or t (it simplifies to `{simplified}`), so it constrains nothing: remove it or correct it"
    )]
    ConstraintWithoutMotion {
        /// The row, 1-based.
        row: usize,
        /// Its simplified form, as text.
        simplified: String,
    },
    /// A kinetic energy without rates.
    #[error(
        "the kinetic energy does not depend on any rate der(q) (it is `{kinetic}`): write T with the rates, e.g. `1/2*m*der(x)^2`"
    )]
    KineticWithoutRates {
        /// T, as text.
        kinetic: String,
    },
    /// Declared by links, no mass or inertia moves with the joints: T = 0, so M = 0.
    #[error("no mass moves: the links the joints {} move carry no mass or inertia that moves with them (a mass on its joint's axis without inertia does not), so the kinetic energy is 0; give the moving links their mass properties", coordinates.join(", "))]
    LinksWithoutMovingMass {
        /// The joints' coordinates.
        coordinates: Vec<String>,
    },
    /// A constant (a default, an initial value) whose evaluation failed.
    #[error("{what} cannot be evaluated: {error}")]
    NotEvaluable {
        /// Which constant.
        what: Constant,
        /// Why.
        error: Box<Error>,
    },
    /// A function at a constant argument outside its domain (`ln(0)`).
    #[error("{error}")]
    ConstantOutOfDomain {
        /// The evaluation error.
        error: Box<Error>,
    },
    /// The same in a body section, naming the function.
    #[error("`{function}`: {error}")]
    FunctionOutOfDomain {
        /// The function.
        function: String,
        /// The evaluation error.
        error: Box<Error>,
    },
    /// A value of a body section that must be 1x1.
    #[error("{what} must be a scalar; this is a {rows}x{cols} value")]
    NotScalar {
        /// The value's role.
        what: Quantity,
        /// Its rows.
        rows: usize,
        /// Its columns.
        cols: usize,
    },
    /// A value of a body section that must be 3x1.
    #[error("{what} must be a 3-vector `[x, y, z]`; this is a {rows}x{cols} value")]
    NotVector3 {
        /// The value's role.
        what: Quantity,
        /// Its rows.
        rows: usize,
        /// Its columns.
        cols: usize,
    },
    /// `[[a, b], [c]]`.
    #[error("the rows of a matrix `[[..], [..]]` must have equal lengths")]
    RaggedMatrix,
    /// A sum of values of different shapes.
    #[error(
        "a sum needs values of one shape: the left side is {}x{}, the right side {}x{}",
        .left.0, .left.1, .right.0, .right.1
    )]
    SumShapes {
        /// (rows, cols) on the left.
        left: (usize, usize),
        /// (rows, cols) on the right.
        right: (usize, usize),
    },
    /// A matrix product of values whose sizes do not fit.
    #[error(
        "a matrix product needs as many columns on the left as rows on the right: the left side is {}x{}, the right side {}x{}",
        .left.0, .left.1, .right.0, .right.1
    )]
    ProductShapes {
        /// (rows, cols) on the left.
        left: (usize, usize),
        /// (rows, cols) on the right.
        right: (usize, usize),
    },
    /// The two sides of a joint row of different shapes.
    #[error(
        "the two sides of a joint row differ in shape: {}x{} and {}x{}",
        .left.0, .left.1, .right.0, .right.1
    )]
    JointRowShapes {
        /// (rows, cols) on the left.
        left: (usize, usize),
        /// (rows, cols) on the right.
        right: (usize, usize),
    },
    /// A joint helper inside an expression.
    #[error("`{helper}(..)` is a joint: write it as a statement of its own in `joints {{ .. }}`")]
    JointInExpression {
        /// The helper.
        helper: String,
    },
    /// A helper argument that must name an axis.
    #[error(
        "argument {index} of `{helper}` must be the name of an axis (`axis b = [0, 0, 1];` in a body or at the top level)"
    )]
    NotAnAxis {
        /// The helper.
        helper: String,
        /// The argument, 1-based.
        index: usize,
    },
    /// An axis whose direction depends on more than parameters.
    #[error("an axis must be a constant direction in its body (parameters allowed): {error}")]
    AxisNotConstant {
        /// The evaluation error.
        error: Box<Error>,
    },
    /// A `link` that breaks a rule of links (its parent, joint, inertia or limits).
    #[error("link `{link}`: {problem}")]
    Link {
        /// The link.
        link: String,
        /// What is wrong, and what to write instead.
        problem: String,
    },
    /// An axis `[0, 0, 0]`.
    #[error("an axis cannot be the zero vector")]
    ZeroAxis,
    /// An orientation factor that is not 3x3.
    #[error("an orientation factor must be 3x3; this is {rows}x{cols}")]
    OrientationFactor {
        /// Its rows.
        rows: usize,
        /// Its columns.
        cols: usize,
    },
    /// An inertia that is not 3x3.
    #[error(
        "an inertia tensor is 3x3 (`diag(Ixx, Iyy, Izz)` or `[[..], [..], [..]]`); this is {rows}x{cols}"
    )]
    InertiaNot3x3 {
        /// Its rows.
        rows: usize,
        /// Its columns.
        cols: usize,
    },
    /// An inertia on a body without orientation.
    #[error(
        "the body `{body}` has an inertia but no `orientation`: give R (a point mass has only mass and position)"
    )]
    InertiaWithoutOrientation {
        /// The body.
        body: String,
    },
    /// A point or axis on a body without orientation.
    #[error(
        "the {key} `{name}` is on the point mass `{body}`: give the body an `orientation` (its points are in body axes)"
    )]
    OnPointMass {
        /// `point` or `axis`.
        key: String,
        /// Its name.
        name: String,
        /// The body.
        body: String,
    },
    /// An entry given twice in one block.
    #[error("`{key}` is given twice in `{owner}`")]
    GivenTwice {
        /// The key.
        key: String,
        /// The body, spring or damper.
        owner: String,
    },
    /// `gravity` given twice.
    #[error("`gravity` is given twice")]
    GravityTwice,
    /// `draw` given twice.
    #[error("`draw` is given twice; write all its lines and traces in one block")]
    DrawTwice,
    /// `draw` names an axis where it joins points.
    #[error("`{name}` is an axis (a direction), not a point: `draw` joins points")]
    DrawnAxis {
        /// The axis.
        name: String,
    },
    /// `draw` names something that is not a point declared before it.
    #[error(
        "`draw` names `{name}`, which is not a point declared before it (declare it with `point {name} = [x, y, z];` or in a body)"
    )]
    UnknownDrawnPoint {
        /// The name written.
        name: String,
    },
    /// A body, point or axis name used twice.
    #[error("the name `{name}` is declared twice among bodies, points and axes")]
    VectorNameTwice {
        /// The name.
        name: String,
    },
    /// A body, point or axis named like a parameter or coordinate.
    #[error(
        "`{name}` is already a parameter or coordinate; a body, point or axis needs its own name"
    )]
    NameTaken {
        /// The name.
        name: String,
    },
    /// A body, spring or damper without a required entry.
    #[error("the {block} `{name}` needs {entry}")]
    MissingEntry {
        /// `body`, `spring` or `damper`.
        block: String,
        /// Its name.
        name: String,
        /// The entry.
        entry: Needed,
    },

    // ----- numbers and physics of the declared quantities -----
    /// Constants whose sum or product, folded while building an expression, is beyond the
    /// range of f64 (about 1.8e308): the folded value would be infinite.
    #[error(
        "the constants in `{expression}` overflow: {operation} is beyond the largest f64 (about 1.8e308); rescale the quantity (other units) or write the constants so that their product or sum stays finite"
    )]
    ConstantOverflow {
        /// The expression as written.
        expression: String,
        /// The folding that overflowed, e.g. `1e200 * 1e200`.
        operation: String,
    },
    /// T is not at most quadratic in the rates: an entry of M = d2T/dq'^2 depends on a rate.
    #[error(
        "the kinetic energy is not a quadratic form in the rates: M[{row}, {column}] = d2T/d der({row}) d der({column}) depends on der({rate}); write T = 1/2 q'^T M(q) q' (plus terms linear in the rates or free of them)"
    )]
    KineticNotQuadratic {
        /// The row's coordinate.
        row: String,
        /// The column's coordinate.
        column: String,
        /// The rate the entry depends on.
        rate: String,
    },
    /// M = d2T/dq'^2 has a negative direction at the declared values: T can be negative.
    #[error(
        "the kinetic energy can be negative: at the declared parameter values and initial guesses (t = 0) the mass matrix M = d2T/dq'^2 has a negative direction along `{coordinate}` (pivot {pivot}, M[{coordinate}, {coordinate}] = {diagonal}); T must be >= 0 for every rate: check the signs, masses and inertias"
    )]
    KineticNotPositive {
        /// The coordinate of the negative pivot.
        coordinate: String,
        /// The pivot of the L D L^T elimination.
        pivot: f64,
        /// M at that coordinate's diagonal.
        diagonal: f64,
    },
    /// `der(y) = v;` in `independent` without `y = ...;`: y is not free, its rate follows
    /// from the constraints.
    #[error(
        "`der({name})` is given in `independent`, but `{name}` is not an independent coordinate (those are: {}); its rate follows from the constraints: give `{name} = value;` too to make it independent, or remove `der({name})`",
        if independent.is_empty() { "none".to_string() } else { independent.join(", ") }
    )]
    RateOfDependent {
        /// The coordinate.
        name: String,
        /// The coordinates whose positions the section sets.
        independent: Vec<String>,
    },
    /// An explicit orientation factor that is not a rotation at the parameter values and
    /// coordinates checked (the declared values and initial guesses; at run time, the
    /// assembled state).
    #[error(
        "the orientation of body `{body}` is not a rotation at {state}: max |(R^T R - I)_ij| = {deviation:.3e} (at most 1e-6 allowed), det R = {determinant:.6}; an orientation must be orthonormal with det R = 1 (write it as a product of rot_x, rot_y, rot_z)"
    )]
    OrientationNotRotation {
        /// The body.
        body: String,
        /// max |(R^T R - I)_ij|.
        deviation: f64,
        /// det R.
        determinant: f64,
        /// `t = 0, x = 0.5, ...`: where it was evaluated.
        state: String,
    },
    /// A parameter's value outside the range its declaration gives it
    /// (`r = 0.1 positive;`): the default, or a value set in its place.
    #[error(
        "parameter `{name}` is {value} at the declared values, but its declaration says `{keyword}` ({meaning})"
    )]
    OutOfRange {
        /// The parameter.
        name: String,
        /// Its value.
        value: f64,
        /// The annotation (`positive`, `nonnegative`).
        keyword: &'static str,
        /// What it means (`greater than 0`).
        meaning: &'static str,
    },
    /// A rolling wheel whose radius is zero or negative at the declared values.
    #[error(
        "the radius of the wheel `{body}` is {value} at the declared values: a wheel's radius must be greater than 0"
    )]
    WheelRadius {
        /// The wheel's body.
        body: String,
        /// Its radius.
        value: f64,
    },
    /// A body's mass below zero at the declared values.
    #[error(
        "the mass of body `{body}` is {value} at the declared values: a mass cannot be negative"
    )]
    NegativeMass {
        /// The body.
        body: String,
        /// Its value.
        value: f64,
    },
    /// An inertia tensor whose (row, column) and (column, row) entries differ.
    #[error(
        "the inertia of body `{body}` is not symmetric: entry ({row}, {column}) is {upper} but ({column}, {row}) is {lower}; a products-of-inertia entry appears twice with the same value"
    )]
    InertiaNotSymmetric {
        /// The body.
        body: String,
        /// 1-based row of the upper entry.
        row: usize,
        /// 1-based column of the upper entry.
        column: usize,
        /// The (row, column) value.
        upper: f64,
        /// The (column, row) value.
        lower: f64,
    },
    /// Principal moments that no mass distribution has: one below zero, or the largest
    /// above the sum of the other two.
    #[error(
        "the inertia of body `{body}` is not physically possible: its principal moments {moments:?} must be >= 0 with each at most the sum of the other two (I1 + I2 >= I3); check the entries and the axes they are about"
    )]
    InertiaNotPhysical {
        /// The body.
        body: String,
        /// The principal moments, ascending.
        moments: [f64; 3],
    },
}

/// `x` or `der(x)`.
/// Names joined by ", ", the first [`LISTED`] of them and then how many more: a
/// mechanism of a thousand coordinates still gets a message that fits a terminal line.
fn listed(names: &[String]) -> String {
    if names.len() <= LISTED {
        return names.join(", ");
    }
    format!(
        "{}, ... ({} more)",
        names[..LISTED].join(", "),
        names.len() - LISTED
    )
}

/// How many names an error message lists before it counts the rest.
const LISTED: usize = 12;

/// The message of [`DeclarationError::NoCoordinates`]: what to add, or that the section is
/// empty.
fn no_coordinates(mechanism: &str, empty_section: bool) -> String {
    if empty_section {
        "`coordinates` is empty: a mechanism needs at least one generalised coordinate (`name = initial guess;`)".to_string()
    } else {
        format!(
            "`{mechanism}` declares no coordinates: add `coordinates {{ phi = 0.0; }}` with each generalised coordinate and its initial guess"
        )
    }
}

/// Known names an unknown-symbol message lists before `...`.
const KNOWN_SHOWN: usize = 8;

/// `"; did you mean `x`? known: x, y, ..."` for an unknown-symbol message (each part only
/// when there is something to say).
fn unknown_hint(suggestion: &Option<String>, known: &[String]) -> String {
    let mut hint = did_you_mean(suggestion);
    if !known.is_empty() {
        hint.push_str(if suggestion.is_some() {
            " known: "
        } else {
            "; known: "
        });
        hint.push_str(&known[..known.len().min(KNOWN_SHOWN)].join(", "));
        if known.len() > KNOWN_SHOWN {
            hint.push_str(", ...");
        }
    }
    hint
}

fn written(name: &str, rate: bool) -> String {
    if rate {
        format!("der({name})")
    } else {
        name.to_string()
    }
}
