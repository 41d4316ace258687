//! The object-safe, run-time-sized face of a mechanism that every solver consumes, and the
//! caller-owned buffers it evaluates into (so the step loop never allocates).

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

use super::info::SystemInfo;
use super::parameter_range::ParameterError;
use super::sparsity::Sparsity;
use crate::linalg::NullSpaceSolve;

/// The argument of [`System::null_space_solver`]: public in a private module, so no code
/// outside this crate can name it, and with a private field, so none can make one.
#[derive(Clone, Copy, Debug)]
pub struct SolverKey(());

impl SolverKey {
    /// The key, for the crate's own solvers.
    pub(crate) fn new() -> Self {
        SolverKey(())
    }
}

/// Caller-owned buffers for one evaluation of a [`System`] (sizes n and m fixed at creation).
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// Mass matrix M(q), n x n.
    pub mass: DMatrix<f64>,
    /// C(q, q') q'.
    pub coriolis: DVector<f64>,
    /// g(q) = dPi/dq.
    pub gravity: DVector<f64>,
    /// tau(t, q, q').
    pub forces: DVector<f64>,
    /// Phi(q, t), length m.
    pub phi: DVector<f64>,
    /// Phi_q, m x n.
    pub phi_q: DMatrix<f64>,
    /// Phi_t, length m.
    pub phi_t: DVector<f64>,
    /// gamma, length m.
    pub gamma: DVector<f64>,
    /// T(q, q').
    pub kinetic: f64,
    /// Pi(q).
    pub potential: f64,
}

impl Evaluation {
    /// Zeroed buffers for n coordinates and m constraint rows.
    pub fn zeros(n: usize, m: usize) -> Self {
        Self {
            mass: DMatrix::zeros(n, n),
            coriolis: DVector::zeros(n),
            gravity: DVector::zeros(n),
            forces: DVector::zeros(n),
            phi: DVector::zeros(m),
            phi_q: DMatrix::zeros(m, n),
            phi_t: DVector::zeros(m),
            gamma: DVector::zeros(m),
            kinetic: 0.0,
            potential: 0.0,
        }
    }
}

/// The constraint rows of a mechanism, Phi(q, t) = 0, and its names: all that assembly,
/// the position and velocity analyses and the [`crate::mobility()`] read. Every
/// [`System`] is one; [`crate::InterpretedConstraints`] is one without the dynamics.
///
/// Every method writes into caller-owned buffers and allocates nothing.
pub trait Kinematic: Send + Sync {
    /// Names, sizes and declared data.
    fn info(&self) -> &SystemInfo;
    /// Phi(q, t) into `phi` (length m).
    fn constraints(&self, t: f64, q: &[f64], phi: &mut [f64]);
    /// Phi_q (m x n) and Phi_t (m) at (q, t). As in [`System::evaluate`], a system may
    /// write Phi_q at its structural nonzeros only (those of [`System::sparsity`] for a
    /// [`System`]): `phi_q` must be made zero once and written by this system alone.
    fn constraint_jacobian(&self, t: f64, q: &[f64], phi_q: &mut DMatrix<f64>, phi_t: &mut [f64]);
}

