//! Mechanics: from a declaration's syntax tree to a [`Model`](crate::Model), and from a
//! model to its equations of motion.
//!
//! Enters: a [`crate::syntax`] tree. Leaves: a checked [`Model`](crate::Model) (symbols,
//! coordinates, parameters, T, Pi, Phi, forces as expressions of one arena) and its
//! [`Equations`](crate::Equations):
//!
//! ```text
//! M(q) q'' + C(q, q') q' + g(q) + Phi_q^T lambda = tau(t, q, q'),   Phi(q, t) = 0,
//! Phi_q q'' = gamma = -(dPhi_q/dq)(q' kron I_n) q' - 2 Phi_qt q' - Phi_tt
//! ```
//!
//! with M = d2T/dq'dq', Khang's C = (dM/dq)(I_n kron q') - 1/2 [(dM/dq)(q' kron I_n)]^T and
//! g = dPi/dq. The stages in order: [`check`] (one rule per function, every error kept),
//! [`resolve`] and [`vectors`] (names of a syntax tree resolved into arena nodes),
//! [`build`] (the model), [`body_model`] with [`bodies`], [`body_checks`] and [`joints`]
//! (energies from rigid bodies and what their mass and inertia must satisfy, joint rows),
//! [`lagrange`] (the equations, with [`kinetic_form`]: T a positive semi-definite quadratic
//! form in the rates), [`tangent`] (dF/dq and dF/dq' for implicit integrators, and with
//! [`dynamics_derivatives`] the inverse dynamics' derivatives for control).

pub(crate) mod bodies;
pub(crate) mod body_checks;
pub(crate) mod body_model;
pub(crate) mod build;
pub(crate) mod check;
pub(crate) mod derivation;
pub(crate) mod drawing;
pub(crate) mod dynamics_derivatives;
pub(crate) mod equations;
pub(crate) mod floating;
pub(crate) mod floating_derivatives;
pub(crate) mod forward_derivatives;
pub(crate) mod forward_dynamics;
pub(crate) mod joints;
pub(crate) mod kinetic_form;
pub(crate) mod kkt_tree;
pub(crate) mod lagrange;
pub(crate) mod linear_form;
pub(crate) mod link_route;
pub(crate) mod links;
pub(crate) mod mass_matrix;
pub(crate) mod mass_slopes;
pub(crate) mod model;
pub(crate) mod motion_jacobians;
pub(crate) mod nonholonomic;
pub(crate) mod rate_degree;
pub(crate) mod recursive;
pub(crate) mod resolve;
pub(crate) mod rigid_body;
pub(crate) mod rolling;
pub(crate) mod running_rows;
pub(crate) mod tangent;
pub(crate) mod tree;
pub(crate) mod tree_derivatives;
pub(crate) mod vectors;
