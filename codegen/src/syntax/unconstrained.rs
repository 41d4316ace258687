//! A declaration without constraint rows (no `constraints`, no `velocity_constraints`, no
//! `joints` rows, no helper joints) and without an `independent` section: every coordinate is
//! independent, at its initial value, at rest. With m = 0 there is nothing to solve for, so the
//! n - m = n degrees of freedom are the coordinates themselves (an open tree of links,
//! particles in a field, a chain in relative angles).
//!
//! It is a rewrite of the syntax tree, so every later check sees an ordinary `independent`.

use crate::syntax::bodies::{BodyItem, Joint};
use crate::syntax::declaration::{Declaration, IndependentItem, Section};

/// Adds `independent` with every coordinate at its declared value when the declaration has
/// no constraint rows and no `independent` section.
pub(crate) fn independent_when_unconstrained(d: &mut Declaration) {
    let rows = d.constraints.as_ref().is_some_and(|s| !s.body.is_empty())
        || d.velocity_constraints
            .as_ref()
            .is_some_and(|s| !s.body.is_empty())
        || d.bodies
            .items
            .iter()
            .any(|i| matches!(i, BodyItem::Joint(Joint::Helper(..) | Joint::Row(..))));
    let Some(coordinates) = d.coordinates.as_ref() else {
        return;
    };
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
