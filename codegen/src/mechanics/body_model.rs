//! Lowering of the body sections ([`crate::syntax::bodies`]) into the arena: world vectors of
//! points and axes, orientations, the [`BodySystem`] handed to [`add_body_terms`], and the
//! joint rows appended to the model's constraints. Items are built in declaration order.

use std::collections::HashMap;

use crate::algebra::eval::eval;
use crate::algebra::expr::{Arena, Id, SymbolId, Vec3};
use crate::algebra::matrix::Matrix;
use crate::algebra::rotation::{Axis, Orientation, RotationFactor};
use crate::error::{DeclarationError, Error, Location, Needed, Quantity, Result};
use crate::mechanics::bodies::{Body, BodySystem, Damper, Spring, add_body_terms};
use crate::mechanics::body_checks::{check_inertia, check_mass, check_orientation, check_radius};
use crate::mechanics::drawing::Drawing;
use crate::mechanics::drawing::build_drawing;
use crate::mechanics::joints::{
    AxisFrame, distance, least_aligned, perpendiculars, prismatic, revolute, spherical,
};
use crate::mechanics::links::{LinkContext, build_link};
use crate::mechanics::model::{Constraint, Coordinate, Model, RotationSequence};
use crate::mechanics::rolling::{Wheel, rolling_rows, tilt_squared_at};
use crate::mechanics::tree::Link;
use crate::mechanics::vectors::{VectorNames, scalar, vec3, vector_value};
use crate::syntax::ast::Ast;
use crate::syntax::bodies::{Bodies, BodyItem, Entry, Joint};
use crate::syntax::declaration::components;

/// The naming context: named world vectors, axis frames and body frames.
#[derive(Default)]
struct Scope {
    vectors: HashMap<String, Vec3>,
    /// The keys of `vectors` in declaration order.
    order: Vec<String>,
    axes: HashMap<String, AxisFrame>,
}

impl VectorNames for Scope {
    fn vector(&self, name: &str) -> Option<[crate::algebra::expr::Id; 3]> {
        self.vectors.get(name).copied()
    }

    fn names(&self) -> Vec<&str> {
        self.order.iter().map(String::as_str).collect()
    }
}

fn declaration(kind: DeclarationError, location: Location) -> Error {
    Error::declaration(kind, location)
}

/// "the {block} `{name}` needs {entry}".
fn missing(block: &str, name: &str, entry: Needed, at: Location) -> Error {
    let kind = DeclarationError::MissingEntry {
        block: block.to_string(),
        name: name.to_string(),
        entry,
    };
    declaration(kind, at)
}

/// The parameter defaults of `model`, for choosing axis perpendiculars.
fn defaults(model: &Model) -> Vec<(SymbolId, f64)> {
    model
        .parameters
        .iter()
        .filter_map(|p| model.arena.as_symbol(p.symbol).map(|s| (s, p.default)))
        .collect()
}

/// The axis frame of the body direction `a0` (body components) turned by `r`.
fn axis_frame(
    arena: &mut Arena,
    a0: &Vec3,
    r: &Matrix,
    known: &[(SymbolId, f64)],
    at: Location,
) -> Result<AxisFrame> {
    let env = |s: SymbolId| known.iter().find(|k| k.0 == s).map(|k| k.1);
    let mut vals = [0.0; 3];
    for (v, &e) in vals.iter_mut().zip(a0) {
        *v = eval(arena, e, &env).map_err(|e| {
            let kind = DeclarationError::AxisNotConstant { error: Box::new(e) };
            declaration(kind, at)
        })?;
    }
    if vals.iter().all(|v| *v == 0.0) {
        return Err(declaration(DeclarationError::ZeroAxis, at));
    }
    let k = least_aligned(vals);
    let [p1, p2] = perpendiculars(arena, a0, k);
    let turn = |arena: &mut Arena, v: &Vec3| -> Result<Vec3> {
        let w = r.mul(arena, &Matrix::column(v.to_vec()))?;
        Ok([w.data[0], w.data[1], w.data[2]])
    };
    Ok(AxisFrame {
        direction: turn(arena, a0)?,
        perpendicular: [turn(arena, &p1)?, turn(arena, &p2)?],
    })
}

