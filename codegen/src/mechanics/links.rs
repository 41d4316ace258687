//! Links: frames of a kinematic tree, each placed relative to its parent (as in URDF).
//!
//! For link i with parent p (or the world), joint origin (xyz_i, rpy_i) and joint axis a_i
//! (a unit vector in the joint frame):
//! - E_i = rot_z(yaw) rot_y(pitch) rot_x(roll), the joint frame's axes in the parent frame;
//! - the joint motion J_i(q_i): rot(a_i, q_i) for `revolute`/`continuous`, a translation
//!   a_i q_i for `prismatic`, the identity for `fixed`;
//! - relative to the parent: R_i = E_i J_i, o_i = xyz_i (+ E_i a_i q_i when prismatic);
//! - in the world: R_w,i = R_w,p R_i, p_w,i = p_w,p + R_w,p o_i.
//!
//! The inertia is declared as in URDF: mass m, centre of mass c (`com`, link frame), the
//! tensor I_c about c in the axes rotated by `com_rpy`. The recursive route uses it about
//! the link origin in link axes: h = m c (first moment) and
//! I_o = R_c I_c R_c^T + m (|c|^2 1 - c c^T).
//!
//! Each link with mass is also a [`Body`] (centre p_w + R_w c, orientation R_w R_c), so
//! the energy route (Khang's calculus over T and Pi) applies to the same declaration and
//! checks the recursive one. Points and axes of a link are in link-frame coordinates.

use crate::algebra::eval::eval;
use crate::algebra::expr::SymbolKind;
use crate::algebra::expr::{Arena, Id, SymbolId, Vec3};
use crate::algebra::matrix::Matrix;
use crate::algebra::rotation::{Axis, Orientation, RotationFactor, elementary_rotation};
use crate::error::{DeclarationError, Error, Location, Quantity, Result};
use crate::mechanics::bodies::Body;
use crate::mechanics::body_checks::{check_inertia, check_mass};
use crate::mechanics::model::Coordinate;
use crate::mechanics::tree::{Link, LinkJoint};
use crate::mechanics::vectors::{VectorNames, scalar, vec3, vector_value};
use crate::syntax::ast::Ast;
use crate::syntax::bodies::Entry;
use crate::syntax::bodies::{FLOATING_JOINT, MOVING_JOINTS};
use crate::syntax::links::floating_configuration_names;

/// What building one link gives besides the [`Link`]: its body (when it has mass), its
/// orientation (for the links below it) and its points and axes in world coordinates.
pub(crate) struct BuiltLink {
    pub(crate) link: Link,
    pub(crate) body: Option<Body>,
    pub(crate) orientation: Orientation,
    /// (name, location, world vector, true for a point / false for an axis direction).
    pub(crate) vectors: Vec<(String, Location, Vec3, bool)>,
}

fn link_error(link: &str, problem: String, at: Location) -> Error {
    let kind = DeclarationError::Link {
        link: link.to_string(),
        problem,
    };
    Error::declaration(kind, at)
}

/// The value of a numeric constant (parameters at their defaults).
fn constant(
    arena: &Arena,
    id: Id,
    known: &[(SymbolId, f64)],
    link: &str,
    what: &str,
    at: Location,
) -> Result<f64> {
    let env = |s: SymbolId| known.iter().find(|k| k.0 == s).map(|k| k.1);
    eval(arena, id, &env).map_err(|e| {
        link_error(
            link,
            format!("{what} must be a constant (parameters allowed): {e}"),
            at,
        )
    })
}

/// rot_z(yaw) rot_y(pitch) rot_x(roll), the URDF convention (fixed axes x, y, z).
pub(crate) fn rpy_matrix(arena: &mut Arena, rpy: &Vec3) -> Result<Matrix> {
    let z = elementary_rotation(arena, Axis::Z, rpy[2]);
    let y = elementary_rotation(arena, Axis::Y, rpy[1]);
    let x = elementary_rotation(arena, Axis::X, rpy[0]);
    z.mul(arena, &y)?.mul(arena, &x)
}

