//! The parsed declaration of a mechanism: what the user wrote, as expressions in one arena.

use crate::algebra::expr::{Arena, Id};
use crate::algebra::rotation::{Orientation, RotationFactor};
use crate::error::Location;
use crate::mechanics::drawing::Drawing;
use crate::mechanics::rigid_body::Body;
use crate::mechanics::tree::Link;
pub use crate::syntax::parameter_range::ParameterRange;

/// A parameter: a run-time constant with a declared default (`l1 = 0.08;`).
#[derive(Clone, Debug)]
pub struct Parameter {
    /// Name, as written.
    pub name: String,
    /// Its symbol node.
    pub symbol: Id,
    /// Default value (the declared constant expression, evaluated).
    pub default: f64,
    /// The values it may take (`r = 0.1 positive;`); [`ParameterRange::Any`] unless declared.
    pub range: ParameterRange,
    /// Where it was declared.
    pub location: Location,
}

/// A generalised coordinate q_i with its rate and acceleration symbols.
#[derive(Clone, Debug)]
pub struct Coordinate {
    /// Name, as written.
    pub name: String,
    /// q_i.
    pub q: Id,
    /// q_i' (`der(name)`).
    pub qd: Id,
    /// q_i'' (`der2(name)`).
    pub qdd: Id,
    /// Initial guess for the assembly Newton iteration: the value of [`Coordinate::guess_expr`]
    /// at the declared parameter values.
    pub guess: f64,
    /// The initial guess as declared: an expression in the parameters (and constants), which
    /// [`crate::Role::InitialValues`] evaluates at the current parameter values.
    pub guess_expr: Id,
    /// Where it was declared.
    pub location: Location,
}

/// An independent coordinate: set by the user at t = 0.
#[derive(Clone, Debug)]
pub struct IndependentSpec {
    /// Index into [`Model::coordinates`].
    pub coordinate: usize,
    /// q_k(0), the value of [`IndependentSpec::position_expr`] at the declared parameter
    /// values.
    pub position: f64,
    /// q_k'(0) (0 when not given), the value of [`IndependentSpec::velocity_expr`] there.
    pub velocity: f64,
    /// q_k(0) as declared: an expression in the parameters.
    pub position_expr: Id,
    /// q_k'(0) as declared, an expression in the parameters; `None` when not given (0).
    pub velocity_expr: Option<Id>,
    /// Where it was declared.
    pub location: Location,
}

/// One scalar constraint row Phi_i(q, t) = 0.
#[derive(Clone, Debug)]
pub struct Constraint {
    /// The residual expression.
    pub expr: Id,
    /// Where it was declared.
    pub location: Location,
    /// The statement the row comes from, as the user reads it: `constraint 2` for the second
    /// statement of `constraints { .. }`, or the joint as written, `revolute(B1, B2, z, z)`,
    /// `P = Q`, `P.z = 0`.
    pub joint: String,
    /// Which row of that statement: `x`, `y`, `z` (the components of a point, or of a vector
    /// equation of 2 or 3 rows), `1`, `2`, .. (of a longer vector equation), `(i, j)` (of a
    /// matrix equation), `axis 1`, `axis 2`
    /// (the parallel-axis rows of `revolute` and `prismatic`), `slide 1`, `slide 2`, `twist`
    /// (the other rows of `prismatic`); empty for a statement with one row.
    pub component: String,
}

impl Constraint {
    /// The label of the row: the joint, then a space and the component when there is one
    /// (`revolute(B1, B2, z, z) y`, `constraint 2`).
    pub fn label(&self) -> String {
        if self.component.is_empty() {
            self.joint.clone()
        } else {
            format!("{} {}", self.joint, self.component)
        }
    }
}

