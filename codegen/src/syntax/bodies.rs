//! The body sections of a declaration: their grammar and syntax tree (built into a
//! [`BodySystem`](crate::BodySystem) and constraint rows of the [`Model`](crate::Model) by
//! `mechanics::body_model`).
//!
//! ```text
//! body_section := "body" NAME "{" (body_item ";")* "}"
//!               | "gravity" "=" vexpr ";"                     world vector g
//!               | "point" NAME "=" vexpr ";"                  a ground (or derived) point, world
//!               | "axis" NAME "=" vexpr ";"                   a ground direction, world
//!               | "spring" NAME "{" "between" "=" vexpr "," vexpr ";"
//!                     "stiffness" "=" vexpr ";" ["free_length" "=" vexpr ";"] "}"
//!               | "damper" NAME "{" "between" "=" vexpr "," vexpr ";"
//!                     "coefficient" "=" vexpr ";" "}"
//!               | "joints" "{" (joint ";")* "}"
//!               | "draw" "{" .. "}"                           lines through points (syntax::draw)
//!               | "link" NAME "{" (link_item ";")* "}"       a frame of a kinematic tree
//! body_item    := "mass" "=" vexpr                            m
//!               | "position" "=" vexpr                        centre of mass r(q, t), world
//!               | "orientation" "=" vexpr                     R = F_1 * F_2 * ... (body to world)
//!               | "inertia" "=" vexpr                         3x3 about the centre, body axes
//!               | "point" NAME "=" vexpr                      body coordinates p: world r + R p
//!               | "axis" NAME "=" vexpr                       body direction a: world R a
//! link_item    := "parent" "=" NAME                           a link above, or `world` (default)
//!               | "joint" "=" KIND "(" COORD "," vexpr ")"     KIND: revolute, continuous,
//!                                                              prismatic; the axis in the joint frame
//!               | "joint" "=" "fixed"                         (the default)
//!               | "xyz" "=" vexpr | "rpy" "=" vexpr           joint frame in the parent frame
//!               | "limit" "=" vexpr | "velocity_limit" "=" expr | "effort_limit" "=" expr
//!               | "mass" "=" vexpr | "com" "=" vexpr | "com_rpy" "=" vexpr
//!               | "inertia" "=" vexpr                         about the com, com_rpy axes
//!               | "point" NAME "=" vexpr | "axis" NAME "=" vexpr   link-frame coordinates
//! joint        := "spherical" "(" P "," Q ")"                 3 rows: P - Q
//!               | "revolute" "(" P "," Q "," a "," b ")"      5 rows: P - Q, a parallel to b
//!               | "prismatic" "(" P "," Q "," a "," b ")"     5 rows
//!               | "distance" "(" P "," Q "," L ")"            1 row: |P - Q|^2 - L^2
//!               | "rolling" "(" BODY "," a "," r ")"          thin wheel on z = 0: 1 row (the
//!                                                              contact height), 2 velocity rows
//!               | vexpr ["=" vexpr]                           one row per entry (B = C: 3 rows)
//! ```
//! `vexpr` is the vector expression language of [`crate::syntax::expression`] (points, axes and
//! bodies are names of 3-vectors; `B.z` is a component). A body without `orientation` is a
//! point mass (it may not carry `inertia`, points or axes). In `revolute` and `prismatic`, `b`
//! (and, for `prismatic`, `a`) must be a declared axis: its two perpendiculars are fixed to its
//! body (see [`crate::mechanics::joints`]).
//!
//! With bodies (or springs) declared, `kinetic` and `potential` are optional: T and Pi are
//! derived (see [`crate::mechanics::bodies`]), and hand-written energies are added to them.
//!
//! Everything is built in declaration order, so a body may use the points of bodies
//! declared before it (`position = B + rot_z(beta) * [0, 0, l2/2];`).

use crate::error::{Error, Expected, Location, ParseError, Result};
use crate::syntax::ast::Ast;
use crate::syntax::draw::{DrawSection, parse_draw};
use crate::syntax::expression::{HELPERS, Language, parse};
use crate::syntax::lex::{Cursor, Tok, block, name};

/// The top-level keywords of the body sections.
pub(crate) const BODY_SECTIONS: &[&str] = &[
    "body", "gravity", "point", "axis", "spring", "damper", "joints", "draw", "link",
];

/// The joint kinds of a link that move: each carries a coordinate.
pub(crate) const MOVING_JOINTS: &[&str] = &["revolute", "continuous", "prismatic"];

/// The joint of a floating root link, `floating(NAME)`: six degrees of freedom relative to
/// the world, its configuration the position and unit quaternion `NAME_x`, .., `NAME_qw`
/// and its velocity `NAME_vx`, .., `NAME_wz` in the link's frame (`mechanics::floating`).
pub(crate) const FLOATING_JOINT: &str = "floating";