/// rot(a, q) for a unit axis a: e_k axes give the elementary rotation (of -q for -e_k),
/// others Rodrigues' formula R = cos q 1 + sin q [a]x + (1 - cos q) a a^T.
pub(crate) fn joint_rotation(arena: &mut Arena, axis: &Vec3, q: Id) -> (Matrix, RotationFactor) {
    if let Some((k, sign)) = unit_axis(arena, axis) {
        let ax = [Axis::X, Axis::Y, Axis::Z][k];
        let angle = if sign < 0 { arena.neg(q) } else { q };
        return (
            elementary_rotation(arena, ax, angle),
            RotationFactor::Elementary(ax, angle),
        );
    }
    let (c, s) = (arena.cos(q), arena.sin(q));
    let one = arena.int(1);
    let omc = arena.sub(one, c);
    let mut data = Vec::with_capacity(9);
    for i in 0..3 {
        for j in 0..3 {
            let aa = arena.mul(&[omc, axis[i], axis[j]]);
            let diag = if i == j { c } else { arena.int(0) };
            // [a]x_ij: (0, -a3, a2; a3, 0, -a1; -a2, a1, 0).
            let skew = match (i, j) {
                (0, 1) => arena.neg(axis[2]),
                (0, 2) => axis[1],
                (1, 0) => axis[2],
                (1, 2) => arena.neg(axis[0]),
                (2, 0) => arena.neg(axis[1]),
                (2, 1) => axis[0],
                _ => arena.int(0),
            };
            let ss = arena.mul2(s, skew);
            data.push(arena.add(&[diag, ss, aa]));
        }
    }
    let m = Matrix::from_fn(3, 3, |i, j| data[3 * i + j]);
    (m.clone(), RotationFactor::Explicit(m))
}

/// (k, sign) when `axis` is exactly ±e_k.
fn unit_axis(arena: &Arena, axis: &Vec3) -> Option<(usize, i32)> {
    let vals: Vec<f64> = axis
        .iter()
        .map(|&a| arena.as_number(a).map(|n| n.to_f64()))
        .collect::<Option<_>>()?;
    let k = vals.iter().position(|v| *v != 0.0)?;
    let others_zero = vals.iter().enumerate().all(|(i, v)| i == k || *v == 0.0);
    (others_zero && vals[k].abs() == 1.0).then_some((k, if vals[k] < 0.0 { -1 } else { 1 }))
}

fn mat_vec(arena: &mut Arena, m: &Matrix, v: &Vec3) -> Result<Vec3> {
    let r = m.mul(arena, &Matrix::column(v.to_vec()))?;
    Ok([r.get(0, 0), r.get(1, 0), r.get(2, 0)])
}

fn add3(arena: &mut Arena, a: &Vec3, b: &Vec3) -> Vec3 {
    [0, 1, 2].map(|i| arena.add2(a[i], b[i]))
}

/// The names an expression uses.
fn names_in<'a>(ast: &'a Ast, out: &mut Vec<(&'a str, Location)>) {
    match ast {
        Ast::Number(..) => {}
        Ast::Name(n, at) => out.push((n, *at)),
        Ast::Neg(a, _) | Ast::Member(a, _, _) => names_in(a, out),
        Ast::Sum(items) | Ast::Product(items) => {
            for (_, a, _) in items {
                names_in(a, out);
            }
        }
        Ast::Pow(a, b, _) => {
            names_in(a, out);
            names_in(b, out);
        }
        Ast::Call(_, args, _) | Ast::Brackets(args, _) => {
            for a in args {
                names_in(a, out);
            }
        }
    }
}

/// A link's entries are in its own frame: constants, written with numbers and parameters.
/// A point, axis or link name there is a world vector in the wrong frame, and a coordinate
/// or `t` would move the frame's definition itself.
fn check_own_frame(link: &str, e: &Entry, cx: &LinkContext<'_>) -> Result<()> {
    let mut names = Vec::new();
    for v in &e.value {
        names_in(v, &mut names);
    }
    for (n, at) in names {
        let moving = n == "t" || cx.coordinates.iter().any(|c| c.name == n);
        if cx.names.vector(n).is_some() || moving {
            let what = if moving {
                "a coordinate or time"
            } else {
                "a point, axis or link in world coordinates"
            };
            let problem = format!(
                "`{}` is in the link's own frame, written with numbers and parameters; `{n}` is {what} (join points of two links in `joints {{ .. }}`)",
                e.key
            );
            return Err(link_error(link, problem, at));
        }
    }
    Ok(())
}

/// The context a link is built in.
pub(crate) struct LinkContext<'a> {
    pub(crate) known: &'a [(SymbolId, f64)],
    pub(crate) coordinates: &'a [Coordinate],
    pub(crate) links: &'a [Link],
    pub(crate) orientations: &'a [Orientation],
    pub(crate) names: &'a dyn VectorNames,
}

