//! What a `link` declares beyond its frame: the coordinate of its joint.
//!
//! - `joint = revolute(q1, [0, 0, 1]);` (or `continuous`, `prismatic`) declares the
//!   coordinate `q1` unless `coordinates { .. }` already does (then its initial guess is
//!   kept); a new one starts at 0.
//! - `joint = floating(base);` declares the six velocity coordinates of a floating root,
//!   `base_vx`, `base_vy`, `base_vz`, `base_wx`, `base_wy`, `base_wz`, first in q' (the
//!   free-flyer layout: `mechanics::floating`).
//!
//! It is a rewrite of the syntax tree, so every later check sees ordinary coordinates (an
//! open tree then needs no `independent`: `syntax::unconstrained`).

use crate::number::Number;
use crate::syntax::ast::Ast;
use crate::syntax::bodies::{BodyItem, FLOATING_JOINT, MOVING_JOINTS};
use crate::syntax::declaration::{Declaration, Item, Section};
use crate::syntax::parameter_range::ParameterRange;

/// Adds the coordinates of the links' joints.
pub(crate) fn declare_link_coordinates(d: &mut Declaration) {
    let mut joints: Vec<(String, crate::error::Location)> = Vec::new();
    let mut floating: Vec<(String, crate::error::Location)> = Vec::new();
    for item in &d.bodies.items {
        let BodyItem::Link { entries, .. } = item else {
            continue;
        };
        for e in entries.iter().filter(|e| e.key == "joint") {
            if let Some(Ast::Call(kind, args, _)) = e.value.first()
                && MOVING_JOINTS.contains(&kind.as_str())
                && let Some(Ast::Name(q, at)) = args.first()
            {
                joints.push((q.clone(), *at));
            }
            if let Some(Ast::Call(kind, args, _)) = e.value.first()
                && kind == FLOATING_JOINT
                && let Some(Ast::Name(base, at)) = args.first()
            {
                floating.extend(floating_velocity_names(base).map(|v| (v, *at)));
            }
        }
    }
    let has_links = d
        .bodies
        .items
        .iter()
        .any(|i| matches!(i, BodyItem::Link { .. }));
    if !has_links {
        return;
    }
    let coordinates = d.coordinates.get_or_insert_with(|| Section {
        at: joints.first().map_or(d.name_at, |j| j.1),
        body: Vec::new(),
    });
    // The floating root's velocities first, in their order (the free-flyer layout).
    for (k, (v, at)) in floating.into_iter().enumerate() {
        coordinates.body.retain(|c| c.name != v);
        coordinates.body.insert(
            k,
            Item {
                name: v,
                at,
                value: Ast::Number(Number::int(0), at),
                range: ParameterRange::Any,
            },
        );
    }
    for (q, at) in joints {
        if !coordinates.body.iter().any(|c| c.name == q) {
            coordinates.body.push(Item {
                name: q,
                at,
                value: Ast::Number(Number::int(0), at),
                range: ParameterRange::Any,
            });
        }
    }
}

/// The velocity coordinates of the floating joint `base`, in the free-flyer order: the
/// linear velocity of the root's origin, then its angular velocity, both in its axes.
pub(crate) fn floating_velocity_names(base: &str) -> [String; 6] {
    ["vx", "vy", "vz", "wx", "wy", "wz"].map(|s| format!("{base}_{s}"))
}

/// The configuration of the floating joint `base`, in the free-flyer order: the root's
/// origin in the world, then its orientation as a unit quaternion (x, y, z, w).
pub(crate) fn floating_configuration_names(base: &str) -> [String; 7] {
    ["x", "y", "z", "qx", "qy", "qz", "qw"].map(|s| format!("{base}_{s}"))
}