/// The factors of an orientation product as written: `F_1 * F_2 * ...` (parenthesised
/// products flattened); a chain with a division keeps everything up to its last divisor as
/// one factor, since only a pure product is a sequence of rotations.
fn product_factors(ast: &Ast, out: &mut Vec<Ast>) {
    let Ast::Product(items) = ast else {
        out.push(ast.clone());
        return;
    };
    let rest = match items.iter().rposition(|i| i.0) {
        Some(last_divisor) => {
            out.push(Ast::Product(items[..=last_divisor].to_vec()));
            &items[last_divisor + 1..]
        }
        None => &items[..],
    };
    for (_, f, _) in rest {
        product_factors(f, out);
    }
}

/// The orientation of a body: the top-level product's factors, elementary where written
/// `rot_x/y/z(angle)`, explicit 3x3 otherwise.
fn orientation(arena: &mut Arena, ast: &Ast, scope: &Scope) -> Result<Orientation> {
    let mut factors = Vec::new();
    let mut flat = Vec::new();
    product_factors(ast, &mut flat);
    for f in &flat {
        match f {
            Ast::Call(name, args, at) if name.starts_with("rot_") && args.len() == 1 => {
                let axis = match name.as_str() {
                    "rot_x" => Axis::X,
                    "rot_y" => Axis::Y,
                    _ => Axis::Z,
                };
                let v = vector_value(arena, &args[0], scope)?;
                factors.push(RotationFactor::Elementary(
                    axis,
                    scalar(&v, Quantity::RotationAngle, *at)?,
                ));
            }
            other => {
                let m = vector_value(arena, other, scope)?;
                if (m.rows, m.cols) != (3, 3) {
                    let (rows, cols) = (m.rows, m.cols);
                    let kind = DeclarationError::OrientationFactor { rows, cols };
                    return Err(declaration(kind, other.location()));
                }
                factors.push(RotationFactor::Explicit(m));
            }
        }
    }
    Ok(Orientation { factors })
}

fn take<'e>(entries: &'e [Entry], key: &str, owner: &str) -> Result<Option<&'e Entry>> {
    let mut found = entries.iter().filter(|e| e.key == key);
    let first = found.next();
    if let Some(second) = found.next() {
        let kind = DeclarationError::GivenTwice {
            key: key.to_string(),
            owner: owner.to_string(),
        };
        return Err(declaration(kind, second.at));
    }
    Ok(first)
}

fn define(scope: &mut Scope, name: &str, at: Location, v: Vec3) -> Result<()> {
    if scope.vectors.insert(name.to_string(), v).is_some() {
        let kind = DeclarationError::VectorNameTwice {
            name: name.to_string(),
        };
        return Err(declaration(kind, at));
    }
    scope.order.push(name.to_string());
    Ok(())
}

/// Lowers the body sections into `model`: adds T, Pi and the damper forces
/// ([`add_body_terms`]) and appends the joint rows to `model.constraints`.
pub(crate) fn build_bodies(bodies: &Bodies, model: &mut Model) -> Result<()> {
    if bodies.items.is_empty() {
        return Ok(());
    }
    let mut lowering = Lowering::new(model);
    check_names_free(bodies, model)?;
    for item in &bodies.items {
        lowering.item(item, model)?;
    }
    lowering.finish(bodies, model)
}

/// No point, axis, body, spring, damper or link is named like a parameter or coordinate.
fn check_names_free(bodies: &Bodies, model: &Model) -> Result<()> {
    for name in model
        .parameters
        .iter()
        .map(|p| p.name.as_str())
        .chain(model.coordinates.iter().map(|c| c.name.as_str()))
    {
        if let Some(at) = named_at(bodies, name) {
            let kind = DeclarationError::NameTaken {
                name: name.to_string(),
            };
            return Err(declaration(kind, at));
        }
    }
    Ok(())
}

