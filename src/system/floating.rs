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
        super::floating_derivatives::inverse_dynamics_differences(self, t, q, v, a)
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
        super::floating_derivatives::forward_dynamics_derivatives(self, t, q, v, effort)
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

/// q (+) v dt (Pinocchio's `integrate`): the root by the exponential of SE(3), its pose
/// (R, p) moved to (R exp([w dt]x), p + R V(w dt) v dt) with the body-frame twist (v, w),
/// `V(phi) = 1 + (1 - cos t)/t^2 [phi]x + (t - sin t)/t^3 [phi]x^2` (t = |phi|); the
/// quaternion multiplied by (sin(t/2) phi/t, cos(t/2)) and normalised; each joint position
/// plus its rate times dt. Exact for a constant twist.
pub fn integrate<const NQ: usize, const NV: usize>(
    q: &SVector<f64, NQ>,
    v: &SVector<f64, NV>,
    dt: f64,
) -> SVector<f64, NQ> {
    let mut out = *q;
    if NQ < 7 || NV < 6 || NQ != NV + 1 {
        return out;
    }
    integrate_slices(q.as_slice(), v.as_slice(), dt, out.as_mut_slice());
    out
}

/// [`integrate`] on slices: q (nq = nv + 1 entries, at least 7) and v (nv) into `out` (nq).
pub(crate) fn integrate_slices(q: &[f64], v: &[f64], dt: f64, out: &mut [f64]) {
    let nv = v.len();
    let u = [v[0] * dt, v[1] * dt, v[2] * dt];
    let phi = [v[3] * dt, v[4] * dt, v[5] * dt];
    let t2 = phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2];
    let t = crate::math::sqrt(t2);
    // (1 - cos t)/t^2, (t - sin t)/t^3 and sin(t/2)/t, by their series below 1e-2 (the
    // first dropped term is below 1e-16 of each).
    let (b, c, s_half, c_half) = if t < 1e-2 {
        let t4 = t2 * t2;
        (
            0.5 - t2 / 24.0 + t4 / 720.0,
            1.0 / 6.0 - t2 / 120.0 + t4 / 5040.0,
            0.5 - t2 / 48.0 + t4 / 3840.0,
            1.0 - t2 / 8.0 + t4 / 384.0,
        )
    } else {
        let (s, co) = crate::math::sin_cos(t);
        let (sh, ch) = crate::math::sin_cos(0.5 * t);
        ((1.0 - co) / t2, (t - s) / (t2 * t), sh / t, ch)
    };
    // V u = u + b phi x u + c phi x (phi x u).
    let pu = cross(&phi, &u);
    let ppu = cross(&phi, &pu);
    let du = [0, 1, 2].map(|i| u[i] + b * pu[i] + c * ppu[i]);
    let quat = [q[3], q[4], q[5], q[6]];
    let r = rotation(&quat);
    for i in 0..3 {
        out[i] = q[i] + r[i][0] * du[0] + r[i][1] * du[1] + r[i][2] * du[2];
    }
    let d = [s_half * phi[0], s_half * phi[1], s_half * phi[2], c_half];
    let mut p = product(&quat, &d);
    let norm = crate::math::sqrt(p.iter().map(|x| x * x).sum::<f64>());
    for x in &mut p {
        *x /= norm;
    }
    out[3..7].copy_from_slice(&p);
    for j in 6..nv {
        out[j + 1] = q[j + 1] + v[j] * dt;
    }
}

fn cross(a: &[f64; 3], b: &[f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// R of the unit quaternion (x, y, z, w), as the generated code forms it.
pub(crate) fn rotation(q: &[f64; 4]) -> [[f64; 3]; 3] {
    let [x, y, z, w] = *q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - z * w),
            2.0 * (x * z + y * w),
        ],
        [
            2.0 * (x * y + z * w),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - x * w),
        ],
        [
            2.0 * (x * z - y * w),
            2.0 * (y * z + x * w),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// The Hamilton product a b of quaternions (x, y, z, w).
fn product(a: &[f64; 4], b: &[f64; 4]) -> [f64; 4] {
    let [ax, ay, az, aw] = *a;
    let [bx, by, bz, bw] = *b;
    [
        aw * bx + bw * ax + ay * bz - az * by,
        aw * by + bw * ay + az * bx - ax * bz,
        aw * bz + bw * az + ax * by - ay * bx,
        aw * bw - ax * bx - ay * by - az * bz,
    ]
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