/// Builds the link `name` declared at `at` with `entries`: its parent, joint, placement,
/// inertia, limits, points and axes, each a step below in the order in which later ones
/// need earlier ones (and in which their errors are reported).
pub(crate) fn build_link(
    arena: &mut Arena,
    name: &str,
    at: Location,
    entries: &[Entry],
    cx: &LinkContext<'_>,
) -> Result<BuiltLink> {
    let r = LinkEntries { name, entries, cx };
    for e in entries
        .iter()
        .filter(|e| e.key != "parent" && e.key != "joint")
    {
        check_own_frame(name, e, cx)?;
    }
    let parent = r.parent()?;
    let joint = r.joint(arena)?;
    if let LinkJoint::Floating { .. } = joint {
        r.check_floating(parent)?;
    }
    let placed = r.placement(arena, parent, &joint)?;
    let inertia = r.inertia(arena, &placed)?;
    let limits = r.limits(arena, &joint)?;
    let vectors = r.vectors(arena, &placed)?;
    Ok(BuiltLink {
        link: Link {
            name: name.to_string(),
            parent,
            joint,
            origin_rotation: placed.origin_rotation,
            origin: placed.origin,
            mass: inertia.mass,
            first_moment: inertia.first_moment,
            inertia: inertia.about_origin,
            rotation: placed.rotation,
            position: placed.position,
            limit: limits.position,
            velocity_limit: limits.velocity,
            effort_limit: limits.effort,
            location: at,
        },
        body: inertia.body,
        orientation: placed.orientation,
        vectors,
    })
}

/// A link's frame: relative to its parent (`origin`, `origin_rotation`) and in the world
/// (`rotation` R_w, `position` p_w, `orientation` the factors of R_w).
struct Placement {
    origin: Vec3,
    origin_rotation: Matrix,
    rotation: Matrix,
    position: Vec3,
    orientation: Orientation,
}

/// A link's inertia: mass m (0 when none is declared), first moment h = m c and I_o about
/// the link origin in link axes, and its [`Body`] when it has mass.
struct LinkInertia {
    mass: Id,
    first_moment: Vec3,
    about_origin: Matrix,
    body: Option<Body>,
}

/// A joint's declared limits: [lower, upper] of its coordinate, and the largest rate and
/// effort.
struct Limits {
    position: Option<[f64; 2]>,
    velocity: Option<f64>,
    effort: Option<f64>,
}

/// The entries of the link `name`, read key by key.
struct LinkEntries<'a> {
    name: &'a str,
    entries: &'a [Entry],
    cx: &'a LinkContext<'a>,
}