/// The object-safe, run-time-sized view of a mechanism that the solvers use: its
/// [`Kinematic`] constraint rows and the dynamics.
///
/// Every method writes into caller-owned buffers and allocates nothing.
pub trait System: Kinematic {
    /// Current parameter values, in declaration order (written into `out`).
    fn parameter_values(&self, out: &mut [f64]);
    /// Sets parameter `index` to `value`; the initial guesses and independent values of
    /// [`Kinematic::info`] follow it (the declared expressions evaluated again).
    ///
    /// # Errors
    /// [`ParameterError::NoSuchParameter`] for an index past the last parameter,
    /// [`ParameterError::OutOfRange`] for a value outside the parameter's declared range
    /// ([`SystemInfo::parameter_ranges`]); nothing changes then.
    fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError>;
    /// Everything at (t, q, q'): see [`Evaluation`]. A system with a [`System::sparsity`]
    /// may write M and Phi_q at their pattern only: `out` must then come from
    /// [`Evaluation::zeros`] and be written by this system alone.
    fn evaluate(&self, t: f64, q: &[f64], qd: &[f64], out: &mut Evaluation);
    /// The structural pattern of M and Phi_q (entries outside it are zero at every state),
    /// which the large-system solvers read instead of scanning the dense matrices; `None`
    /// (the default) when unknown.
    fn sparsity(&self) -> Option<&Sparsity> {
        None
    }
    /// World positions of the drawn points of [`SystemInfo::drawing`] at (t, q), 3 values per
    /// point into `out` (see [`crate::Mechanism::draw_points`]); nothing by default.
    fn draw_points(&self, t: f64, q: &[f64], out: &mut [f64]) {
        let _ = (t, q, out);
    }
    /// Not API (sealed: only this crate can name [`SolverKey`], so no code outside it can
    /// call or override this): a solver of the augmented system by the null space of Phi_q
    /// specialised to this system's static sizes (every loop with a constant trip count),
    /// which [`crate::Dynamics`] asks for on its first solve; `None` (the default) keeps the
    /// run-time-sized one. Only [`crate::Compiled`], where the sizes are type parameters,
    /// provides it.
    #[doc(hidden)]
    fn null_space_solver(&self, key: SolverKey) -> Option<Box<dyn NullSpaceSolve>> {
        let _ = key;
        None
    }
    /// Exact tangent matrices of the dynamic residual
    /// F = M(q) q'' + C(q, q') q' + g(q) - tau(t, q, q') + Phi_q(q, t)^T lambda:
    /// `out.stiffness` = dF/dq and `out.damping` = dF/dq' (n x n), for the Newton iteration of
    /// implicit integrators (HHT). Returns `None` when not provided (the default); the
    /// solver then uses finite differences. `mechanism!` and [`crate::Interpreted`] provide
    /// them, derived symbolically by codegen (`residual_tangent`).
    fn tangent(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        lambda: &[f64],
        out: &mut Tangent,
    ) -> Option<()> {
        let _ = (t, q, qd, qdd, lambda, out);
        None
    }

    /// Inverse dynamics at (t, q, q', q''): the effort u = M q'' + C q' + g - tau along the
    /// coordinates that, added to the declared forces tau, gives the accelerations q'' when
    /// no constraint acts (Pinocchio's `rnea` for a robot without declared forces), into
    /// `out` (n values). For a tree of links the routine is Newton-Euler (O(n)), as the
    /// macro's [`crate::Mechanism::inverse_dynamics`]; a mechanism with constraint rows
    /// also needs Phi_q^T lambda (the algorithm [`crate::inverse_dynamics`] solves for it).
    /// `None` when not provided (the default): compute it from [`System::evaluate`].
    /// [`crate::Compiled`] provides it, and [`crate::Interpreted`] when built with the
    /// robotics routines ([`crate::Interpreted::from_model_with`]).
    fn inverse_dynamics(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) -> Option<()> {
        let _ = (t, q, qd, qdd, out);
        None
    }

    /// Forward dynamics of a mechanism without constraint rows by its own generated routine:
    /// q'' = M(q)^-1 (u - b) for the effort `effort` u (n values; b = C q' + g - tau) into
    /// `qdd`, and tau into `forces` (n values each), without evaluating the dense M: for a
    /// tree of links the articulated-body recursion or the factorisation M = L^T D L over
    /// M's pattern, whichever counts fewer operations (the macro's
    /// [`crate::Mechanism::forward_dynamics`]). `Some(false)` when M is not positive
    /// definite at q beyond round-off (a pivot not above 1e-14 of its reference) or a
    /// result is not finite: the caller then solves from [`System::evaluate`], which
    /// reports why. `None` when not provided (the default, and for a mechanism with
    /// constraint rows); [`crate::Interpreted`] provides it.
    fn forward_dynamics(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        effort: &[f64],
        qdd: &mut [f64],
        forces: &mut [f64],
    ) -> Option<bool> {
        let _ = (t, q, qd, effort, qdd, forces);
        None
    }

