//! The derived equations of motion, ready for emission or evaluation.
//!
//! M(q) q'' + C(q, q') q' + g(q) + Phi_q^T lambda = tau(t, q, q'),  Phi(q, t) = 0,
//! Phi_q q'' = gamma.

use crate::algebra::expr::Id;
use crate::algebra::matrix::Matrix;

/// Everything derived from a [`crate::Model`] (all expressions live in the model's arena).
#[derive(Clone, Debug)]
pub struct Equations {
    /// Number of coordinates n.
    pub n: usize,
    /// Number of constraint rows m.
    pub m: usize,
    /// M = d2T/dq'dq' (n x n).
    pub mass: Matrix,
    /// Khang's C = (dM/dq)(I_n kron q') - 1/2 [(dM/dq)(q' kron I_n)]^T (n x n).
    pub coriolis_matrix: Matrix,
    /// The velocity-dependent inertial forces h (n x 1), simplified on their own (cheaper
    /// than multiplying C out). For the usual T = 1/2 q'^T M(q) q' this is exactly C q'. For a
    /// general T (terms linear in q', explicit t) it is the full
    /// h = d/dt(dT/dq')|_(q''=0) - dT/dq, so that M q'' + h + g + Phi_q^T lambda = tau holds;
    /// then h differs from Khang's C q'.
    pub coriolis_forces: Matrix,
    /// g = dPi/dq (n x 1).
    pub gravity: Matrix,
    /// tau (n x 1).
    pub forces: Matrix,
    /// Phi (m x 1).
    pub phi: Matrix,
    /// Phi_q (m x n).
    pub phi_q: Matrix,
    /// Phi_t (m x 1).
    pub phi_t: Matrix,
    /// gamma = -(dPhi_q/dq)(q' kron q') - 2 Phi_qt q' - Phi_tt (m x 1).
    pub gamma: Matrix,
    /// T.
    pub kinetic: Id,
    /// Pi.
    pub potential: Id,
}
