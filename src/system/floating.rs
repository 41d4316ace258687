//! The compiled face of a floating-base robot: [`FloatingBase`] is what `mechanism!` emits
//! for a tree whose root link declares `joint = floating(NAME)` (or a URDF imported with
//! `floating = true`), in Pinocchio's free-flyer layout:
//!
//! ```text
//! q = [p (3), quaternion x, y, z, w (4), joint positions]      NQ = 7 + joints
//! v = [v (3), w (3), joint rates]                              NV = 6 + joints
//! M(q) a + C(q, v) v + g(q) = tau                               (M: NV x NV)
//! p' = R(quaternion) v,   R' = R [w]x,   joint positions' = joint rates
//! ```
//!
//! p is the root's origin in the world, v the velocity of that origin and w the root's
//! angular velocity, both in the root's axes; a = v' and tau's first six entries are the
//! force and the moment about the root's origin in its axes.
//!
//! It is a trait of its own, not [`super::Mechanism`]: q and v differ in size and v is not
//! the rate of q, so every solver written for `Mechanism` (the projections, the KKT
//! solves, the integrators stepping q += h q') would be wrong on it; here the type system
//! keeps the two apart, and [`FloatingBase::integrate`] moves q on its manifold.

use nalgebra::{SMatrix, SVector};

pub use super::free_flyer::integrate;
use super::free_flyer::{cross, rotation};

use super::{ParameterError, ParameterRange};