/// The body sections as they are lowered item by item, in declaration order (later items
/// use the names that earlier ones define).
struct Lowering {
    /// The parameters at their declared values.
    known: Vec<(SymbolId, f64)>,
    /// The declared values and the initial guesses at t = 0, for the orientation check.
    at_guesses: Vec<(SymbolId, f64)>,
    /// The coordinates' symbols.
    coordinate_symbols: Vec<SymbolId>,
    /// The coordinates' symbols and t: what a drawn point may move with.
    moving: Vec<SymbolId>,
    scope: Scope,
    system: BodySystem,
    rows: Vec<Constraint>,
    /// The joint rows that vanish identically (`Model::vanished_rows`).
    vanished: Vec<String>,
    velocity_rows: Vec<Constraint>,
    drawing: Option<Drawing>,
    links: Vec<Link>,
    orientations: Vec<Orientation>,
}

impl Lowering {
    fn new(model: &Model) -> Self {
        let known = defaults(model);
        let mut at_guesses = known.clone();
        at_guesses.extend(
            model
                .coordinates
                .iter()
                .filter_map(|c| Some((model.arena.as_symbol(c.q)?, c.guess))),
        );
        at_guesses.extend(model.arena.as_symbol(model.time).map(|s| (s, 0.0)));
        let coordinate_symbols: Vec<SymbolId> = model
            .coordinates
            .iter()
            .filter_map(|c| model.arena.as_symbol(c.q))
            .collect();
        let mut moving = coordinate_symbols.clone();
        moving.extend(model.arena.as_symbol(model.time));
        Lowering {
            known,
            at_guesses,
            coordinate_symbols,
            moving,
            scope: Scope::default(),
            system: BodySystem::default(),
            rows: Vec::new(),
            vanished: Vec::new(),
            velocity_rows: Vec::new(),
            drawing: None,
            links: Vec::new(),
            orientations: Vec::new(),
        }
    }

    /// Lowers one item: one match arm per kind of body-section item.
    fn item(&mut self, item: &BodyItem, model: &mut Model) -> Result<()> {
        let arena = &mut model.arena;
        let scope = &mut self.scope;
        match item {
            BodyItem::Gravity(v, at) => {
                if self.system.gravity.is_some() {
                    return Err(declaration(DeclarationError::GravityTwice, *at));
                }
                let m = vector_value(arena, v, scope)?;
                self.system.gravity = Some(vec3(&m, Quantity::Gravity, *at)?);
            }
            BodyItem::Point(name, at, v) => {
                let m = vector_value(arena, v, scope)?;
                let p = vec3(&m, Quantity::Point(name.clone()), *at)?;
                define(scope, name, *at, p)?;
            }
            BodyItem::Axis(name, at, v) => {
                let m = vector_value(arena, v, scope)?;
                let a = vec3(&m, Quantity::Axis(name.clone()), *at)?;
                let id = Matrix::identity(arena, 3);
                let frame = axis_frame(arena, &a, &id, &self.known, *at)?;
                define(scope, name, *at, frame.direction)?;
                scope.axes.insert(name.clone(), frame);
            }
            BodyItem::Body { name, at, entries } => {
                let (known, guesses) = (&self.known, &self.at_guesses);
                let body = build_body(arena, name, *at, entries, scope, known, guesses)?;
                if let Some(orientation) = &body.orientation {
                    let sequence =
                        RotationSequence::of(arena, name, orientation, &model.coordinates);
                    model.rotations.push(sequence);
                }
                self.system.bodies.push(body);
            }
            BodyItem::Spring { name, at, entries } | BodyItem::Damper { name, at, entries } => {
                let spring = matches!(item, BodyItem::Spring { .. });
                let element = Element {
                    name,
                    at: *at,
                    entries,
                };
                element.lower(arena, scope, spring, &mut self.system)?;
            }
            BodyItem::Link { name, at, entries } => {
                self.link(arena, &model.coordinates, name, *at, entries)?;
            }
            BodyItem::Joint(Joint::Helper(h, args, at)) if h == "rolling" => {
                let cx = RollingContext {
                    scope,
                    bodies: &self.system.bodies,
                    q: &self.coordinate_symbols,
                    time: arena.as_symbol(model.time),
                    at_guesses: &self.at_guesses,
                };
                let [height, slip_x, slip_y] = rolling_statement(arena, args, *at, &cx)?;
                self.rows.push(height);
                self.velocity_rows.extend([slip_x, slip_y]);
            }
            BodyItem::Joint(j) => {
                let rows = joint_rows(arena, j, scope, &self.at_guesses)?;
                if rows.iter().all(|r| arena.is_zero(r.expr)) {
                    // Constrains nothing at all: the check names the statement.
                    self.rows.extend(rows);
                } else {
                    let (zero, kept): (Vec<_>, Vec<_>) =
                        rows.into_iter().partition(|r| arena.is_zero(r.expr));
                    if let Some(first) = zero.first() {
                        let components: Vec<&str> =
                            zero.iter().map(|r| r.component.as_str()).collect();
                        let vanished = format!("{} ({})", first.joint, components.join(", "));
                        self.vanished.push(vanished);
                    }
                    self.rows.extend(kept);
                }
            }
            BodyItem::Draw(d) => {
                if self.drawing.is_some() {
                    return Err(Error::declaration(DeclarationError::DrawTwice, d.at));
                }
                self.drawing = Some(build_drawing(
                    arena,
                    d,
                    |n| scope.vectors.get(n).copied(),
                    |n| scope.axes.contains_key(n),
                    &self.moving,
                )?);
            }
        }
        Ok(())
    }