/// True when `keyword` starts a body section.
pub(crate) fn is_body_section(keyword: &str) -> bool {
    BODY_SECTIONS.contains(&keyword)
}

/// `key = value` with where the key is.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Entry {
    /// The key (`mass`, `point`, `between`, ...).
    pub(crate) key: String,
    /// The name after `point` or `axis`.
    pub(crate) name: Option<String>,
    /// Where the key is.
    pub(crate) at: Location,
    /// The value (two for `between`).
    pub(crate) value: Vec<Ast>,
}

/// One top-level body item, in declaration order.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum BodyItem {
    Body {
        name: String,
        at: Location,
        entries: Vec<Entry>,
    },
    Gravity(Ast, Location),
    Point(String, Location, Ast),
    Axis(String, Location, Ast),
    Spring {
        name: String,
        at: Location,
        entries: Vec<Entry>,
    },
    Damper {
        name: String,
        at: Location,
        entries: Vec<Entry>,
    },
    Joint(Joint),
    Draw(DrawSection),
    /// A link of a kinematic tree (see [`crate::mechanics::links`]).
    Link {
        name: String,
        at: Location,
        entries: Vec<Entry>,
    },
}

/// A constraint statement of `joints`.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Joint {
    Helper(String, Vec<Ast>, Location),
    Row(Ast, Option<Ast>, Location),
}

/// All body sections of a declaration.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Bodies {
    pub(crate) items: Vec<BodyItem>,
}

impl Bodies {
    /// True when bodies or springs declare energy (then `kinetic` may be left out).
    pub(crate) fn declares_energy(&self) -> bool {
        self.items.iter().any(|i| {
            matches!(
                i,
                BodyItem::Body { .. } | BodyItem::Spring { .. } | BodyItem::Link { .. }
            )
        })
    }

    /// The location of the first body item, if any.
    pub(crate) fn first_location(&self) -> Option<Location> {
        self.items.first().map(|i| match i {
            BodyItem::Body { at, .. }
            | BodyItem::Link { at, .. }
            | BodyItem::Spring { at, .. }
            | BodyItem::Damper { at, .. }
            | BodyItem::Gravity(_, at)
            | BodyItem::Point(_, at, _)
            | BodyItem::Axis(_, at, _)
            | BodyItem::Joint(Joint::Helper(_, _, at) | Joint::Row(_, _, at)) => *at,
            BodyItem::Draw(d) => d.at,
        })
    }

    /// The number of constraint rows the `joints` statements add (by shapes, before evaluation).
    pub(crate) fn constraint_rows(&self) -> usize {
        let mut vectors: Vec<&str> = Vec::new();
        for i in &self.items {
            match i {
                BodyItem::Body { name, entries, .. } | BodyItem::Link { name, entries, .. } => {
                    vectors.push(name);
                    for e in entries {
                        if let Some(n) = &e.name {
                            vectors.push(n);
                        }
                    }
                }
                BodyItem::Point(n, _, _) | BodyItem::Axis(n, _, _) => vectors.push(n),
                _ => {}
            }
        }
        let is_vector = |n: &str| vectors.contains(&n);
        self.items
            .iter()
            .map(|i| match i {
                BodyItem::Joint(Joint::Helper(h, _, _)) => match h.as_str() {
                    "spherical" => 3,
                    "distance" => 1,
                    // The contact height, and the contact point's two ground velocities.
                    "rolling" => 3,
                    _ => 5,
                },
                BodyItem::Joint(Joint::Row(lhs, _, _)) => {
                    lhs.shape(&is_vector).map_or(1, |s| s.0 * s.1)
                }
                _ => 0,
            })
            .sum()
    }
}

