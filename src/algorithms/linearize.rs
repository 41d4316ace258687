//! Linearisation of the constrained dynamics in the independent coordinates.
//!
//! With u the independent coordinates and q(u) the configuration assembled from them
//! (Phi(q(u), t) = 0), the motion is the ODE u'' = a(u, u') on the constraint manifold,
//! a = the u-rows of q'' from the augmented system. About a state (u0, u0') the tangent
//! dynamics are
//!
//! ```text
//! d/dt [du; du'] = A [du; du'],   A = [ 0        I        ]
//!                                     [ da/du    da/du'   ]
//! ```
//!
//! with the derivatives by central differences of the full constrained dynamics (assembly,
//! velocities and the augmented system at each perturbed point). The null-space basis
//! R = dq/du (from Phi_q R = 0, the dependent/independent partition) gives the reduced mass
//! M_r = R^T M R, stiffness K_r = -M_r da/du and damping D_r = -M_r da/du'
//! (Haug 1989, ch. 6; Nikravesh 1988, sec. 12.4). Eigenvalues s of A give the natural
//! frequencies omega = |s| (rad/s) and f = omega / (2 pi) (Hz) of the oscillatory modes.

use nalgebra::{Complex, DMatrix};

use crate::algorithms::dynamics::Dynamics;
use crate::algorithms::kinematics::{
    AssemblyOptions, check_fixed, solve_positions, solve_velocities,
};
use crate::error::Error;
use crate::system::System;

/// The linearised dynamics about one state.
#[derive(Clone, Debug, PartialEq)]
pub struct Linearization {
    /// Independent coordinate indices u.
    pub independent: Vec<usize>,
    /// State matrix A (2k x 2k) of d/dt [du; du'].
    pub a: DMatrix<f64>,
    /// Null-space basis R = dq/du (n x k).
    pub basis: DMatrix<f64>,
    /// Reduced mass M_r = R^T M R (k x k).
    pub mass: DMatrix<f64>,
    /// Reduced stiffness K_r = -M_r da/du.
    pub stiffness: DMatrix<f64>,
    /// Reduced damping D_r = -M_r da/du'.
    pub damping: DMatrix<f64>,
    /// Eigenvalues of A.
    pub eigenvalues: Vec<Complex<f64>>,
    /// Natural frequencies |s| (rad/s) of the oscillatory modes (Im s > 0), ascending.
    pub frequencies_rad_s: Vec<f64>,
    /// The same in Hz.
    pub frequencies_hz: Vec<f64>,
}

/// Linearises about the consistent state (q, q') at time t, with `independent` the
/// coordinates u. Use q' = 0 at an equilibrium.
pub fn linearize(
    system: &dyn System,
    t: f64,
    q: &[f64],
    qd: &[f64],
    independent: &[usize],
    options: &AssemblyOptions,
) -> Result<Linearization, Error> {
    let info = system.info();
    let n = info.n();
    check_fixed(info, independent)?;
    let k = independent.len();
    let mut dynamics = Dynamics::new(info);
    let a = state_matrix(system, t, q, qd, independent, options, &mut dynamics)?;
    // R = dq/du: velocities for unit independent rates, minus the rheonomic part.
    let mut basis = DMatrix::zeros(n, k);
    let mut v0 = vec![0.0; n];
    solve_velocities(system, t, q, independent, &mut v0, options)?;
    for j in 0..k {
        let mut v = vec![0.0; n];
        v[independent[j]] = 1.0;
        solve_velocities(system, t, q, independent, &mut v, options)?;
        for i in 0..n {
            basis[(i, j)] = v[i] - v0[i];
        }
    }
    dynamics.solve(system, t, q, qd)?;
    let mass = basis.transpose() * &dynamics.evaluation().mass * &basis;
    let stiffness = -(&mass * a.view((k, 0), (k, k)));
    let damping = -(&mass * a.view((k, k), (k, k)));
    let eigenvalues = crate::linalg::eigenvalues(&a, "the state matrix A")?;
    let mut frequencies_rad_s: Vec<f64> = eigenvalues
        .iter()
        .filter(|s| s.im > 1e-9 * (1.0 + s.norm()))
        .map(|s| s.norm())
        .collect();
    frequencies_rad_s.sort_by(f64::total_cmp);
    let frequencies_hz = frequencies_rad_s
        .iter()
        .map(|w| w / (2.0 * std::f64::consts::PI))
        .collect();
    Ok(Linearization {
        independent: independent.to_vec(),
        a,
        basis,
        mass,
        stiffness,
        damping,
        eigenvalues,
        frequencies_rad_s,
        frequencies_hz,
    })
}

/// A = [0 I; da/du da/du'] by central differences (h = 1e-5 (1 + |u|)) of the constrained
/// accelerations a(u, u') of the independent coordinates: at each perturbed point the
/// configuration is re-assembled and the augmented system solved.
fn state_matrix(
    system: &dyn System,
    t: f64,
    q: &[f64],
    qd: &[f64],
    independent: &[usize],
    options: &AssemblyOptions,
    dynamics: &mut Dynamics,
) -> Result<DMatrix<f64>, Error> {
    let n = system.info().n();
    let k = independent.len();
    let mut accel = |du: &[f64], dv: &[f64]| -> Result<Vec<f64>, Error> {
        let mut qq = q.to_vec();
        let mut vv = vec![0.0; n];
        for (j, &c) in independent.iter().enumerate() {
            qq[c] += du[j];
            vv[c] = qd[c] + dv[j];
        }
        solve_positions(system, t, independent, &mut qq, options)?;
        solve_velocities(system, t, &qq, independent, &mut vv, options)?;
        dynamics.solve(system, t, &qq, &vv)?;
        Ok(independent
            .iter()
            .map(|&c| dynamics.accelerations()[c])
            .collect())
    };
    let mut a = DMatrix::zeros(2 * k, 2 * k);
    for j in 0..k {
        a[(j, k + j)] = 1.0;
    }
    let zero = vec![0.0; k];
    for j in 0..2 * k {
        let base = if j < k {
            q[independent[j]]
        } else {
            qd[independent[j - k]]
        };
        let h = 1e-5 * (1.0 + base.abs());
        let mut e = vec![0.0; k];
        e[j % k] = h;
        let (p, m) = if j < k {
            (
                accel(&e, &zero)?,
                accel(&e.iter().map(|x| -x).collect::<Vec<_>>(), &zero)?,
            )
        } else {
            (
                accel(&zero, &e)?,
                accel(&zero, &e.iter().map(|x| -x).collect::<Vec<_>>())?,
            )
        };
        for i in 0..k {
            a[(k + i, j)] = (p[i] - m[i]) / (2.0 * h);
        }
    }
    Ok(a)
}