    /// Builds a link ([`build_link`]) and defines its name (its origin), points and axes.
    fn link(
        &mut self,
        arena: &mut Arena,
        coordinates: &[Coordinate],
        name: &str,
        at: Location,
        entries: &[Entry],
    ) -> Result<()> {
        let cx = LinkContext {
            known: &self.known,
            coordinates,
            links: &self.links,
            orientations: &self.orientations,
            names: &self.scope,
        };
        let built = build_link(arena, name, at, entries, &cx)?;
        let scope = &mut self.scope;
        define(scope, name, at, built.link.position)?;
        for (pname, pat, v, point) in built.vectors {
            if point {
                define(scope, &pname, pat, v)?;
            } else {
                let frame = axis_frame(arena, &v, &built.link.rotation, &self.known, pat)?;
                define(scope, &pname, pat, frame.direction)?;
                scope.axes.insert(pname, frame);
            }
        }
        self.system.bodies.extend(built.body);
        self.links.push(built.link);
        self.orientations.push(built.orientation);
        Ok(())
    }

    /// Moves what the items built into `model`: the drawing, the links and which route
    /// they take, gravity, T and Pi ([`add_body_terms`]) and the joint rows.
    fn finish(mut self, bodies: &Bodies, model: &mut Model) -> Result<()> {
        model.drawing = self.drawing.unwrap_or_default();
        model.kinetic_from_links = !self.links.is_empty()
            && model.arena.is_zero(model.kinetic)
            && !bodies
                .items
                .iter()
                .any(|i| matches!(i, BodyItem::Body { .. }));
        model.potential_from_links = model.kinetic_from_links
            && model.arena.is_zero(model.potential)
            && self.system.springs.is_empty();
        model.gravity = self.system.gravity;
        model.links = self.links;
        if model.kinetic_from_links {
            // No `body` is declared: every body is a link's, and the recursive route needs
            // none of their energies (their T alone is O(n^3) for a chain of n links).
            model.link_bodies = std::mem::take(&mut self.system.bodies);
        }
        add_body_terms(model, &self.system)?;
        model.constraints.extend(self.rows);
        model.vanished_rows = self.vanished;
        model.velocity_constraints.extend(self.velocity_rows);
        Ok(())
    }
}

/// A spring or damper item: its name, place and entries.
struct Element<'a> {
    name: &'a str,
    at: Location,
    entries: &'a [Entry],
}

