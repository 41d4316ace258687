//! Solo12 declared from its URDF with a floating base in a `#![no_std]` crate: the
//! `FloatingBase` methods and the manifold step build for a target without std.

use mechanism::nalgebra::SVector;
use mechanism::{FloatingBase, mechanism};

mechanism!(urdf = "mechanisms/urdf/solo12.urdf", floating = true);

/// One explicit Euler step of the free-falling robot on its manifold: a = M^-1 (u - b),
/// q moved by v h, v by a h (`None` where M is not positive definite).
pub fn step(
    q: &SVector<f64, 19>,
    v: &SVector<f64, 18>,
    u: &SVector<f64, 18>,
    h: f64,
) -> Option<(SVector<f64, 19>, SVector<f64, 18>)> {
    let a = Solo::default().forward_dynamics(0.0, q, v, u)?;
    Some((Solo::integrate(q, v, h), v + a * h))
}
