//! A spatial tree declared with links, emitted by `mechanism!`: the robotics methods against
//! each other and against independent truth (finite differences of the placements, the
//! power balance of C q').

use mechanism::Mechanism;
use nalgebra::{SMatrix, SVector};

// The spatial tree with every kind of link, shared with codegen's route tests.
mechanism::mechanism!(file = "codegen/tests/bodies/link_tree.mech");

type V = SVector<f64, 5>;

fn state(k: usize) -> (V, V, V) {
    let f = |s: f64, a: f64| V::from_fn(|i, _| ((k * 7 + i * 3) as f64 * s + a).sin());
    (f(0.37, 0.0) * 2.5, f(0.61, 1.0) * 1.7, f(0.23, 2.0) * 3.1)
}

fn max_abs<const R: usize, const C: usize>(m: &SMatrix<f64, R, C>) -> f64 {
    m.iter().fold(0.0_f64, |a, x| a.max(x.abs()))
}

/// Newton-Euler's inverse dynamics equals composite bodies' M times q'' plus the bias, and
/// the forward dynamics (M = L^T D L over M's pattern, generated) inverts it: two
/// algorithms that share nothing but the links. Both sides sum O(100) products of
/// magnitude up to ~100 N m: 1e-12 of that scale bounds their rounding; the forward
/// dynamics against nalgebra's Cholesky solve of the same M and b, to 1e-13 cond(M) of
/// |q''| (both solves err by about eps cond(M) |q''|).
#[test]
fn inverse_and_forward_dynamics_agree_with_mass_and_bias() {
    let r = LinkTree::default();
    for k in 0..20 {
        let (q, qd, qdd) = state(k);
        let (m, b) = r.mass_and_bias(0.0, &q, &qd);
        let tau = r.inverse_dynamics(0.0, &q, &qd, &qdd);
        let direct = m * qdd + b;
        let scale = max_abs(&direct).max(1.0);
        assert!(max_abs(&(tau - direct)) <= 1e-12 * scale, "state {k}");
        let back = r.forward_dynamics(0.0, &q, &qd, &tau).unwrap();
        assert!(max_abs(&(back - qdd)) <= 1e-9 * max_abs(&qdd), "state {k}");
        let eig = m.symmetric_eigenvalues();
        let cond = eig.max() / eig.min();
        let dense = m.cholesky().unwrap().solve(&(tau - b));
        let err = max_abs(&(back - dense));
        assert!(err <= 1e-13 * cond * max_abs(&dense), "state {k}: {err:e}");
        // The single-output methods agree with the combined program.
        let e = r.evaluate(0.0, &q, &qd);
        assert!(max_abs(&(e.mass - m)) <= 1e-14 * max_abs(&m));
        assert!(max_abs(&(e.coriolis + e.gravity - b)) <= 1e-12 * scale);
        assert!(max_abs(&(r.bias(0.0, &q, &qd) - b)) <= 1e-12 * scale);
    }
}

/// The frame Jacobian's columns are the derivatives of the placement: the origin's
/// velocity dp/dq_j, and the angular velocity vee(dR/dq_j R^T). Central differences with
/// h = 1e-6 err by O(h^2) ~ 1e-12 times the third derivative (~1 m here) plus
/// rounding ~1e-16/h = 1e-10: 1e-8 bounds both.
#[test]
fn frame_jacobians_are_the_derivatives_of_the_placements() {
    let r = LinkTree::default();
    assert_eq!(
        LinkTree::FRAMES,
        &["base", "l1", "l2", "l3", "tool", "slider", "branch"]
    );
    let h = 1e-6;
    for frame in 0..LinkTree::FRAMES.len() {
        for k in 0..5 {
            let (q, _, _) = state(k);
            let jac = r.frame_jacobian(frame, &q).unwrap();
            let (rot, _) = r.frame_placement(frame, &q).unwrap();
            // R is a rotation.
            let orth = rot.transpose() * rot - SMatrix::<f64, 3, 3>::identity();
            assert!(max_abs(&orth) < 1e-14);
            for j in 0..5 {
                let mut qp = q;
                qp[j] += h;
                let mut qm = q;
                qm[j] -= h;
                let (rp, pp) = r.frame_placement(frame, &qp).unwrap();
                let (rm, pm) = r.frame_placement(frame, &qm).unwrap();
                let dp = (pp - pm) / (2.0 * h);
                let dr = (rp - rm) / (2.0 * h);
                let w = dr * rot.transpose();
                let omega = [w[(2, 1)], w[(0, 2)], w[(1, 0)]];
                for i in 0..3 {
                    assert!(
                        (jac[(i, j)] - dp[i]).abs() < 1e-8,
                        "frame {frame} v{i} q{j}"
                    );
                    assert!(
                        (jac[(3 + i, j)] - omega[i]).abs() < 1e-8,
                        "frame {frame} w{i} q{j}"
                    );
                }
            }
        }
    }
    assert!(
        r.frame_placement(LinkTree::FRAMES.len(), &V::zeros())
            .is_none()
    );
    assert_eq!(LinkTree::frame_index("tool"), Some(4));
}