impl Element<'_> {
    /// The scalar entry `key`, if given.
    fn value(&self, arena: &mut Arena, key: &str, scope: &Scope) -> Result<Option<Id>> {
        match take(self.entries, key, self.name)? {
            Some(e) => {
                let m = vector_value(arena, &e.value[0], scope)?;
                Ok(Some(scalar(&m, Quantity::Entry(key.to_string()), e.at)?))
            }
            None => Ok(None),
        }
    }

    /// A spring (stiffness, free length 0 unless given) or a damper (coefficient) between
    /// the two ends of `between`, added to `system`.
    fn lower(
        &self,
        arena: &mut Arena,
        scope: &Scope,
        spring: bool,
        system: &mut BodySystem,
    ) -> Result<()> {
        let (name, at) = (self.name, self.at);
        let what = if spring { "spring" } else { "damper" };
        let between = take(self.entries, "between", name)?
            .ok_or_else(|| missing(what, name, Needed::Between, at))?;
        let mut ends = Vec::new();
        for v in &between.value {
            let m = vector_value(arena, v, scope)?;
            ends.push(vec3(&m, Quantity::End(name.to_string()), v.location())?);
        }
        let ends = [ends[0], ends[1]];
        if spring {
            let stiffness = self
                .value(arena, "stiffness", scope)?
                .ok_or_else(|| missing("spring", name, Needed::Stiffness, at))?;
            let free_length = match self.value(arena, "free_length", scope)? {
                Some(l) => l,
                None => arena.int(0),
            };
            system.springs.push(Spring {
                name: name.to_string(),
                ends,
                stiffness,
                free_length,
            });
        } else {
            let coefficient = self
                .value(arena, "coefficient", scope)?
                .ok_or_else(|| missing("damper", name, Needed::Coefficient, at))?;
            system.dampers.push(Damper {
                name: name.to_string(),
                ends,
                coefficient,
            });
        }
        Ok(())
    }
}

/// What a `rolling` statement reads: the names, the bodies so far, the coordinate and time
/// symbols and the values at the initial guesses.
struct RollingContext<'a> {
    scope: &'a Scope,
    bodies: &'a [Body],
    q: &'a [SymbolId],
    time: Option<SymbolId>,
    at_guesses: &'a [(SymbolId, f64)],
}

/// `rolling(B, a, r)` (see [`crate::mechanics::rolling`]): the contact-height row, then the
/// two sliding rows (velocity level), labelled with the statement and `z`, `x`, `y`.
fn rolling_statement(
    arena: &mut Arena,
    args: &[Ast],
    at: Location,
    cx: &RollingContext<'_>,
) -> Result<[Constraint; 3]> {
    let body = match &args[0] {
        Ast::Name(n, _) => cx
            .bodies
            .iter()
            .find(|b| &b.name == n && b.orientation.is_some()),
        _ => None,
    };
    let Some(body) = body else {
        let kind = DeclarationError::RollingNeedsBody {
            found: args[0].text(),
        };
        return Err(declaration(kind, args[0].location()));
    };
    let m = vector_value(arena, &args[1], cx.scope)?;
    let axis = vec3(&m, helper_argument("rolling", 2), args[1].location())?;
    let m = vector_value(arena, &args[2], cx.scope)?;
    let radius = scalar(&m, helper_argument("rolling", 3), args[2].location())?;
    check_radius(arena, &body.name, radius, cx.at_guesses, args[2].location())?;
    let Some(orientation) = &body.orientation else {
        unreachable!("the body was found with an orientation");
    };
    let wheel = Wheel {
        centre: &body.position,
        orientation,
        axis: &axis,
        radius,
    };
    let built = rolling_rows(arena, &wheel, cx.q, cx.time)?;
    // NaN counts as vertical: the contact is undefined there too.
    if !tilt_squared_at(arena, &built, cx.at_guesses).is_some_and(|v| v > 1e-12) {
        let kind = DeclarationError::RollingAxisVertical {
            body: body.name.clone(),
        };
        return Err(declaration(kind, args[1].location()));
    }
    let written: Vec<String> = args.iter().map(Ast::text).collect();
    let joint = format!("rolling({})", written.join(", "));
    let row = |expr, component: &str| Constraint {
        expr,
        location: at,
        joint: joint.clone(),
        component: component.to_string(),
    };
    Ok([
        row(built.height, "z"),
        row(built.slip[0], "x"),
        row(built.slip[1], "y"),
    ])
}