impl LinkEntries<'_> {
    /// The entry `key`, if given; given twice is an error at the second.
    fn take(&self, key: &str) -> Result<Option<&Entry>> {
        let mut found = self.entries.iter().filter(|e| e.key == key);
        let first = found.next();
        if let Some(second) = found.next() {
            let kind = DeclarationError::GivenTwice {
                key: key.to_string(),
                owner: self.name.to_string(),
            };
            return Err(Error::declaration(kind, second.at));
        }
        Ok(first)
    }

    /// The 3-vector entry `key`, if given.
    fn vector(&self, arena: &mut Arena, key: &str) -> Result<Option<Vec3>> {
        match self.take(key)? {
            Some(e) => {
                let m = vector_value(arena, &e.value[0], self.cx.names)?;
                Ok(Some(vec3(&m, Quantity::Entry(key.to_string()), e.at)?))
            }
            None => Ok(None),
        }
    }

    /// The entry `key`'s values as numbers (parameters at their defaults), if given.
    fn numbers(&self, arena: &mut Arena, key: &str) -> Result<Option<(Vec<f64>, Location)>> {
        let Some(e) = self.take(key)? else {
            return Ok(None);
        };
        let m = vector_value(arena, &e.value[0], self.cx.names)?;
        let mut out = Vec::new();
        for &x in m.data() {
            let what = format!("`{key}`");
            out.push(constant(arena, x, self.cx.known, self.name, &what, e.at)?);
        }
        Ok(Some((out, e.at)))
    }

    /// The index of the parent link among those declared above, or `None` for the world.
    fn parent(&self) -> Result<Option<usize>> {
        let Some(e) = self.take("parent")? else {
            return Ok(None);
        };
        match &e.value[0] {
            Ast::Name(p, _) if p == "world" => Ok(None),
            Ast::Name(p, pat) => match self.cx.links.iter().position(|l| &l.name == p) {
                Some(k) => Ok(Some(k)),
                None => {
                    let known: Vec<&str> = self.cx.links.iter().map(|l| l.name.as_str()).collect();
                    let problem = format!(
                        "its parent `{p}` is not a link declared above it (links above: {}; or `world`)",
                        if known.is_empty() {
                            "none".to_string()
                        } else {
                            known.join(", ")
                        }
                    );
                    Err(link_error(self.name, problem, *pat))
                }
            },
            other => {
                let problem = format!(
                    "`parent` names a link declared above it, or `world`; found `{}`",
                    other.text()
                );
                Err(link_error(self.name, problem, other.location()))
            }
        }
    }

    /// The joint: `fixed` (also when none is given), or a moving joint's coordinate (not
    /// moving another link) and unit axis.
    fn joint(&self, arena: &mut Arena) -> Result<LinkJoint> {
        let Some(e) = self.take("joint")? else {
            return Ok(LinkJoint::Fixed);
        };
        let name = self.name;
        match &e.value[0] {
            Ast::Name(f, _) if f == "fixed" => Ok(LinkJoint::Fixed),
            Ast::Call(kind, args, kat) if MOVING_JOINTS.contains(&kind.as_str()) => {
                let Some(Ast::Name(q, qat)) = args.first().filter(|_| args.len() == 2) else {
                    let problem = format!(
                        "write `joint = {kind}(COORDINATE, [ax, ay, az]);`: the joint's coordinate and its axis in the joint frame"
                    );
                    return Err(link_error(name, problem, *kat));
                };
                let coordinate = self.joint_coordinate(q, *qat)?;
                let axis = self.joint_axis(arena, &args[1])?;
                Ok(if kind == "prismatic" {
                    LinkJoint::Prismatic { coordinate, axis }
                } else {
                    LinkJoint::Revolute { coordinate, axis }
                })
            }
            Ast::Call(kind, args, kat) if kind == FLOATING_JOINT => {
                let Some(Ast::Name(base, bat)) = args.first().filter(|_| args.len() == 1) else {
                    let problem = "write `joint = floating(NAME);`: NAME names the root's configuration (NAME_x, .., NAME_qw) and velocities (NAME_vx, .., NAME_wz)".to_string();
                    return Err(link_error(name, problem, *kat));
                };
                let coordinate = self.joint_coordinate(&format!("{base}_vx"), *bat)?;
                let configuration = floating_configuration_names(base)
                    .map(|c| arena.symbol(&c, SymbolKind::Coordinate));
                Ok(LinkJoint::Floating {
                    coordinate,
                    configuration,
                })
            }
            other => {
                let problem = format!(
                    "unknown joint `{}`: write `fixed`, revolute, continuous or prismatic(COORDINATE, [ax, ay, az]), or floating(NAME) on a root link",
                    other.text()
                );
                Err(link_error(name, problem, other.location()))
            }
        }
    }

    /// A floating joint joins a root link to the world (its `parent`, if written, is
    /// `world`), one link of the tree has it, and the configuration alone places the link
    /// (no `xyz`, `rpy` or limits).
    fn check_floating(&self, parent: Option<usize>) -> Result<()> {
        let at = self.take("joint")?.map_or(Location::default(), |e| e.at);
        if let Some(p) = parent {
            let problem = format!(
                "a floating joint joins a root link to the world, and `{}` has the parent `{}`: remove `parent` (or write `parent = world;`), or give `{}` a revolute, prismatic or fixed joint",
                self.name, self.cx.links[p].name, self.name
            );
            return Err(link_error(self.name, problem, at));
        }
        if let Some(other) =
            (self.cx.links.iter()).find(|l| matches!(l.joint, LinkJoint::Floating { .. }))
        {
            let problem = format!(
                "the link `{}` is already the floating root: one link of a tree floats, the others hang from it",
                other.name
            );
            return Err(link_error(self.name, problem, at));
        }
        let placed = ["xyz", "rpy", "limit", "velocity_limit", "effort_limit"];
        if let Some(e) = self
            .entries
            .iter()
            .find(|e| placed.contains(&e.key.as_str()))
        {
            let problem = format!(
                "a floating link is placed by its configuration (position and quaternion) and has no `{}`",
                e.key
            );
            return Err(link_error(self.name, problem, e.at));
        }
        Ok(())
    }

    /// The index of the coordinate `q` a moving joint names, which no link above moves.
    fn joint_coordinate(&self, q: &str, at: Location) -> Result<usize> {
        let cx = self.cx;
        let coordinate = cx
            .coordinates
            .iter()
            .position(|c| c.name == q)
            .ok_or_else(|| link_error(self.name, format!("`{q}` is not a coordinate"), at))?;
        if let Some(other) = cx
            .links
            .iter()
            .find(|l| l.joint.coordinate() == Some(coordinate))
        {
            let problem = format!(
                "the coordinate `{q}` already moves the joint of link `{}`",
                other.name
            );
            return Err(link_error(self.name, problem, at));
        }
        Ok(coordinate)
    }

    /// The joint axis a / |a|: numbers when a is numeric (a itself when already unit), the
    /// quotient of expressions when it is written in parameters (unit when they change).
    fn joint_axis(&self, arena: &mut Arena, written: &Ast) -> Result<Vec3> {
        let m = vector_value(arena, written, self.cx.names)?;
        let a = vec3(&m, Quantity::Entry("joint axis".into()), written.location())?;
        let mut v = [0.0; 3];
        for (k, x) in v.iter_mut().enumerate() {
            let at = written.location();
            *x = constant(arena, a[k], self.cx.known, self.name, "the joint axis", at)?;
        }
        let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        if norm.is_nan() || norm <= 0.0 || !norm.is_finite() {
            let problem = "the joint axis is the zero vector".to_string();
            return Err(link_error(self.name, problem, written.location()));
        }
        let numeric = a.iter().all(|&x| arena.as_number(x).is_some());
        if numeric && norm == 1.0 {
            return Ok(a);
        }
        let mut out = a;
        if numeric {
            for (k, o) in out.iter_mut().enumerate() {
                *o = arena.float(v[k] / norm)?;
            }
        } else {
            let squares: Vec<Id> = a.iter().map(|&x| arena.mul2(x, x)).collect();
            let sum = arena.add(&squares);
            let length = arena.sqrt(sum)?;
            for o in out.iter_mut() {
                *o = arena.div(*o, length)?;
            }
        }
        Ok(out)
    }

    /// The link's frame: R_i = E_i J_i and o_i = xyz_i (+ E_i a_i q_i when prismatic)
    /// relative to the parent, R_w,i = R_w,p R_i and p_w,i = p_w,p + R_w,p o_i in the world.
    fn placement(
        &self,
        arena: &mut Arena,
        parent: Option<usize>,
        joint: &LinkJoint,
    ) -> Result<Placement> {
        let cx = self.cx;
        let origin = match self.vector(arena, "xyz")? {
            Some(v) => v,
            None => zero3(arena),
        };
        let origin_rotation = match self.vector(arena, "rpy")? {
            Some(v) => rpy_matrix(arena, &v)?,
            None => Matrix::identity(arena, 3),
        };
        let (mut factors, parent_rotation, parent_position) = match parent {
            Some(p) => (
                cx.orientations[p].factors.clone(),
                cx.links[p].rotation.clone(),
                cx.links[p].position,
            ),
            None => (Vec::new(), Matrix::identity(arena, 3), zero3(arena)),
        };
        if !origin_rotation.is_identity(arena) {
            factors.push(RotationFactor::Explicit(origin_rotation.clone()));
        }
        let mut relative_rotation = origin_rotation.clone();
        let mut relative_origin = origin;
        match joint {
            LinkJoint::Fixed => {}
            LinkJoint::Revolute { coordinate, axis } => {
                let q = cx.coordinates[*coordinate].q;
                let (m, f) = joint_rotation(arena, axis, q);
                relative_rotation = origin_rotation.mul(arena, &m)?;
                factors.push(f);
            }
            LinkJoint::Prismatic { coordinate, axis } => {
                let q = cx.coordinates[*coordinate].q;
                let aq = axis.map(|a| arena.mul2(a, q));
                let slide = mat_vec(arena, &origin_rotation, &aq)?;
                relative_origin = add3(arena, &origin, &slide);
            }
            LinkJoint::Floating { configuration, .. } => {
                let m = quaternion_matrix(arena, configuration);
                relative_rotation = m.clone();
                relative_origin = [configuration[0], configuration[1], configuration[2]];
                factors.push(RotationFactor::Explicit(m));
            }
        }
        let rotation = parent_rotation.mul(arena, &relative_rotation)?;
        let moved = mat_vec(arena, &parent_rotation, &relative_origin)?;
        let position = add3(arena, &parent_position, &moved);
        Ok(Placement {
            origin,
            origin_rotation,
            rotation,
            position,
            orientation: Orientation { factors },
        })
    }

    /// The declared mass m, centre of mass c and tensor I_c (about c, in the axes rotated
    /// by R_c = `com_rpy`), as the link's inertia about its origin,
    /// I_o = R_c I_c R_c^T + m (|c|^2 1 - c c^T), and as a [`Body`] at p_w + R_w c.
    fn inertia(&self, arena: &mut Arena, placed: &Placement) -> Result<LinkInertia> {
        let (name, cx) = (self.name, self.cx);
        let mass = match self.take("mass")? {
            Some(e) => {
                let m = vector_value(arena, &e.value[0], cx.names)?;
                let m = scalar(&m, Quantity::Mass, e.at)?;
                check_mass(arena, name, m, cx.known, e.at)?;
                Some(m)
            }
            None => None,
        };
        let com = self.vector(arena, "com")?;
        let com_rotation = match self.vector(arena, "com_rpy")? {
            Some(v) => rpy_matrix(arena, &v)?,
            None => Matrix::identity(arena, 3),
        };
        let inertia_c = match self.take("inertia")? {
            Some(e) => {
                if mass.is_none() {
                    let problem = "declares an inertia but no mass: add `mass = ...;`".to_string();
                    return Err(link_error(name, problem, e.at));
                }
                let m = vector_value(arena, &e.value[0], cx.names)?;
                if (m.rows(), m.cols()) != (3, 3) {
                    let (rows, cols) = (m.rows(), m.cols());
                    let kind = DeclarationError::InertiaNot3x3 { rows, cols };
                    return Err(Error::declaration(kind, e.at));
                }
                check_inertia(arena, name, &m, cx.known, e.at)?;
                Some(m)
            }
            None => None,
        };
        let c = match com {
            Some(c) => c,
            None => zero3(arena),
        };
        let m = match mass {
            Some(m) => m,
            None => arena.int(0),
        };
        let first_moment = c.map(|ci| arena.mul2(m, ci));
        let about_origin = about_origin(arena, m, &c, &com_rotation, inertia_c.as_ref())?;
        let body = match mass {
            Some(mass) => {
                let rc = mat_vec(arena, &placed.rotation, &c)?;
                let mut f = placed.orientation.factors.clone();
                if !com_rotation.is_identity(arena) {
                    f.push(RotationFactor::Explicit(com_rotation.clone()));
                }
                Some(Body {
                    name: name.to_string(),
                    mass,
                    position: add3(arena, &placed.position, &rc),
                    orientation: Some(Orientation { factors: f }),
                    inertia: inertia_c,
                })
            }
            None => None,
        };
        Ok(LinkInertia {
            mass: m,
            first_moment,
            about_origin,
            body,
        })
    }

    /// `limit = [lower, upper]` (lower <= upper), `velocity_limit` and `effort_limit` (one
    /// value >= 0 each), none of them on a fixed joint.
    fn limits(&self, arena: &mut Arena, joint: &LinkJoint) -> Result<Limits> {
        let name = self.name;
        let limit = match self.numbers(arena, "limit")? {
            Some((v, lat)) => {
                if v.len() != 2 || v[0].is_nan() || v[1].is_nan() || v[0] > v[1] {
                    let problem = "`limit = [lower, upper];` needs lower <= upper".to_string();
                    return Err(link_error(name, problem, lat));
                }
                Some([v[0], v[1]])
            }
            None => None,
        };
        let single = |arena: &mut Arena, key: &str| -> Result<Option<f64>> {
            match self.numbers(arena, key)? {
                Some((v, lat)) if v.len() != 1 || v[0].is_nan() || v[0] < 0.0 => {
                    Err(link_error(name, format!("`{key}` is one value >= 0"), lat))
                }
                Some((v, _)) => Ok(Some(v[0])),
                None => Ok(None),
            }
        };
        let velocity_limit = single(arena, "velocity_limit")?;
        let effort_limit = single(arena, "effort_limit")?;
        if *joint == LinkJoint::Fixed
            && let Some(e) = self.entries.iter().find(|e| e.key.ends_with("limit"))
        {
            let problem = format!("a fixed joint has no `{}`", e.key);
            return Err(link_error(name, problem, e.at));
        }
        Ok(Limits {
            position: limit,
            velocity: velocity_limit,
            effort: effort_limit,
        })
    }

    /// The link's points (p_w + R_w p in the world) and axes (as written), with their names
    /// and places.
    fn vectors(
        &self,
        arena: &mut Arena,
        placed: &Placement,
    ) -> Result<Vec<(String, Location, Vec3, bool)>> {
        let mut vectors = Vec::new();
        for e in self
            .entries
            .iter()
            .filter(|e| e.key == "point" || e.key == "axis")
        {
            let pname = e.name.clone().unwrap_or_default();
            let mv = vector_value(arena, &e.value[0], self.cx.names)?;
            let point = e.key == "point";
            let what = if point {
                Quantity::Point(pname.clone())
            } else {
                Quantity::Axis(pname.clone())
            };
            let p = vec3(&mv, what, e.at)?;
            let rp = mat_vec(arena, &placed.rotation, &p)?;
            let world = if point {
                add3(arena, &placed.position, &rp)
            } else {
                p
            };
            vectors.push((pname, e.at, world, point));
        }
        Ok(vectors)
    }
}

