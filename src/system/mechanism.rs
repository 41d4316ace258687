//! The compiled face of a mechanism: [`Mechanism`] is what `mechanism!` emits, with static
//! sizes (`N` coordinates, `M` constraint rows), specialised allocation-free code and one
//! method per derived quantity. The solvers consume the run-time [`super::System`] instead;
//! [`super::Compiled`] adapts one to the other.
//!
//! Equations (Van Khang 2011), with q the N redundant coordinates:
//!
//! ```text
//! M(q) q'' + C(q, q') q' + g(q) + Phi_q(q, t)^T lambda = tau(t, q, q'),   Phi(q, t) = 0
//! Phi_q q'' = gamma = -(dPhi_q/dq)(q' kron q') - 2 Phi_qt q' - Phi_tt
//! ```

use nalgebra::{SMatrix, SVector};

use super::parameter_range::{ParameterError, ParameterRange};
use super::rotation_factor::RotationFactor;
use super::sparsity::{EvaluationSlices, StaticSparsity};

/// q, the N coordinates of a mechanism with static sizes (lengths in m, angles in rad).
pub type Coordinates<const N: usize> = SVector<f64, N>;
/// q', the rates of the coordinates.
pub type Velocities<const N: usize> = SVector<f64, N>;
/// q'', the accelerations of the coordinates.
pub type Accelerations<const N: usize> = SVector<f64, N>;
/// lambda, one Lagrange multiplier per constraint row (the generalised constraint force on
/// coordinate k is -(Phi_q^T lambda)_k).
pub type Multipliers<const M: usize> = SVector<f64, M>;

/// One coordinate the user sets directly (`independent { phi = 0.0; der(phi) = 2*pi; }`):
/// its index in q, its position and its rate at t = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Independent {
    /// Index of the coordinate in q.
    pub coordinate: usize,
    /// Prescribed position q_k(0).
    pub position: f64,
    /// Prescribed rate q_k'(0) (0 when the declaration gives none).
    pub velocity: f64,
}

/// Everything the solver needs at one (t, q, q'), evaluated together so that sin, cos and
/// common subexpressions are computed once.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticEvaluation<const N: usize, const M: usize> {
    /// Mass matrix M(q) = d2T/dq'dq'.
    pub mass: SMatrix<f64, N, N>,
    /// Velocity-dependent forces C(q, q') q'.
    pub coriolis: SVector<f64, N>,
    /// Conservative forces g(q) = dPi/dq.
    pub gravity: SVector<f64, N>,
    /// Applied generalised forces tau(t, q, q').
    pub forces: SVector<f64, N>,
    /// Constraint residuals Phi(q, t).
    pub phi: SVector<f64, M>,
    /// Constraint Jacobian Phi_q (M x N).
    pub phi_q: SMatrix<f64, M, N>,
    /// Explicit time derivative Phi_t.
    pub phi_t: SVector<f64, M>,
    /// Acceleration right-hand side gamma, with Phi_q q'' = gamma.
    pub gamma: SVector<f64, M>,
    /// Kinetic energy T(q, q').
    pub kinetic: f64,
    /// Potential energy Pi(q).
    pub potential: f64,
}

impl<const N: usize, const M: usize> StaticEvaluation<N, M> {
    /// Every entry zero (a buffer for [`Mechanism::evaluate_into`]).
    pub fn zeros() -> Self {
        Self {
            mass: SMatrix::zeros(),
            coriolis: SVector::zeros(),
            gravity: SVector::zeros(),
            forces: SVector::zeros(),
            phi: SVector::zeros(),
            phi_q: SMatrix::zeros(),
            phi_t: SVector::zeros(),
            gamma: SVector::zeros(),
            kinetic: 0.0,
            potential: 0.0,
        }
    }
}