/// A whole declaration.
#[derive(Clone, Debug)]
pub struct Model {
    /// Struct name (`SpatialCrankSlider`).
    pub name: String,
    /// Doc comment lines (without the `///`).
    pub doc: Vec<String>,
    /// True when declared `pub struct`.
    pub public: bool,
    /// The expression arena holding every expression below.
    pub arena: Arena,
    /// The time symbol t.
    pub time: Id,
    /// Parameters, in declaration order.
    pub parameters: Vec<Parameter>,
    /// Coordinates q, in declaration order.
    pub coordinates: Vec<Coordinate>,
    /// Independent coordinates and their initial values.
    pub independent: Vec<IndependentSpec>,
    /// Kinetic energy T(q, q', t).
    pub kinetic: Id,
    /// Where T is declared (`kinetic`, or the first body): the derivation's checks of T
    /// report there.
    pub kinetic_location: Location,
    /// Potential energy Pi(q, t).
    pub potential: Id,
    /// Constraint rows Phi(q, t).
    pub constraints: Vec<Constraint>,
    /// The joint rows left out of `constraints` because they are identically zero, one
    /// entry per statement: the statement and the components left out
    /// (`revolute(A, O, n1, z) (z, axis 1, axis 2)`), the z rows and the axis rows of a
    /// joint between bodies that move in one plane. Each such row would be a zero row of
    /// Phi_q, a redundancy of every configuration, so it is dropped where it is built. A
    /// joint all of whose rows vanish keeps them, and the declaration's check refuses it.
    pub vanished_rows: Vec<String>,
    /// Velocity constraint rows A(q, t) q' + a(q, t) = 0 (`velocity_constraints`, the
    /// sliding rows of `rolling`): expressions linear in the rates.
    pub velocity_constraints: Vec<Constraint>,
    /// Generalised forces tau(t, q, q'), one per coordinate (0 where none is declared).
    pub forces: Vec<Id>,
    /// The declared drawing (`draw { .. }`), empty when there is none.
    pub drawing: Drawing,
    /// The links of a kinematic tree (`link` sections), parents before children; empty
    /// when the declaration has none.
    pub links: Vec<Link>,
    /// True when the links carry all of T (no `body`, no `kinetic`): then [`crate::derive()`]
    /// takes the recursive route (`mechanics::recursive`) for M and C q'.
    pub kinetic_from_links: bool,
    /// True when, besides, Pi is the links' gravity alone (no spring, no `potential`): then
    /// g and Pi come from the recursive route too.
    pub potential_from_links: bool,
    /// The declared gravity vector g (world), when there is one.
    pub gravity: Option<[Id; 3]>,
    /// The orientation of each body that declares one, as the product it is written as: the
    /// rotation sequences whose angles can be singular (a body that lies flat in
    /// `rot_z(psi) * rot_x(phi) * rot_y(th)`).
    pub rotations: Vec<RotationSequence>,
    /// The links' rigid bodies when the links carry all of T (`kinetic_from_links`): their
    /// T and gravity Pi are not in `kinetic` and `potential`, which the recursive route
    /// never reads for them; the energy route (`derive_with(model, Route::Lagrange)`)
    /// builds them from these bodies when asked. Empty otherwise (the links' bodies are
    /// then terms of `kinetic` and `potential` like any other body).
    pub link_bodies: Vec<Body>,
}

/// A body's orientation R = F_1 F_2 ... (body to world) as declared: for each factor, the
/// axis of an elementary rotation and which coordinate is its angle. The runtime reads it
/// to name a singularity of the angles (two of their axes in line, where their rates are
/// not determined).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RotationSequence {
    /// The body.
    pub body: String,
    /// The factors, left to right: the axis of `rot_x`, `rot_y`, `rot_z` (0, 1, 2; `None`
    /// for an explicit 3x3 factor) and the index of the coordinate that is its angle (`None`
    /// for an angle that is not exactly one coordinate: a parameter, an expression).
    pub factors: Vec<(Option<usize>, Option<usize>)>,
}

impl RotationSequence {
    /// The sequence of `orientation`, the orientation of `body`, with the coordinates of
    /// `coordinates` as the angles it names.
    pub(crate) fn of(
        arena: &Arena,
        body: &str,
        orientation: &Orientation,
        coordinates: &[Coordinate],
    ) -> Self {
        let coordinate = |angle: Id| coordinates.iter().position(|c| c.q == angle);
        let factors = orientation
            .factors
            .iter()
            .map(|f| match f {
                RotationFactor::Elementary(axis, angle) => {
                    let angle = arena.as_symbol(*angle).map(|s| arena.symbol_node(s));
                    (Some(axis.index()), angle.and_then(coordinate))
                }
                RotationFactor::Explicit(_) => (None, None),
            })
            .collect();
        Self {
            body: body.to_string(),
            factors,
        }
    }
}

impl Model {
    /// Whether T or Pi depends on t explicitly (a moving base written into a declared
    /// `kinetic`, a `potential` with t). With T = T2 + T1 + T0 (quadratic, linear and free
    /// of the rates), what the motion balances is then the Jacobi integral h = T2 - T0 + Pi,
    ///
    /// ```text
    /// dh/dt = tau . q' + lambda . Phi_t - dT/dt|_(q, q') + dPi/dt|_q,
    /// ```
    ///
    /// and T + Pi = h + T1 + 2 T0: T + Pi - W is not constant even for an exact solution.
    pub fn energies_depend_on_time(&self) -> bool {
        self.depends_on_time(self.kinetic) || self.depends_on_time(self.potential)
    }

    /// Whether the expression `e` of this model reads t.
    pub fn depends_on_time(&self, e: Id) -> bool {
        let a = &self.arena;
        a.as_symbol(self.time)
            .is_some_and(|time| a.depends_on_any(e, |s| s == time))
    }
}