/// The quantity "argument `index` of `helper`".
fn helper_argument(helper: &str, index: usize) -> Quantity {
    Quantity::HelperArgument {
        helper: helper.to_string(),
        index,
    }
}

/// Where `name` is declared as a body, point or axis.
fn named_at(bodies: &Bodies, name: &str) -> Option<Location> {
    bodies.items.iter().find_map(|i| match i {
        BodyItem::Body {
            name: n,
            at,
            entries,
        }
        | BodyItem::Link {
            name: n,
            at,
            entries,
        } => {
            if n == name {
                return Some(*at);
            }
            entries
                .iter()
                .find(|e| e.name.as_deref() == Some(name))
                .map(|e| e.at)
        }
        BodyItem::Point(n, at, _) | BodyItem::Axis(n, at, _) if n == name => Some(*at),
        _ => None,
    })
}

// One function: one step per body key (mass, position, orientation, inertia, points, axes),
// in the order in which the later ones need the earlier ones.
fn build_body(
    arena: &mut Arena,
    name: &str,
    at: Location,
    entries: &[Entry],
    scope: &mut Scope,
    known: &[(SymbolId, f64)],
    at_guesses: &[(SymbolId, f64)],
) -> Result<Body> {
    // A body without a mass would silently carry none: a massless frame says `mass = 0;`.
    let me = take(entries, "mass", name)?.ok_or_else(|| missing("body", name, Needed::Mass, at))?;
    let mass = {
        let m = vector_value(arena, &me.value[0], scope)?;
        scalar(&m, Quantity::Mass, me.at)?
    };
    check_mass(arena, name, mass, known, me.at)?;
    let pe = take(entries, "position", name)?
        .ok_or_else(|| missing("body", name, Needed::Position, at))?;
    let pm = vector_value(arena, &pe.value[0], scope)?;
    let position = vec3(&pm, Quantity::Position, pe.at)?;
    let orient = match take(entries, "orientation", name)? {
        Some(e) => {
            let o = orientation(arena, &e.value[0], scope)?;
            check_orientation(arena, name, &o, at_guesses, e.at)?;
            Some(o)
        }
        None => None,
    };
    let inertia = match take(entries, "inertia", name)? {
        Some(e) => {
            if orient.is_none() {
                let kind = DeclarationError::InertiaWithoutOrientation {
                    body: name.to_string(),
                };
                return Err(declaration(kind, e.at));
            }
            let m = vector_value(arena, &e.value[0], scope)?;
            if (m.rows, m.cols) != (3, 3) {
                let (rows, cols) = (m.rows, m.cols);
                let kind = DeclarationError::InertiaNot3x3 { rows, cols };
                return Err(declaration(kind, e.at));
            }
            check_inertia(arena, name, &m, known, e.at)?;
            Some(m)
        }
        None => None,
    };
    let r = match &orient {
        Some(o) => o.matrix(arena)?,
        None => Matrix::identity(arena, 3),
    };
    define(scope, name, at, position)?;
    for e in entries
        .iter()
        .filter(|e| e.key == "point" || e.key == "axis")
    {
        let pname = e.name.clone().unwrap_or_default();
        if orient.is_none() {
            let kind = DeclarationError::OnPointMass {
                key: e.key.clone(),
                name: pname,
                body: name.to_string(),
            };
            return Err(declaration(kind, e.at));
        }
        let m = vector_value(arena, &e.value[0], scope)?;
        let what = if e.key == "point" {
            Quantity::Point(pname.clone())
        } else {
            Quantity::Axis(pname.clone())
        };
        let p = vec3(&m, what, e.at)?;
        if e.key == "point" {
            let rp = r.mul(arena, &Matrix::column(p.to_vec()))?;
            let world = [0, 1, 2].map(|i| arena.add2(position[i], rp.data[i]));
            define(scope, &pname, e.at, world)?;
        } else {
            let frame = axis_frame(arena, &p, &r, known, e.at)?;
            define(scope, &pname, e.at, frame.direction)?;
            scope.axes.insert(pname, frame);
        }
    }
    Ok(Body {
        name: name.to_string(),
        mass,
        position,
        orientation: orient,
        inertia,
    })
}

