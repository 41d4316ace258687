//! The derivation as the crate exports it: the equations of motion of `lagrange` (Khang's
//! calculus over T, or the recursive route for a tree of links), then the velocity rows
//! A q' + a = 0 stacked under the position rows (`nonholonomic`).

use crate::error::Result;
use crate::mechanics::equations::Equations;
use crate::mechanics::lagrange::{self, Route};
use crate::mechanics::link_route::for_links;
use crate::mechanics::model::Model;
use crate::mechanics::nonholonomic::append_velocity_rows;

/// Derives the equations of motion of `model`: M, C, C q', g, tau, Phi, Phi_q, Phi_t,
/// gamma, T, Pi, the inverse dynamics and the link frames (see `mechanics::lagrange`), with
/// the velocity constraints as the last rows of Phi_q, Phi_t and gamma
/// (`mechanics::nonholonomic`). All expressions are built in `model.arena`.
///
/// # Errors
/// [`crate::error::DeclarationError::NoCoordinates`] (with no place),
/// [`crate::error::DerivationError::NotASymbol`] for a coordinate that is not a symbol,
/// [`crate::error::DerivationError::ForceCount`] when the number of forces differs from the
/// number of coordinates, [`crate::error::DerivationError::ForbiddenDependence`] when the
/// potential or a constraint depends on a rate or an acceleration, or T or a force on an
/// acceleration; [`crate::error::AlgebraError::InvalidId`] for a foreign id; a velocity
/// constraint not linear in the rates (`DeclarationError::VelocityNotLinear`, at its row);
/// differentiation errors; a [`crate::error::BudgetError`] beyond the arena's budget (for a
/// tree of links, with the remedies that apply to links).
pub fn derive(model: &mut Model) -> Result<Equations> {
    derive_with(model, lagrange::Route::Auto)
}

/// [`derive()`] with the route for M and C q' chosen.
///
/// # Errors
/// As [`derive()`].
pub fn derive_with(model: &mut Model, route: Route) -> Result<Equations> {
    let derived = lagrange::derive_with(model, route).and_then(|mut eqs| {
        append_velocity_rows(model, &mut eqs)?;
        Ok(eqs)
    });
    derived.map_err(|e| for_links(model, e))
}
