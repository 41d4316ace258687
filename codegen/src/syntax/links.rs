//! What a `link` declares beyond its frame: the coordinate of its joint, and, for an open
//! tree, the independent coordinates.
//!
//! - `joint = revolute(q1, [0, 0, 1]);` (or `continuous`, `prismatic`) declares the
//!   coordinate `q1` unless `coordinates { .. }` already does (then its initial guess is
//!   kept); a new one starts at 0.
//! - A declaration with links and no constraint rows (no `constraints`, no `joints`) and no
//!   `independent` section is an open tree: every coordinate is independent, at its initial
//!   value, at rest.
//!
//! Both are rewrites of the syntax tree, so every later check sees ordinary coordinates.

use crate::number::Number;
use crate::syntax::ast::Ast;
use crate::syntax::bodies::{BodyItem, Joint, MOVING_JOINTS};
use crate::syntax::declaration::{Declaration, IndependentItem, Item, Section};

/// Adds the coordinates of the links' joints and, for an open tree, `independent`.
pub(crate) fn declare_link_coordinates(d: &mut Declaration) {
    let mut joints: Vec<(String, crate::error::Location)> = Vec::new();
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
    for (q, at) in joints {
        if !coordinates.body.iter().any(|c| c.name == q) {
            coordinates.body.push(Item {
                name: q,
                at,
                value: Ast::Number(Number::int(0), at),
            });
        }
    }
    let rows = d.constraints.as_ref().is_some_and(|s| !s.body.is_empty())
        || d.bodies
            .items
            .iter()
            .any(|i| matches!(i, BodyItem::Joint(Joint::Helper(..) | Joint::Row(..))));
    if rows || d.independent.is_some() || coordinates.body.is_empty() {
        return;
    }
    let body = coordinates
        .body
        .iter()
        .map(|c| IndependentItem {
            name: c.name.clone(),
            rate: false,
            at: c.at,
            value: c.value.clone(),
        })
        .collect();
    d.independent = Some(Section {
        at: coordinates.at,
        body,
    });
}