/// A floating-base robot with static sizes (module docs): what `mechanism!` emits for a
/// declaration whose root link floats.
pub trait FloatingBase<const NQ: usize, const NV: usize>: Clone + Send + Sync + 'static {
    /// The struct name.
    const NAME: &'static str;
    /// The names of q's entries: `base_x`, `base_y`, `base_z`, `base_qx`, .., `base_qw`,
    /// then the joints'.
    const CONFIGURATION: [&'static str; NQ];
    /// The names of v's entries: `base_vx`, .., `base_wz`, then the joints'.
    const VELOCITIES: [&'static str; NV];
    /// Parameter names, in declaration order.
    const PARAMETERS: &'static [&'static str];
    /// The neutral configuration: the root at the origin with the identity quaternion
    /// (0, 0, 0, 1), each joint at its declared guess.
    const NEUTRAL: [f64; NQ];
    /// The link frames' names, in declaration order.
    const FRAMES: &'static [&'static str] = &[];

    /// The range each parameter's declaration gives it (`m = 3.0 positive;`), in
    /// declaration order; empty (the default) when no parameter has one.
    /// [`FloatingBase::set_parameter`] refuses a value outside it.
    const PARAMETER_RANGES: &'static [ParameterRange] = &[];

    /// The value of parameter `index`, `None` past the last.
    fn parameter(&self, index: usize) -> Option<f64>;
    /// Sets parameter `index` to `value` and refreshes the cached values.
    ///
    /// # Errors
    /// [`ParameterError::NoSuchParameter`] for an index past the last parameter,
    /// [`ParameterError::OutOfRange`] for a value outside the declared range
    /// ([`FloatingBase::PARAMETER_RANGES`]); the parameter keeps its value.
    fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError>;

    /// M(q), NV x NV, symmetric positive definite (Pinocchio's `crba`, both triangles).
    fn mass_matrix(&self, q: &SVector<f64, NQ>) -> SMatrix<f64, NV, NV>;
    /// C(q, v) v without gravity.
    fn coriolis_forces(&self, q: &SVector<f64, NQ>, v: &SVector<f64, NV>) -> SVector<f64, NV>;
    /// g(q): the generalised gravity (Pinocchio's `computeGeneralizedGravity`).
    fn gravity(&self, q: &SVector<f64, NQ>) -> SVector<f64, NV>;
    /// The declared generalised forces tau(t, q, v).
    fn generalized_forces(
        &self,
        t: f64,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
    ) -> SVector<f64, NV>;
    /// T = 1/2 v^T M(q) v.
    fn kinetic_energy(&self, q: &SVector<f64, NQ>, v: &SVector<f64, NV>) -> f64;
    /// Pi(q) of the links' gravity.
    fn potential_energy(&self, q: &SVector<f64, NQ>) -> f64;
    /// M and the bias b = C v + g - tau in one program (Pinocchio's `crba` and
    /// `nonLinearEffects` when no force is declared).
    fn mass_and_bias(
        &self,
        t: f64,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
    ) -> (SMatrix<f64, NV, NV>, SVector<f64, NV>);
    /// b = C v + g - tau alone, one Newton-Euler pass.
    fn bias(&self, t: f64, q: &SVector<f64, NQ>, v: &SVector<f64, NV>) -> SVector<f64, NV>;
    /// M a + C v + g - tau (Pinocchio's `rnea` when no force is declared): the effort that
    /// gives the acceleration a.
    fn inverse_dynamics(
        &self,
        t: f64,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
    ) -> SVector<f64, NV>;
    /// a = M^-1 (effort - b) (Pinocchio's `aba`), by the factorisation M = L^T D L that
    /// follows M's pattern; `None` when a pivot is not above 1e-14 of its diagonal entry
    /// or a is not finite.
    fn forward_dynamics(
        &self,
        t: f64,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
        effort: &SVector<f64, NV>,
    ) -> Option<SVector<f64, NV>>;

    /// The derivatives of the inverse dynamics tau_id = M a + C v + g - tau
    /// ([`FloatingBase::inverse_dynamics`]) at (t, q, v, a): (dtau_id/dq, dtau_id/dv), NV x NV
    /// each (dtau_id/da is M), Pinocchio's `computeRNEADerivatives` with its free flyer when
    /// no force is declared. Column k of dtau_id/dq is the rate along q (+) e e_k
    /// ([`integrate`]: the root moved by the twist e_k in its own axes, a joint by
    /// addition), so the root's first three columns are zero (the dynamics in the root's
    /// axes do not see its position) and the next three turn gravity in the root's axes.
    /// Emitted by `mechanism!` (derived symbolically, `mechanics::floating_derivatives` in
    /// codegen); the default takes central differences on the manifold (about 1e-10
    /// relative).
    fn inverse_dynamics_derivatives(
        &self,
        t: f64,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
        a: &SVector<f64, NV>,
    ) -> (SMatrix<f64, NV, NV>, SMatrix<f64, NV, NV>) {
        super::floating_derivatives::inverse_dynamics_differences(
            |q, v| self.inverse_dynamics(t, q, v, a),
            q,
            v,
        )
    }

    /// The derivatives of the forward dynamics at (t, q, v) and `effort`
    /// ([`FloatingBase::forward_dynamics`]): (da/dq, da/dv, M^-1), with
    /// da/dx = -M^-1 dtau_id/dx at the a of the forward dynamics and da/d(effort) = M^-1
    /// (Pinocchio's `computeABADerivatives`), q's direction as in
    /// [`FloatingBase::inverse_dynamics_derivatives`]. No allocation. `None` where M is not
    /// positive definite at q or a value is not finite.
    #[allow(clippy::type_complexity)]
    fn forward_dynamics_derivatives(
        &self,
        t: f64,
        q: &SVector<f64, NQ>,
        v: &SVector<f64, NV>,
        effort: &SVector<f64, NV>,
    ) -> Option<(
        SMatrix<f64, NV, NV>,
        SMatrix<f64, NV, NV>,
        SMatrix<f64, NV, NV>,
    )> {
        super::floating_derivatives::forward_dynamics_derivatives(
            self.mass_and_bias(t, q, v),
            effort,
            |a| self.inverse_dynamics_derivatives(t, q, v, a),
        )
    }

    /// The index of the frame `name` in [`FloatingBase::FRAMES`].
    fn frame_index(name: &str) -> Option<usize> {
        Self::FRAMES.iter().position(|f| *f == name)
    }
    /// (R, p) of link frame `frame`: its axes and origin in the world; `None` past the
    /// last frame.
    fn frame_placement(
        &self,
        frame: usize,
        q: &SVector<f64, NQ>,
    ) -> Option<(SMatrix<f64, 3, 3>, SVector<f64, 3>)>;
    /// J (6 x NV) of link frame `frame`, Pinocchio's LOCAL_WORLD_ALIGNED Jacobian: J v =
    /// [velocity of the frame's origin; its angular velocity], world axes.
    fn frame_jacobian(&self, frame: usize, q: &SVector<f64, NQ>) -> Option<SMatrix<f64, 6, NV>>;

    /// The centre of mass c in the world: x + R h / m, with m = M[0, 0] the total mass and
    /// h the first moment about the root's origin in its axes, read off M's root block
    /// `[[m 1, -[h]x], [[h]x, I]]` (Pinocchio's `centerOfMass`).
    fn center_of_mass(&self, q: &SVector<f64, NQ>) -> SVector<f64, 3> {
        let m = self.mass_matrix(q);
        center_of_mass(q, &m)
    }

    /// The centroidal momentum matrix A_g (6 x NV, Pinocchio's `ccrba`): A_g v = [p; L_c],
    /// the linear momentum and the angular momentum about the centre of mass, world axes.
    /// M's root rows are the momentum in the root's axes about its origin, so
    /// `A_g = [[R, 0], [-[c - x]x R, R]] M[0..6, :]`.
    fn centroidal_momentum_matrix(&self, q: &SVector<f64, NQ>) -> SMatrix<f64, 6, NV> {
        let m = self.mass_matrix(q);
        centroidal_momentum_matrix(q, &m)
    }

    /// The neutral configuration as a vector.
    fn neutral() -> SVector<f64, NQ> {
        SVector::from(Self::NEUTRAL)
    }

    /// q moved by v for the time dt on the configuration manifold ([`integrate`]).
    fn integrate(q: &SVector<f64, NQ>, v: &SVector<f64, NV>, dt: f64) -> SVector<f64, NQ> {
        integrate(q, v, dt)
    }
}