/// [0, 0, 0].
fn zero3(arena: &mut Arena) -> Vec3 {
    [arena.int(0), arena.int(0), arena.int(0)]
}

/// I_o = R_c I_c R_c^T + m (|c|^2 1 - c c^T): the inertia about the link origin (parallel
/// axes), 0 for I_c when none is declared.
fn about_origin(
    arena: &mut Arena,
    m: Id,
    c: &Vec3,
    com_rotation: &Matrix,
    inertia_c: Option<&Matrix>,
) -> Result<Matrix> {
    let mut inertia = match inertia_c {
        Some(ic) => com_rotation
            .mul(arena, ic)?
            .mul(arena, &com_rotation.transpose()?)?,
        None => Matrix::zeros(arena, 3, 3),
    };
    let cc = {
        let sq: Vec<Id> = c.iter().map(|&x| arena.mul2(x, x)).collect();
        arena.add(&sq)
    };
    for i in 0..3 {
        for j in 0..3 {
            let cij = arena.mul2(c[i], c[j]);
            let shift = if i == j {
                arena.sub(cc, cij)
            } else {
                arena.neg(cij)
            };
            let shift = arena.mul2(m, shift);
            let v = arena.add2(inertia.get(i, j), shift);
            inertia.set(i, j, v);
        }
    }
    Ok(inertia)
}