    /// The placement of link frame `frame` (an index into [`SystemInfo::frames`]) at q:
    /// `rotation` R, the link axes in world axes, and `position` p, the frame's origin in
    /// the world, so that a point with link coordinates r is at p + R r. `None` for an
    /// index out of range or when not provided (the default; as for
    /// [`System::inverse_dynamics`]).
    fn frame_placement(
        &self,
        frame: usize,
        q: &[f64],
        rotation: &mut Matrix3<f64>,
        position: &mut Vector3<f64>,
    ) -> Option<()> {
        let _ = (frame, q, rotation, position);
        None
    }

    /// The Jacobian J (6 x n) of link frame `frame` at q into `out`: [v; w] = J q', v the
    /// velocity of the frame's origin and w its angular velocity, both in world axes
    /// (Pinocchio's `LOCAL_WORLD_ALIGNED`). `None` as for [`System::frame_placement`].
    fn frame_jacobian(&self, frame: usize, q: &[f64], out: &mut DMatrix<f64>) -> Option<()> {
        let _ = (frame, q, out);
        None
    }

    /// The derivatives of the inverse dynamics tau_id = M q'' + C q' + g - tau at
    /// (t, q, q', q''): `out.stiffness` = dtau_id/dq and `out.damping` = dtau_id/dq' (n x n;
    /// the residual's tangent at lambda = 0, see [`System::tangent`]). `None` when not
    /// provided (the default; [`crate::Compiled`] provides them, and
    /// [`crate::Interpreted::for_derivatives`]) or not finite.
    fn inverse_dynamics_derivatives(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut Tangent,
    ) -> Option<()> {
        let _ = (t, q, qd, qdd, out);
        None
    }

    /// dtau_id/dp, the inverse dynamics' derivatives by the declared parameters (n x p,
    /// columns in declaration order) into `out`. `None` when not provided (the default, and
    /// [`crate::Interpreted`] unless built by [`crate::Interpreted::for_derivatives`]), for
    /// `out` of another shape, or not finite.
    fn parameter_derivatives(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut DMatrix<f64>,
    ) -> Option<()> {
        let _ = (t, q, qd, qdd, out);
        None
    }

    /// Exact tangents of the constraint rows for linearisation (see [`ConstraintTangent`]):
    /// with w = Phi_q q' + Phi_t and R = Phi_q q'' - gamma, `out.velocity` = dw/dq,
    /// `out.stiffness` = dR/dq and `out.damping` = dR/dq' (m x n), at (t, q, q', q'').
    /// `None` when not provided (the default; [`crate::Compiled`] provides them, and
    /// [`crate::Interpreted`] for a mechanism with velocity constraints, or built by
    /// [`crate::Interpreted::for_linearization`] or [`crate::Interpreted::for_derivatives`]).
    fn constraint_tangent(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut ConstraintTangent,
    ) -> Option<()> {
        let _ = (t, q, qd, qdd, out);
        None
    }
}

/// The constraint rows' tangents (see [`System::constraint_tangent`]): the linearised
/// constraints are `velocity` dq + Phi_q dq' = 0 and
/// `stiffness` dq + `damping` dq' + Phi_q dq'' = 0.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstraintTangent {
    /// d(Phi_q q' + Phi_t)/dq, m x n.
    pub velocity: DMatrix<f64>,
    /// d(Phi_q q'' - gamma)/dq, m x n.
    pub stiffness: DMatrix<f64>,
    /// d(Phi_q q'' - gamma)/dq', m x n.
    pub damping: DMatrix<f64>,
}

impl ConstraintTangent {
    /// Zero matrices for m rows and n coordinates.
    pub fn zeros(m: usize, n: usize) -> Self {
        Self {
            velocity: DMatrix::zeros(m, n),
            stiffness: DMatrix::zeros(m, n),
            damping: DMatrix::zeros(m, n),
        }
    }
}

/// dF/dq and dF/dq' of the dynamic residual F = M q'' + C q' + g - tau + Phi_q^T lambda
/// (see [`System::tangent`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Tangent {
    /// dF/dq, n x n ("stiffness").
    pub stiffness: DMatrix<f64>,
    /// dF/dq', n x n ("damping").
    pub damping: DMatrix<f64>,
}

impl Tangent {
    /// Zero matrices for n coordinates.
    pub fn zeros(n: usize) -> Self {
        Self {
            stiffness: DMatrix::zeros(n, n),
            damping: DMatrix::zeros(n, n),
        }
    }
}
