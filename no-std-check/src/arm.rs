//! The Franka Panda declared from its URDF in a `#![no_std]` crate: the robotics methods of a
//! link declaration (inverse and forward dynamics, a frame's placement and Jacobian) build
//! for a target without std.

use mechanism::nalgebra::{SMatrix, SVector};
use mechanism::{Mechanism, mechanism};

mechanism!(
    urdf = "mechanisms/urdf/panda.urdf",
    lock = ["panda_finger_joint1", "panda_finger_joint2"]
);

/// One computed-torque command: u = tau_id(q, q', q_d'' + kd (q_d' - q') + kp (q_d - q)).
pub fn computed_torque(
    q: &SVector<f64, 7>,
    qd: &SVector<f64, 7>,
    target: (&SVector<f64, 7>, &SVector<f64, 7>, &SVector<f64, 7>),
    gains: (f64, f64),
) -> SVector<f64, 7> {
    let (q_d, qd_d, qdd_d) = target;
    let command = qdd_d + (qd_d - qd) * gains.1 + (q_d - q) * gains.0;
    Panda::default().inverse_dynamics(0.0, q, qd, &command)
}

/// q'' of the free arm under the effort `u` (`None` where M is not positive definite).
pub fn accelerations(
    q: &SVector<f64, 7>,
    qd: &SVector<f64, 7>,
    u: &SVector<f64, 7>,
) -> Option<SVector<f64, 7>> {
    Panda::default().forward_dynamics(0.0, q, qd, u)
}

/// The hand's Jacobian (6 x 7, world axes) at q.
pub fn hand_jacobian(q: &SVector<f64, 7>) -> Option<SMatrix<f64, 6, 7>> {
    let hand = Panda::frame_index("panda_hand")?;
    Panda::default().frame_jacobian(hand, q)
}

/// The derivatives a controller linearises the free arm with at (q, q', u): dtau/dq and
/// dtau/dq' of the inverse dynamics at q'' = `qdd`, and dq''/dq, dq''/dq' and M^-1 of the
/// forward dynamics (`None` where M is not positive definite).
#[allow(clippy::type_complexity)]
pub fn derivatives(
    q: &SVector<f64, 7>,
    qd: &SVector<f64, 7>,
    qdd: &SVector<f64, 7>,
    u: &SVector<f64, 7>,
) -> Option<(
    (SMatrix<f64, 7, 7>, SMatrix<f64, 7, 7>),
    (SMatrix<f64, 7, 7>, SMatrix<f64, 7, 7>, SMatrix<f64, 7, 7>),
)> {
    let arm = Panda::default();
    let inverse = arm.inverse_dynamics_derivatives(0.0, q, qd, qdd);
    Some((inverse, arm.forward_dynamics_derivatives(0.0, q, qd, u)?))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The computed torque with zero gains at q'' = forward dynamics of u gives u back.
    #[test]
    fn inverse_dynamics_inverts_forward_dynamics() {
        let q = SVector::<f64, 7>::from([0.1, -0.7, 0.2, -2.2, 0.1, 1.5, 0.8]);
        let qd = SVector::<f64, 7>::from([0.3, -0.2, 0.1, 0.4, -0.5, 0.2, 0.1]);
        let u = SVector::<f64, 7>::from([3.0, -8.0, 1.0, 5.0, 0.5, -0.3, 0.1]);
        let qdd = accelerations(&q, &qd, &u).unwrap();
        let back = computed_torque(&q, &qd, (&q, &qd, &qdd), (0.0, 0.0));
        // M's condition number here is below 1e3: 1e-10 of |u| bounds the round trip.
        assert!((back - u).amax() < 1e-10 * u.amax());
        assert!(hand_jacobian(&q).is_some());
        // dq''/du = M^-1: the product with M is the identity (cond(M) < 1e3 as above).
        let ((_, _), (_, _, inverse)) = derivatives(&q, &qd, &qdd, &u).unwrap();
        let m = Panda::default().mass_matrix(&q);
        assert!((inverse * m - SMatrix::<f64, 7, 7>::identity()).amax() < 1e-12);
    }
}