/// A mechanism with derived equations and static sizes: `N` coordinates, `M` constraint rows.
///
/// Implemented by the code `mechanism!` emits. Every method is allocation-free. The emitted
/// code computes the values that depend on parameters only (`m2*g`, `sin(alpha)`, ...) once
/// per parameter set ([`Mechanism::refresh`]), not on every call.
///
/// # Example
///
/// The derived quantities of a Cartesian pendulum at one state, checked against what they
/// must be by hand (M = m I, g = dPi/dq = [0, m g], Phi_q = [2x, 2y]):
///
/// ```
/// use mechanism::prelude::*;
///
/// mechanism! {
///     pub struct Pendulum;
///     parameters { m = 2.0; l = 1.0; g = 9.81; }
///     coordinates { x = 0.6; y = -0.8; }
///     independent { x = 0.6; }
///     kinetic = 1/2*m*(der(x)^2 + der(y)^2);
///     potential = m*g*y;
///     constraints { x^2 + y^2 - l^2; }
/// }
///
/// let model = Pendulum::default();
/// let q = Coordinates::<2>::from(Pendulum::INITIAL_GUESS);
/// let qd = Velocities::<2>::new(0.8, 0.6); // along the circle: Phi_q q' = 0
/// assert_eq!(Pendulum::COORDINATES, ["x", "y"]);
/// assert_eq!(model.mass_matrix(&q), SMatrix::<f64, 2, 2>::identity() * 2.0);
/// assert_eq!(model.gravity(&q), SVector::<f64, 2>::new(0.0, 2.0 * 9.81));
/// let e = model.evaluate(0.0, &q, &qd); // everything at once, sin/cos and CSE shared
/// assert!((e.phi_q[(0, 0)] - 1.2).abs() < 1e-15 && (e.phi_q[(0, 1)] + 1.6).abs() < 1e-15);
/// assert!((e.phi_q * qd)[0].abs() < 1e-15);
/// // A parameter is a field: a longer rod without a rebuild.
/// let mut longer = Pendulum::default();
/// longer.l = 1.5;
/// assert!((longer.constraints(0.0, &q)[0] - (1.0 - 2.25)).abs() < 1e-15);
/// ```
///
/// Hand it to the run-time solvers with [`Compiled::new`](crate::Compiled::new) (with the
/// `std` feature), or step it with [`FixedStep`](crate::fixed::FixedStep) anywhere.
pub trait Mechanism<const N: usize, const M: usize>: Clone + Send + Sync + 'static {
    /// Name of the mechanism (the struct name).
    const NAME: &'static str;
    /// Coordinate names, in the order of q.
    const COORDINATES: [&'static str; N];
    /// Parameter names, in declaration order.
    const PARAMETERS: &'static [&'static str];
    /// Declared initial guesses for q (the start of the assembly Newton iteration), at the
    /// declared parameter defaults: a guess written with parameters (`z = r;`) is
    /// evaluated there. [`Mechanism::initial_guess`] gives them at the current values.
    const INITIAL_GUESS: [f64; N];
    /// The independent coordinates and their initial values, at the declared parameter
    /// defaults (`der(th) = v/r` evaluated with the default v and r).
    /// [`Mechanism::independent`] gives them at the current values.
    const INDEPENDENT: &'static [Independent];
    /// The range each parameter's declaration gives it (`r = 0.1 positive;`), in
    /// declaration order; empty (the default) when no parameter has one.
    /// [`Mechanism::set_parameter`] refuses a value outside it.
    const PARAMETER_RANGES: &'static [ParameterRange] = &[];
    /// The joint and the component of each constraint row, in row order (see
    /// [`super::ConstraintRow`]): `("revolute(B1, B2, z, z)", "y")`, `("constraint 2", "")`. Empty
    /// for hand-written impls ([`super::Compiled::new`] then names the rows `row 1`, `row 2`, ..).
    const CONSTRAINT_ROWS: &'static [(&'static str, &'static str)] = &[];
    /// How many of the M rows (the last ones) are velocity constraints A q' + a = 0 (their
    /// Phi is 0, their Jacobian row A, their Phi_t a); 0 for a holonomic mechanism.
    const VELOCITY_ROWS: usize = 0;
    /// The points of the declared drawing (`draw { .. }`), in order: name, and whether it is
    /// a ground point. Empty when the declaration draws nothing.
    const DRAW_POINTS: &'static [(&'static str, bool)] = &[];
    /// The drawing's polylines, as indices into [`Mechanism::DRAW_POINTS`].
    const DRAW_LINES: &'static [&'static [usize]] = &[];
    /// The drawn points whose paths are traced (indices into [`Mechanism::DRAW_POINTS`]).
    const DRAW_TRACES: &'static [usize] = &[];
    /// The orientation products the bodies declare (`rot_z(psi) * rot_x(phi) * rot_y(th)`):
    /// each body's name and factors, in declaration order; empty without bodies. Read to
    /// name a singularity of the orientation angles.
    const ORIENTATIONS: &'static [(&'static str, &'static [RotationFactor])] = &[];
    /// The limits the moving joints of a link tree declare (`limit`, `velocity_limit`,
    /// `effort_limit`), one entry per coordinate that has any, in coordinate order. Kept
    /// for reference: nothing enforces them (see [`super::JointLimits`]).
    const JOINT_LIMITS: &'static [super::JointLimits] = &[];

    /// Value of parameter `index` (declaration order), or `None` out of range.
    fn parameter(&self, index: usize) -> Option<f64>;
    /// Sets parameter `index` to `value` and refreshes the cached values
    /// ([`Mechanism::refresh`]).
    ///
    /// # Errors
    /// [`ParameterError::NoSuchParameter`] for an index past the last parameter,
    /// [`ParameterError::OutOfRange`] for a value outside the declared range
    /// ([`Mechanism::PARAMETER_RANGES`]); the parameter keeps its value.
    fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError>;
    /// The initial guesses for q at the current parameter values: the declared expressions
    /// (`z = r;`) evaluated from the parameters as they are now, through
    /// [`Mechanism::set_parameter`] or a field. Equal to [`Mechanism::INITIAL_GUESS`] at
    /// the defaults; by default (a hand-written impl) that constant.
    fn initial_guess(&self) -> [f64; N] {
        Self::INITIAL_GUESS
    }
    /// Entry `k` of [`Mechanism::INDEPENDENT`] with its position and rate at the current
    /// parameter values (`der(th) = v/r` with v and r as they are now); `None` for `k` past
    /// the last. By default (a hand-written impl) the constant's entry.
    fn independent(&self, k: usize) -> Option<Independent> {
        Self::INDEPENDENT.get(k).copied()
    }
    /// M(q) = d2T/dq'dq'.
    fn mass_matrix(&self, q: &SVector<f64, N>) -> SMatrix<f64, N, N>;
    /// Khang's C(q, q') = (dM/dq)(I_n kron q') - 1/2 [(dM/dq)(q' kron I_n)]^T.
    fn coriolis_matrix(&self, q: &SVector<f64, N>, qd: &SVector<f64, N>) -> SMatrix<f64, N, N>;
    /// C(q, q') q'.
    fn coriolis_forces(&self, q: &SVector<f64, N>, qd: &SVector<f64, N>) -> SVector<f64, N>;
    /// g(q) = dPi/dq.
    fn gravity(&self, q: &SVector<f64, N>) -> SVector<f64, N>;
    /// tau(t, q, q').
    fn generalized_forces(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
    ) -> SVector<f64, N>;
    /// Phi(q, t).
    fn constraints(&self, t: f64, q: &SVector<f64, N>) -> SVector<f64, M>;
    /// Phi_q(q, t).
    fn constraint_jacobian(&self, t: f64, q: &SVector<f64, N>) -> SMatrix<f64, M, N>;
    /// Phi_t(q, t) = dPhi/dt at fixed q (zero for scleronomic constraints).
    fn constraint_time_derivative(&self, t: f64, q: &SVector<f64, N>) -> SVector<f64, M>;
    /// gamma(t, q, q') = -(dPhi_q/dq)(q' kron q') - 2 Phi_qt q' - Phi_tt.
    fn constraint_gamma(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
    ) -> SVector<f64, M>;
    /// T(q, q').
    fn kinetic_energy(&self, q: &SVector<f64, N>, qd: &SVector<f64, N>) -> f64;
    /// Pi(q).
    fn potential_energy(&self, q: &SVector<f64, N>) -> f64;
    /// All of the above at one (t, q, q'), sharing sin, cos and common subexpressions.
    fn evaluate(&self, t: f64, q: &SVector<f64, N>, qd: &SVector<f64, N>)
    -> StaticEvaluation<N, M>;
    /// [`Mechanism::evaluate`] written into `out` (every entry overwritten): M, C q', g,
    /// tau, Phi, Phi_q, Phi_t, gamma, T and Pi at (t, q, q'), with nothing returned by
    /// value, for a caller that reuses one buffer. The emitted code writes the entries
    /// directly (on x86-64 builds without AVX2, from a second copy compiled with AVX2
    /// where the CPU has it, with the same bits); the default copies the result of
    /// `evaluate`.
    fn evaluate_into(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
        out: &mut StaticEvaluation<N, M>,
    ) {
        *out = self.evaluate(t, q, qd);
    }
    /// The structural nonzeros of M and Phi_q (see [`StaticSparsity`]); `None` for a
    /// hand-written impl that does not provide [`Mechanism::evaluate_sparse_into`].
    const SPARSITY: Option<StaticSparsity> = None;

    /// [`Mechanism::evaluate_into`] into run-time buffers, writing M and Phi_q at
    /// [`Mechanism::SPARSITY`] only (the caller keeps their other entries at zero: no
    /// zeroing or copying of the dense matrices per call) and every entry of the vectors.
    /// Returns false, writing nothing, when a slice does not have the length of n = `N`
    /// coordinates and m = `M` rows, or when the impl does not provide it (the default).
    fn evaluate_sparse_into(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
        out: &mut EvaluationSlices<'_>,
    ) -> bool {
        let _ = (t, q, qd, out);
        false
    }
    /// Phi_q (column-major, M N entries) written at [`Mechanism::SPARSITY`] only (the
    /// caller keeps the other entries at zero) and Phi_t (M entries). Returns false, writing
    /// nothing, for slices of other lengths or when not provided (the default).
    fn constraint_jacobian_sparse_into(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        phi_q: &mut [f64],
        phi_t: &mut [f64],
    ) -> bool {
        let _ = (t, q, phi_q, phi_t);
        false
    }
    /// Brings values cached from the parameters up to date (the emitted code caches the
    /// parameter-only subexpressions; `set_parameter` refreshes them itself, a change
    /// through a field does not). Nothing by default.
    fn refresh(&mut self) {}
    /// The derived equations as readable text (what the snapshot tests pin).
    fn equations() -> &'static str;

    /// World positions of the drawn points at (t, q): x, y, z of point k in
    /// `out[3 k..3 k + 3]` (`out` must hold 3 [`Mechanism::DRAW_POINTS`]`.len()` values; a
    /// shorter slice is left untouched). Nothing for a declaration without a drawing.
    fn draw_points(&self, t: f64, q: &SVector<f64, N>, out: &mut [f64]) {
        let _ = (t, q, out);
    }

    /// M(q) and the bias b(t, q, q') = C q' + g - tau: without constraints the dynamics is
    /// M q'' + b = u for an effort u along the coordinates. One program in the emitted code
    /// (M and b share their sines, cosines and subexpressions); the default reads
    /// [`Mechanism::evaluate`].
    fn mass_and_bias(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
    ) -> (SMatrix<f64, N, N>, SVector<f64, N>) {
        let e = self.evaluate(t, q, qd);
        (e.mass, e.coriolis + e.gravity - e.forces)
    }

    /// The bias b(t, q, q') = C q' + g - tau alone, without M: the effort that holds the
    /// mechanism at q'' = 0 (Pinocchio's `nonLinearEffects` for a robot without declared
    /// forces). Emitted as its own program (for links one Newton-Euler pass with the base
    /// accelerating at -g, O(n)); the default reads [`Mechanism::evaluate`].
    fn bias(&self, t: f64, q: &SVector<f64, N>, qd: &SVector<f64, N>) -> SVector<f64, N> {
        let e = self.evaluate(t, q, qd);
        e.coriolis + e.gravity - e.forces
    }

    /// Inverse dynamics: the effort u = M q'' + C q' + g - tau that, added to the declared
    /// forces tau, gives the accelerations q'' when no constraint acts (Pinocchio's `rnea`
    /// for a robot without declared forces). Emitted for links by Newton-Euler (O(n)); the
    /// default multiplies out [`Mechanism::mass_and_bias`]. A mechanism with constraint rows
    /// also needs Phi_q^T lambda: see `mechanism::inverse_dynamics` at run time.
    fn inverse_dynamics(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        let (m, b) = self.mass_and_bias(t, q, qd);
        m * qdd + b
    }

    /// Forward dynamics of an unconstrained mechanism (M = 0 rows): q'' from
    /// M q'' = u - b. Emitted as straight-line code (M, b and the factorisation
    /// M = L^T D L whose fill-in follows M's pattern: for a tree of links, no branch fills
    /// another); the default factors the static M by Cholesky at run time (no allocation).
    /// `None` when the mechanism has constraint rows (solve the KKT system,
    /// [`crate::fixed::kkt_solve`]) or M is not positive definite at q (a pivot not above
    /// 1e-14 of its diagonal entry, or of the largest one for the default), or q'' is not
    /// finite.
    fn forward_dynamics(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
        effort: &SVector<f64, N>,
    ) -> Option<SVector<f64, N>> {
        if M != 0 {
            return None;
        }
        let (m, b) = self.mass_and_bias(t, q, qd);
        let rhs = effort - b;
        // A pivot below 1e-14 of the largest diagonal entry: M is singular to round-off.
        let chol = crate::fixed::cholesky::Cholesky::new(m, 1e-14);
        if chol.first_dropped().is_some() {
            return None;
        }
        let qdd = chol.solve(&rhs);
        qdd.iter().all(|x| x.is_finite()).then_some(qdd)
    }

    /// Forward dynamics with the constraint rows: q'' and lambda of the augmented (KKT)
    /// system M q'' + Phi_q^T lambda = tau - C q' - g, Phi_q q'' = gamma at (t, q, q'),
    /// with the semantics and errors of [`crate::fixed::kkt_solve`] (which this default
    /// calls on [`Mechanism::evaluate`]). Emitted for a mechanism with constraint rows
    /// where it counts fewer operations: M = L^T D L over M's pattern as the forward
    /// dynamics factors it, u = M^-1 Q, Y = M^-1 Phi_q^T and S = Phi_q M^-1 Phi_q^T in
    /// straight-line code, then [`crate::fixed::kkt_tree_solve`] (S lambda = Phi_q u -
    /// gamma, q'' = u - Y lambda, redundant rows dropped as `kkt_solve` drops them); where
    /// a pivot is not above 1e-12 of its diagonal entry (M singular off the constraint
    /// manifold) or a value is not finite, it returns what `kkt_solve` returns.
    ///
    /// # Errors
    /// Those of [`crate::fixed::kkt_solve`].
    fn constrained_dynamics(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
    ) -> Result<crate::fixed::KktSolution<N, M>, crate::fixed::FixedError> {
        crate::fixed::kkt_solve(&self.evaluate(t, q, qd), t)
    }

    /// The link frames (`link` sections) in declaration order; empty without links.
    const FRAMES: &'static [&'static str] = &[];

    /// The index of the frame called `name` in [`Mechanism::FRAMES`].
    fn frame_index(name: &str) -> Option<usize> {
        Self::FRAMES.iter().position(|f| *f == name)
    }

    /// The placement of link frame `frame` at q: (R, p), R the link axes in world axes and
    /// p its origin in the world (the world frame: z up where gravity is -z). `None` for an
    /// index out of range, or a declaration without links.
    fn frame_placement(
        &self,
        frame: usize,
        q: &SVector<f64, N>,
    ) -> Option<(SMatrix<f64, 3, 3>, SVector<f64, 3>)> {
        let _ = (frame, q);
        None
    }

    /// The Jacobian J (6 x N) of link frame `frame` at q: [v; w] = J q', v the velocity of
    /// the frame's origin and w its angular velocity, both in world axes (Pinocchio's
    /// `LOCAL_WORLD_ALIGNED`). `None` as for [`Mechanism::frame_placement`].
    fn frame_jacobian(&self, frame: usize, q: &SVector<f64, N>) -> Option<SMatrix<f64, 6, N>> {
        let _ = (frame, q);
        None
    }

    /// The derivatives of the inverse dynamics tau_id = M q'' + C q' + g - tau
    /// ([`Mechanism::inverse_dynamics`]) at (t, q, q', q''): (dtau_id/dq, dtau_id/dq'),
    /// N x N each (dtau_id/dq'' is M), Pinocchio's `computeRNEADerivatives` for a robot
    /// without declared forces. Emitted for every declaration, derived symbolically and
    /// sharing the subexpressions of the dynamics; the default reads
    /// [`Mechanism::residual_tangent`] at lambda = 0 (the same matrices), or takes central
    /// differences of [`Mechanism::inverse_dynamics`] where there is none (about 1e-10
    /// relative).
    fn inverse_dynamics_derivatives(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
    ) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>) {
        crate::fixed::derivatives::inverse_dynamics_derivatives(self, t, q, qd, qdd)
    }

    /// The derivatives of the inverse dynamics by the declared parameters,
    /// dtau_id/dp (N x P, P = [`Mechanism::PARAMETERS`]`.len()`, columns in declaration
    /// order), written column-major into `out` (entry (i, k) at `out[i + k N]`): for
    /// identification and design. The units of column k are those of tau per unit of
    /// parameter k. Returns false, writing nothing, when `out` does not hold N P values or
    /// the impl does not provide it (the default; the code `mechanism!` emits does).
    fn inverse_dynamics_parameter_derivatives(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
        out: &mut [f64],
    ) -> bool {
        let _ = (t, q, qd, qdd, out);
        false
    }

    /// The derivatives of the forward dynamics of a mechanism without constraint rows at
    /// (t, q, q') and the effort u ([`Mechanism::forward_dynamics`]):
    /// (dq''/dq, dq''/dq', M^-1), with dq''/dx = -M^-1 dtau_id/dx at the q'' of the forward
    /// dynamics and dq''/du = M^-1 (Carpentier & Mansard 2018; Pinocchio's
    /// `computeABADerivatives`). No allocation. `None` as for
    /// [`Mechanism::forward_dynamics`] (constraint rows: see
    /// [`Mechanism::constrained_dynamics_derivatives`]; M not positive definite at q) or
    /// where a value is not finite.
    #[allow(clippy::type_complexity)]
    fn forward_dynamics_derivatives(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
        effort: &SVector<f64, N>,
    ) -> Option<(SMatrix<f64, N, N>, SMatrix<f64, N, N>, SMatrix<f64, N, N>)> {
        crate::fixed::forward_dynamics_derivatives(self, t, q, qd, effort)
    }

    /// The derivatives of the constrained forward dynamics at (t, q, q') with the effort
    /// u added to the declared forces: q'' and lambda of [`crate::fixed::kkt_solve`] and
    /// their derivatives by q, q' and u, through the augmented system's derivative (see
    /// [`crate::fixed::KktDerivatives`]; the rows kkt_solve finds redundant keep
    /// lambda = 0 and dlambda = 0). No allocation; a mechanism without rows gets the
    /// derivatives of [`Mechanism::forward_dynamics_derivatives`].
    ///
    /// # Errors
    /// As [`crate::fixed::kkt_derivatives`].
    fn constrained_dynamics_derivatives(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
        effort: &SVector<f64, N>,
    ) -> Result<crate::fixed::KktDerivatives<N, M>, crate::fixed::FixedError> {
        crate::fixed::kkt_derivatives(self, t, q, qd, effort)
    }

    /// The constraint rows' tangents at (t, q, q', q''): with w = Phi_q q' + Phi_t and
    /// R = Phi_q q'' - gamma, (dw/dq, dR/dq, dR/dq'), M x N each (see
    /// [`crate::ConstraintTangent`]); what the constrained dynamics' derivatives read.
    /// `None` when not provided (the default; the code `mechanism!` emits provides it).
    #[allow(clippy::type_complexity)]
    fn constraint_tangent(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
    ) -> Option<(SMatrix<f64, M, N>, SMatrix<f64, M, N>, SMatrix<f64, M, N>)> {
        let _ = (t, q, qd, qdd);
        None
    }

    /// K = dF/dq and D = dF/dq' of the residual F = M q'' + C q' + g - tau + Phi_q^T lambda,
    /// derived symbolically (exact Jacobians for implicit integrators); `None` when the
    /// mechanism does not provide them.
    fn residual_tangent(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
        lambda: &SVector<f64, M>,
    ) -> Option<(SMatrix<f64, N, N>, SMatrix<f64, N, N>)> {
        let _ = (t, q, qd, qdd, lambda);
        None
    }
}
