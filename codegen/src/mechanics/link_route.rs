//! What [`crate::derive()`] adds for a tree of links: the energies of the links' bodies
//! for the energy route, the check that some mass moves, T from the recursive route's M,
//! and the frames of the links.
//!
//! Where the links carry all of T (`Model::kinetic_from_links`) the model holds their
//! bodies aside (`Model::link_bodies`): the recursive route reads the tree itself, and
//! only `derive_with(model, Route::Lagrange)` forms their T and Pi (for a chain of n links
//! T alone has O(n^3) terms).

use crate::algebra::expr::{Arena, Id, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::{DeclarationError, Error, Result};
use crate::mechanics::bodies::{BodySystem, body_terms};
use crate::mechanics::equations::FrameEquations;
use crate::mechanics::model::Model;
use crate::mechanics::tree::Link;

/// T and Pi for the energy route: the model's own, plus the links' bodies' T and gravity Pi
/// where the model holds them aside.
pub(crate) fn energies(model: &mut Model) -> Result<(Id, Id)> {
    if model.link_bodies.is_empty() {
        return Ok((model.kinetic, model.potential));
    }
    let system = BodySystem {
        bodies: model.link_bodies.clone(),
        gravity: model.gravity,
        springs: Vec::new(),
        dampers: Vec::new(),
    };
    let terms = body_terms(model, &system)?;
    let a = &mut model.arena;
    Ok((
        a.add2(model.kinetic, terms.kinetic),
        a.add2(model.potential, terms.potential),
    ))
}

/// Refuses links whose M is identically 0: no mass or inertia moves with any joint, so T
/// = 0 and the equations say nothing of the accelerations.
pub(crate) fn check_moving_mass(model: &Model, mass: &Matrix) -> Result<()> {
    if !mass.is_zero(&model.arena) {
        return Ok(());
    }
    let kind = DeclarationError::LinksWithoutMovingMass {
        coordinates: model.coordinates.iter().map(|c| c.name.clone()).collect(),
    };
    Err(Error::declaration(kind, model.kinetic_location))
}

/// T = 1/2 q'^T M q', each pair once: sum_i 1/2 M_ii q_i'^2 + sum_{i<j} M_ij q_i' q_j'.
pub(crate) fn quadratic_form(arena: &mut Arena, mass: &Matrix, qd: &[SymbolId]) -> Id {
    let n = qd.len();
    let half = arena.rational(1, 2).unwrap_or_else(|_| arena.int(0));
    let mut terms = Vec::with_capacity(n * (n + 1) / 2);
    for (i, &si) in qd.iter().enumerate() {
        let qi = arena.symbol_node(si);
        for (j, &sj) in qd.iter().enumerate().skip(i) {
            let qj = arena.symbol_node(sj);
            let c = if i == j { half } else { arena.int(1) };
            terms.push(arena.mul(&[c, mass.get(i, j), qi, qj]));
        }
    }
    arena.add(&terms)
}

/// Each link's frame: its name, rotation and position (the Jacobians are derived when a
/// routine needs them: `Role::FrameJacobian`).
pub(crate) fn frame_equations(links: &[Link]) -> Vec<FrameEquations> {
    links
        .iter()
        .map(|link| FrameEquations {
            name: link.name.clone(),
            rotation: link.rotation.clone(),
            position: Matrix::column(link.position.to_vec()),
        })
        .collect()
}

/// `e` as met while deriving or compiling `model`: a budget error of a tree of links says
/// what applies to links ([`crate::error::BudgetError::of_links`]).
pub(crate) fn for_links(model: &Model, e: Error) -> Error {
    let moving = model
        .links
        .iter()
        .filter(|l| l.joint.coordinate().is_some());
    match e {
        Error::Budget(b) if model.kinetic_from_links => Error::Budget(b.of_links(moving.count())),
        other => other,
    }
}