/// The rows of one `joints` statement, labelled with the statement as written and the
/// component of each row (see [`Constraint::joint`]).
// One function: one match arm per joint kind, each its rows (see `mechanics::joints`).
/// The rows of joint `j`; `at_guesses` (the parameter defaults, the coordinates' guesses
/// and t = 0) fixes where a prismatic joint locks its twist.
fn joint_rows(
    arena: &mut Arena,
    j: &Joint,
    scope: &Scope,
    at_guesses: &[(SymbolId, f64)],
) -> Result<Vec<Constraint>> {
    let (exprs, components, joint, at) = match j {
        Joint::Row(lhs, rhs, at) => {
            let l = vector_value(arena, lhs, scope)?;
            let v = match rhs {
                Some(r) => {
                    let r = vector_value(arena, r, scope)?;
                    if (l.rows, l.cols) != (r.rows, r.cols) {
                        let (left, right) = ((l.rows, l.cols), (r.rows, r.cols));
                        let kind = DeclarationError::JointRowShapes { left, right };
                        return Err(declaration(kind, *at));
                    }
                    l.sub(arena, &r)?
                }
                None => l,
            };
            let joint = match rhs {
                Some(r) => format!("{} = {}", lhs.text(), r.text()),
                None => lhs.text(),
            };
            (v.data, components(v.rows, v.cols), joint, *at)
        }
        Joint::Helper(h, args, at) => {
            let v = |arena: &mut Arena, i: usize| -> Result<Vec3> {
                let m = vector_value(arena, &args[i], scope)?;
                let what = Quantity::HelperArgument {
                    helper: h.clone(),
                    index: i + 1,
                };
                vec3(&m, what, args[i].location())
            };
            let frame = |i: usize| -> Result<AxisFrame> {
                match &args[i] {
                    Ast::Name(n, _) if scope.axes.contains_key(n) => Ok(scope.axes[n].clone()),
                    other => {
                        let kind = DeclarationError::NotAnAxis {
                            helper: h.clone(),
                            index: i + 1,
                        };
                        Err(declaration(kind, other.location()))
                    }
                }
            };
            let (p, q) = (v(arena, 0)?, v(arena, 1)?);
            let (rows, components): (_, &[&str]) = match h.as_str() {
                "spherical" => (spherical(arena, &p, &q), &["x", "y", "z"]),
                "distance" => {
                    let m = vector_value(arena, &args[2], scope)?;
                    let l = scalar(&m, Quantity::Distance, args[2].location())?;
                    (distance(arena, &p, &q, l), &[""])
                }
                "revolute" => {
                    let a = v(arena, 2)?;
                    let b = frame(3)?;
                    (
                        revolute(arena, &p, &q, &a, &b),
                        &["x", "y", "z", "axis 1", "axis 2"],
                    )
                }
                _ => {
                    let (a, b) = (frame(2)?, frame(3)?);
                    (
                        prismatic(arena, &p, &q, &a, &b, at_guesses),
                        &["axis 1", "axis 2", "slide 1", "slide 2", "twist"],
                    )
                }
            };
            let written: Vec<String> = args.iter().map(Ast::text).collect();
            let joint = format!("{h}({})", written.join(", "));
            let components = components.iter().map(|c| c.to_string()).collect();
            (rows, components, joint, *at)
        }
    };
    debug_assert_eq!(exprs.len(), components.len());
    Ok(exprs
        .into_iter()
        .zip(components)
        .map(|(expr, component)| Constraint {
            expr,
            location: at,
            joint: joint.clone(),
            component,
        })
        .collect())
}
