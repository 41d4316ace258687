//! The derivatives of a floating-base robot's dynamics by the tangent of its configuration
//! manifold (Pinocchio's `computeRNEADerivatives` and `computeABADerivatives` with
//! `JointModelFreeFlyer`): column k of a derivative by q is the rate of change along
//! q (+) e e_k ([`super::free_flyer::integrate`] with the velocity e_k for the time e), so q's
//! NQ entries are differentiated through NV directions. The forward dynamics' follow from
//! the inverse dynamics' at a = M^-1 (effort - b): differentiating M a + b = effort,
//!
//! ```text
//! da/dq = -M^-1 dtau_id/dq,   da/dv = -M^-1 dtau_id/dv,   da/d(effort) = M^-1.
//! ```

use nalgebra::{SMatrix, SVector};

use super::free_flyer::integrate;
use crate::fixed::cholesky::Cholesky;

/// A pivot below 1e-14 of M's largest diagonal entry: M is singular to round-off (the
/// tolerance of the floating base's `forward_dynamics`).
const SINGULAR: f64 = 1e-14;

/// (dtau_id/dq, dtau_id/dv) by central differences on the manifold, for an impl that does
/// not provide them: q (+) (+-h e_k), the step h = 6e-6 max(1, |x_k|) (eps^(1/3): the
/// truncation h^2 and the round-off eps/h balanced, about 1e-10 relative).
/// `tau_id(q, v)` is the inverse dynamics at the caller's t and a.
pub(crate) fn inverse_dynamics_differences<const NQ: usize, const NV: usize>(
    tau_id: impl Fn(&SVector<f64, NQ>, &SVector<f64, NV>) -> SVector<f64, NV>,
    q: &SVector<f64, NQ>,
    v: &SVector<f64, NV>,
) -> (SMatrix<f64, NV, NV>, SMatrix<f64, NV, NV>) {
    let mut dq = SMatrix::<f64, NV, NV>::zeros();
    let mut dv = SMatrix::<f64, NV, NV>::zeros();
    for k in 0..NV {
        let mut e = SVector::<f64, NV>::zeros();
        // The joints' step scales with their position; the root's twist starts at zero.
        let at = if k < 6 { 0.0 } else { q[k + 1] };
        let h = 6e-6 * at.abs().max(1.0);
        e[k] = 1.0;
        let (up, down) = (integrate(q, &e, h), integrate(q, &e, -h));
        let diff = tau_id(&up, v) - tau_id(&down, v);
        dq.set_column(k, &(diff / (2.0 * h)));
        let h = 6e-6 * v[k].abs().max(1.0);
        let (mut up, mut down) = (*v, *v);
        up[k] += h;
        down[k] -= h;
        let diff = tau_id(q, &up) - tau_id(q, &down);
        dv.set_column(k, &(diff / (up[k] - down[k])));
    }
    (dq, dv)
}

/// (da/dq, da/dv, M^-1) at (t, q, v) and `effort` (module docs); `None` where M is not
/// positive definite (a pivot below 1e-14 of the largest diagonal entry) or a value is not
/// finite.
#[allow(clippy::type_complexity)]
/// `(mass, bias)` are M and b at (t, q, v); `derivatives(a)` gives (dtau_id/dq, dtau_id/dv)
/// at the solved a.
pub(crate) fn forward_dynamics_derivatives<const NV: usize>(
    (mass, bias): (SMatrix<f64, NV, NV>, SVector<f64, NV>),
    effort: &SVector<f64, NV>,
    derivatives: impl FnOnce(&SVector<f64, NV>) -> (SMatrix<f64, NV, NV>, SMatrix<f64, NV, NV>),
) -> Option<(
    SMatrix<f64, NV, NV>,
    SMatrix<f64, NV, NV>,
    SMatrix<f64, NV, NV>,
)> {
    let chol = Cholesky::new(mass, SINGULAR);
    if chol.first_dropped().is_some() {
        return None;
    }
    let a = chol.solve(&(effort - bias));
    // M^-1 = L^-T L^-1, its lower triangle computed and mirrored (exactly symmetric).
    let inverse = chol.inverse();
    let (dq, dv) = derivatives(&a);
    let (dq, dv) = (-chol.solve_columns(&dq), -chol.solve_columns(&dv));
    let finite = [&dq, &dv, &inverse]
        .iter()
        .all(|m| m.iter().fold(true, |ok, x| ok & x.is_finite()));
    finite.then_some((dq, dv, inverse))
}
