//! The factors of the orientation products bodies declare
//! (`rot_z(psi) * rot_x(phi) * rot_y(th)`), by which the runtime names a singularity of
//! orientation angles: an attitude where two of the angles' axes line up and their rates
//! are not determined (`algorithms/coordinate_singularity.rs`).

/// One factor of a body's declared orientation R = F_1 F_2 ... (body to world).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RotationFactor {
    /// The axis of an elementary rotation: 0, 1, 2 for `rot_x`, `rot_y`, `rot_z`; `None`
    /// for an explicit 3 x 3 factor.
    pub axis: Option<usize>,
    /// The coordinate that is its angle (its index in q); `None` for any other angle (a
    /// parameter, an expression).
    pub coordinate: Option<usize>,
}
