//! The derivatives of the crank-slider's constrained dynamics (q'' and lambda by q, q' and
//! an effort) through the fixed-size solver, for a target without std.

use mechanism::Mechanism;
use mechanism::fixed::{FixedError, KktDerivatives, State};
use mechanism::nalgebra::SVector;

use crate::SpatialCrankSlider;

/// q'', lambda and their derivatives at the state `state` with the effort `u` added to the
/// declared forces.
pub fn derivatives(
    state: &State<4>,
    u: &SVector<f64, 4>,
) -> Result<KktDerivatives<4, 3>, FixedError> {
    SpatialCrankSlider::default().constrained_dynamics_derivatives(state.t, &state.q, &state.qd, u)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An effort along the coordinates moves q'' only within the constraints: Phi_q dq''/du
    /// = 0 (the derivative of Phi_q q'' = gamma by u, with gamma free of u).
    #[test]
    fn effort_responses_keep_the_constraints() {
        let state = crate::start(2.0).unwrap();
        let d = derivatives(&state, &SVector::zeros()).unwrap();
        let phi_q = SpatialCrankSlider::default().constraint_jacobian(state.t, &state.q);
        assert!((phi_q * d.dqdd_du).amax() < 1e-10 * d.dqdd_du.amax().max(1.0));
    }
}
