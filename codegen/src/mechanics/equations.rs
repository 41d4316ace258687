//! The derived equations of motion, ready for emission or evaluation.
//!
//! M(q) q'' + C(q, q') q' + g(q) + Phi_q^T lambda = tau(t, q, q'),  Phi(q, t) = 0,
//! Phi_q q'' = gamma; velocity constraints A q' + a = 0 are further rows of Phi_q (A),
//! Phi_t (a) and gamma, with Phi = 0 there.

use crate::algebra::expr::Id;
use crate::algebra::matrix::Matrix;

/// Everything derived from a [`crate::Model`] (all expressions live in the model's arena).
#[derive(Clone, Debug)]
pub struct Equations {
    /// Number of coordinates n.
    pub n: usize,
    /// Number of constraint rows m: the position rows, then `velocity_rows` velocity rows.
    pub m: usize,
    /// How many of the m rows (the last ones) are velocity constraints A q' + a = 0
    /// (`mechanics::nonholonomic`): their Phi is 0, their Phi_q row A, their Phi_t a.
    pub velocity_rows: usize,
    /// M = d2T/dq'dq' (n x n).
    pub mass: Matrix,
    /// Khang's C = (dM/dq)(I_n kron q') - 1/2 [(dM/dq)(q' kron I_n)]^T (n x n); `None`
    /// for a tree of links on the recursive route, where it is derived only when a
    /// routine needs it (compiling the macro's `coriolis_matrix`): its n^2 entries read
    /// every slope dM_ij/dq_k, O(n^3) of them for a chain.
    pub coriolis_matrix: Option<Matrix>,
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
    /// The inverse dynamics tau_id(t, q, q', q'') = M q'' + C q' + g - tau (n x 1): the
    /// effort that, with the declared forces and no constraint forces, produces q''. In the
    /// acceleration symbols `der2(q)`.
    pub inverse_dynamics: Matrix,
    /// The bias b(t, q, q') = C q' + g - tau (n x 1): with M, the unconstrained dynamics
    /// M q'' + b = u for an effort u along the coordinates. For a tree of links one
    /// Newton-Euler pass (with the base accelerating at -g), else the sum of the three.
    pub bias: Matrix,
    /// The frames of the declared links, in declaration order (empty without links).
    pub frames: Vec<FrameEquations>,
}

/// The placement of one link frame (its Jacobian is derived when a routine needs it:
/// `Role::FrameJacobian`).
#[derive(Clone, Debug)]
pub struct FrameEquations {
    /// The link's name.
    pub name: String,
    /// R (3x3): the link axes in world axes.
    pub rotation: Matrix,
    /// p (3x1): the link origin in the world.
    pub position: Matrix,
}

/// One output of the combined evaluation program: the emitted `evaluate` and the
/// interpreter's both compute [`EvaluationOutput::ORDER`] with one CSE'd program, so shared
/// subexpressions of M, C q', g, tau, Phi, Phi_q, Phi_t, gamma, T and Pi are computed once.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum EvaluationOutput {
    /// M, n x n.
    Mass,
    /// C(q, q') q', n x 1.
    CoriolisForces,
    /// g = dPi/dq, n x 1.
    Gravity,
    /// tau, n x 1.
    Forces,
    /// Phi, m x 1.
    Phi,
    /// Phi_q, m x n.
    PhiQ,
    /// dPhi/dt, m x 1.
    PhiT,
    /// gamma, m x 1.
    Gamma,
    /// T, 1 x 1.
    Kinetic,
    /// Pi, 1 x 1.
    Potential,
}

impl EvaluationOutput {
    /// The outputs of the evaluation program, in order.
    pub const ORDER: [EvaluationOutput; 10] = [
        EvaluationOutput::Mass,
        EvaluationOutput::CoriolisForces,
        EvaluationOutput::Gravity,
        EvaluationOutput::Forces,
        EvaluationOutput::Phi,
        EvaluationOutput::PhiQ,
        EvaluationOutput::PhiT,
        EvaluationOutput::Gamma,
        EvaluationOutput::Kinetic,
        EvaluationOutput::Potential,
    ];

    /// (rows, cols) of the output for n coordinates and m constraint rows.
    pub fn shape(self, n: usize, m: usize) -> (usize, usize) {
        match self {
            EvaluationOutput::Mass => (n, n),
            EvaluationOutput::CoriolisForces
            | EvaluationOutput::Gravity
            | EvaluationOutput::Forces => (n, 1),
            EvaluationOutput::Phi | EvaluationOutput::PhiT | EvaluationOutput::Gamma => (m, 1),
            EvaluationOutput::PhiQ => (m, n),
            EvaluationOutput::Kinetic | EvaluationOutput::Potential => (1, 1),
        }
    }
}

impl Equations {
    /// The matrix of one evaluation output (T and Pi as 1 x 1).
    pub fn evaluation_output(&self, output: EvaluationOutput) -> Matrix {
        match output {
            EvaluationOutput::Mass => self.mass.clone(),
            EvaluationOutput::CoriolisForces => self.coriolis_forces.clone(),
            EvaluationOutput::Gravity => self.gravity.clone(),
            EvaluationOutput::Forces => self.forces.clone(),
            EvaluationOutput::Phi => self.phi.clone(),
            EvaluationOutput::PhiQ => self.phi_q.clone(),
            EvaluationOutput::PhiT => self.phi_t.clone(),
            EvaluationOutput::Gamma => self.gamma.clone(),
            EvaluationOutput::Kinetic => Matrix::column(vec![self.kinetic]),
            EvaluationOutput::Potential => Matrix::column(vec![self.potential]),
        }
    }

    /// The matrices of the evaluation program, in [`EvaluationOutput::ORDER`].
    pub fn evaluation_outputs(&self) -> Vec<Matrix> {
        EvaluationOutput::ORDER
            .iter()
            .map(|&o| self.evaluation_output(o))
            .collect()
    }
}