/// c = x + R h / m from q and M (see [`FloatingBase::center_of_mass`]).
fn center_of_mass<const NQ: usize, const NV: usize>(
    q: &SVector<f64, NQ>,
    m: &SMatrix<f64, NV, NV>,
) -> SVector<f64, 3> {
    if NQ < 7 || NV < 6 {
        return SVector::zeros();
    }
    // M[0..3, 3..6] = -[h]x = [[0, h_z, -h_y], [-h_z, 0, h_x], [h_y, -h_x, 0]].
    let h = [m[(1, 5)], m[(2, 3)], m[(0, 4)]];
    let r = rotation(&[q[3], q[4], q[5], q[6]]);
    let mass = m[(0, 0)];
    SVector::from_fn(|i, _| q[i] + (r[i][0] * h[0] + r[i][1] * h[1] + r[i][2] * h[2]) / mass)
}

/// A_g from q and M (see [`FloatingBase::centroidal_momentum_matrix`]).
fn centroidal_momentum_matrix<const NQ: usize, const NV: usize>(
    q: &SVector<f64, NQ>,
    m: &SMatrix<f64, NV, NV>,
) -> SMatrix<f64, 6, NV> {
    let mut out = SMatrix::<f64, 6, NV>::zeros();
    if NQ < 7 || NV < 6 {
        return out;
    }
    let r = rotation(&[q[3], q[4], q[5], q[6]]);
    let c = center_of_mass(q, m);
    let d = [c[0] - q[0], c[1] - q[1], c[2] - q[2]];
    for j in 0..NV {
        let f = [m[(0, j)], m[(1, j)], m[(2, j)]];
        let n = [m[(3, j)], m[(4, j)], m[(5, j)]];
        let rot = |v: [f64; 3]| [0, 1, 2].map(|i| r[i][0] * v[0] + r[i][1] * v[1] + r[i][2] * v[2]);
        let (p, l) = (rot(f), rot(n));
        let dp = cross(&d, &p);
        for i in 0..3 {
            out[(i, j)] = p[i];
            out[(3 + i, j)] = l[i] - dp[i];
        }
    }
    out
}