/// Parses the body section starting with `keyword` (already consumed, at `at`).
pub(crate) fn parse_body_section(
    c: &mut Cursor<'_>,
    keyword: &str,
    at: Location,
    bodies: &mut Bodies,
) -> Result<()> {
    match keyword {
        "gravity" => {
            let written = "gravity".to_string();
            c.expect(&Tok::Punct('='), Expected::EqualsAfter { written })?;
            let v = parse(c, Language::Vector)?;
            c.expect(&Tok::Punct(';'), Expected::GravitySemicolon)?;
            bodies.items.push(BodyItem::Gravity(v, at));
        }
        "point" | "axis" => {
            let (name, nat) = name(c, keyword)?;
            let written = format!("{keyword} {name}");
            c.expect(&Tok::Punct('='), Expected::EqualsAfter { written })?;
            let v = parse(c, Language::Vector)?;
            c.expect(&Tok::Punct(';'), Expected::Semicolon)?;
            bodies.items.push(if keyword == "point" {
                BodyItem::Point(name, nat, v)
            } else {
                BodyItem::Axis(name, nat, v)
            });
        }
        "body" | "spring" | "damper" | "link" => {
            let (name, nat) = name(c, keyword)?;
            let entries = block(c, |c| entry(c, keyword))?;
            bodies.items.push(match keyword {
                "body" => BodyItem::Body {
                    name,
                    at: nat,
                    entries,
                },
                "link" => BodyItem::Link {
                    name,
                    at: nat,
                    entries,
                },
                "spring" => BodyItem::Spring {
                    name,
                    at: nat,
                    entries,
                },
                _ => BodyItem::Damper {
                    name,
                    at: nat,
                    entries,
                },
            });
        }
        "draw" => bodies.items.push(BodyItem::Draw(parse_draw(c, at)?)),
        _ => {
            let joints = block(c, joint)?;
            bodies.items.extend(joints.into_iter().map(BodyItem::Joint));
        }
    }
    Ok(())
}

/// The keys each block accepts.
fn keys(block: &str) -> &'static [&'static str] {
    match block {
        "body" => &[
            "mass",
            "position",
            "orientation",
            "inertia",
            "point",
            "axis",
        ],
        "link" => &[
            "parent",
            "joint",
            "xyz",
            "rpy",
            "limit",
            "velocity_limit",
            "effort_limit",
            "mass",
            "com",
            "com_rpy",
            "inertia",
            "point",
            "axis",
        ],
        "spring" => &["between", "stiffness", "free_length"],
        _ => &["between", "coefficient"],
    }
}

fn entry(c: &mut Cursor<'_>, block: &str) -> Result<Entry> {
    let (key, at) = name(c, block)?;
    if !keys(block).contains(&key.as_str()) {
        let kind = ParseError::UnknownEntry {
            key,
            block: block.to_string(),
            keys: keys(block),
        };
        return Err(Error::parse(kind, at));
    }
    let name = if key == "point" || key == "axis" {
        Some(name(c, &key)?.0)
    } else {
        None
    };
    let written = key.clone();
    c.expect(&Tok::Punct('='), Expected::EqualsAfter { written })?;
    if block == "link" && key == "joint" {
        let value = vec![link_joint(c)?];
        return Ok(Entry {
            key,
            name: None,
            at,
            value,
        });
    }
    let mut value = vec![parse(c, Language::Vector)?];
    if key == "between" {
        c.expect(&Tok::Punct(','), Expected::BetweenComma)?;
        value.push(parse(c, Language::Vector)?);
    }
    Ok(Entry {
        key,
        name,
        at,
        value,
    })
}

/// A link's joint: `fixed`, `KIND(COORDINATE, axis)` or `floating(NAME)` as a call (its
/// kind and arguments are checked when the link is built, `mechanics::links`).
fn link_joint(c: &mut Cursor<'_>) -> Result<Ast> {
    let (kind, at) = name(c, "joint")?;
    let moving = MOVING_JOINTS.contains(&kind.as_str());
    if !moving && kind != "fixed" && kind != FLOATING_JOINT {
        return Err(Error::parse(ParseError::UnknownJoint { found: kind }, at));
    }
    if !c.eat(&Tok::Open(crate::syntax::lex::Delim::Paren)) {
        return Ok(Ast::Name(kind, at));
    }
    let (q, qat) = name(c, "joint")?;
    if kind == FLOATING_JOINT {
        c.expect(
            &Tok::Close(crate::syntax::lex::Delim::Paren),
            Expected::ArgumentSeparator,
        )?;
        return Ok(Ast::Call(kind, vec![Ast::Name(q, qat)], at));
    }
    c.expect(&Tok::Punct(','), Expected::ArgumentSeparator)?;
    let axis = parse(c, Language::Vector)?;
    c.expect(
        &Tok::Close(crate::syntax::lex::Delim::Paren),
        Expected::ArgumentSeparator,
    )?;
    Ok(Ast::Call(kind, vec![Ast::Name(q, qat), axis], at))
}

fn joint(c: &mut Cursor<'_>) -> Result<Joint> {
    let at = c.peek().location();
    let lhs = parse(c, Language::Vector)?;
    if c.eat(&Tok::Punct('=')) {
        let rhs = parse(c, Language::Vector)?;
        return Ok(Joint::Row(lhs, Some(rhs), at));
    }
    Ok(match lhs {
        Ast::Call(f, args, at) if HELPERS.contains(&f.as_str()) => Joint::Helper(f, args, at),
        other => Joint::Row(other, None, at),
    })
}