/// R(q) of the unit quaternion q = (x, y, z, w) = `configuration[3..7]`:
/// [[1 - 2(y^2 + z^2), 2(xy - zw), 2(xz + yw)],
///  [2(xy + zw), 1 - 2(x^2 + z^2), 2(yz - xw)],
///  [2(xz - yw), 2(yz + xw), 1 - 2(x^2 + y^2)]] (Eigen's and Pinocchio's convention).
pub(crate) fn quaternion_matrix(arena: &mut Arena, configuration: &[Id; 7]) -> Matrix {
    let [x, y, z, w] = [3, 4, 5, 6].map(|k| configuration[k]);
    let two = arena.int(2);
    let one = arena.int(1);
    let mut p = |a: Id, b: Id| arena.mul(&[two, a, b]);
    let (xx, yy, zz) = (p(x, x), p(y, y), p(z, z));
    let (xy, xz, yz) = (p(x, y), p(x, z), p(y, z));
    let (xw, yw, zw) = (p(x, w), p(y, w), p(z, w));
    let d = |arena: &mut Arena, a: Id, b: Id| {
        let s = arena.add2(a, b);
        arena.sub(one, s)
    };
    let entries = [
        d(arena, yy, zz),
        arena.sub(xy, zw),
        arena.add2(xz, yw),
        arena.add2(xy, zw),
        d(arena, xx, zz),
        arena.sub(yz, xw),
        arena.sub(xz, yw),
        arena.add2(yz, xw),
        d(arena, xx, yy),
    ];
    Matrix::from_fn(3, 3, |i, j| entries[3 * i + j])
}