/// Newton-Euler's C q' against the power balance q'^T C q' = 1/2 q'^T M' q', with
/// M' = dM/dt along q' by central differences (h = 1e-6: error ~1e-10 of |M|).
#[test]
fn coriolis_forces_satisfy_the_power_balance() {
    let r = LinkTree::default();
    let h = 1e-6;
    for k in 0..10 {
        let (q, qd, _) = state(k);
        let mdot = (r.mass_matrix(&(q + qd * h)) - r.mass_matrix(&(q - qd * h))) / (2.0 * h);
        let lhs = qd.dot(&r.coriolis_forces(&q, &qd));
        let rhs = 0.5 * qd.dot(&(mdot * qd));
        assert!(
            (lhs - rhs).abs() < 1e-7 * (1.0 + rhs.abs()),
            "{lhs} vs {rhs}"
        );
    }
}

/// The open tree needs no `independent`: every coordinate is independent, at rest.
#[test]
fn an_open_tree_has_every_coordinate_independent() {
    assert_eq!(LinkTree::COORDINATES, ["q1", "q2", "q3", "d4", "q5"]);
    assert_eq!(LinkTree::INDEPENDENT.len(), 5);
    assert!(LinkTree::INDEPENDENT.iter().all(|i| i.velocity == 0.0));
}

/// The residual's tangent (for the implicit integrators), derived symbolically from the
/// recursive route's expressions, against central differences of
/// F(q, q') = M q'' + C q' + g - tau: K = dF/dq, D = dF/dq'. h = 1e-6 bounds the
/// difference's error by ~1e-12 |F'''| + 1e-16 |F| / h: 1e-7 of the scale.
#[test]
fn residual_tangent_is_the_derivative_of_the_residual() {
    let r = LinkTree::default();
    let h = 1e-6;
    let lambda = SVector::<f64, 0>::zeros();
    for k in 0..5 {
        let (q, qd, qdd) = state(k);
        let (stiffness, damping) = r.residual_tangent(0.0, &q, &qd, &qdd, &lambda).unwrap();
        let f = |q: &V, qd: &V| r.inverse_dynamics(0.0, q, qd, &qdd);
        let scale = max_abs(&f(&q, &qd)).max(1.0);
        for j in 0..5 {
            let e = V::from_fn(|i, _| if i == j { h } else { 0.0 });
            let dq = (f(&(q + e), &qd) - f(&(q - e), &qd)) / (2.0 * h);
            let dqd = (f(&q, &(qd + e)) - f(&q, &(qd - e))) / (2.0 * h);
            for i in 0..5 {
                assert!(
                    (stiffness[(i, j)] - dq[i]).abs() < 1e-7 * scale,
                    "K[{i},{j}]"
                );
                assert!(
                    (damping[(i, j)] - dqd[i]).abs() < 1e-7 * scale,
                    "D[{i},{j}]"
                );
            }
        }
    }
}

// Two links: the second turns about its own origin and carries a point mass there and no
// inertia, so its joint moves no mass (M's second row and column vanish).
mechanism::mechanism! {
    struct IdleJoint;
    parameters { g = 9.81; }
    gravity = [0, 0, -g];
    link arm {
        joint = revolute(a, [0, 0, 1]);
        mass = 2;
        com = [0.5, 0, 0];
        inertia = [[0.01, 0, 0], [0, 0.02, 0], [0, 0, 0.03]];
    }
    link hub {
        parent = arm;
        joint = revolute(b, [0, 0, 1]);
        xyz = [1, 0, 0];
        mass = 1;
    }
}

/// Where M is singular the generated forward dynamics says so (`None`: the second pivot of
/// M = L^T D L is 0), without a panic or a NaN.
#[test]
fn the_forward_dynamics_refuses_a_singular_mass_matrix() {
    let r = IdleJoint::default();
    let q = SVector::<f64, 2>::new(0.3, -0.4);
    let qd = SVector::<f64, 2>::new(0.5, 1.0);
    let u = SVector::<f64, 2>::new(1.0, 0.0);
    let m = r.mass_matrix(&q);
    assert_eq!((m[(1, 1)], m[(0, 1)]), (0.0, 0.0));
    assert_eq!(r.forward_dynamics(0.0, &q, &qd, &u), None);
    // The bias and the inverse dynamics are defined all the same.
    assert!(r.bias(0.0, &q, &qd).iter().all(|x| x.is_finite()));
}
