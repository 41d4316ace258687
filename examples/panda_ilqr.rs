//! Iterative LQR (Li & Todorov 2004) on the Franka Panda, linearised with the generated
//! derivatives of its forward dynamics.
//!
//! The arm starts at rest in a ready pose and must reach another pose, at rest, in one
//! second. The dynamics is discretised by semi-implicit Euler with h = 10 ms,
//!
//! ```text
//! q'_(t+1) = q'_t + h f(q_t, q'_t, u_t),   q_(t+1) = q_t + h q'_(t+1),
//! ```
//!
//! with f = q'' the forward dynamics (`forward_dynamics`). Its Jacobians
//! A = dx_(t+1)/dx_t and B = dx_(t+1)/du_t come from `forward_dynamics_derivatives`, which
//! returns dq''/dq, dq''/dq' and M^-1 = dq''/du in one allocation-free call (the inverse
//! dynamics' derivatives differentiated symbolically at build time, Carpentier & Mansard's
//! dq''/dx = -M^-1 dtau/dx). The cost is quadratic: 1/2 (x - x_goal)^T Q (x - x_goal) +
//! 1/2 u^T R u per step and a heavier terminal term. Each iteration runs the backward
//! Riccati pass (with Levenberg-Marquardt regularisation on Q_uu) and a forward rollout
//! with a backtracking line search, and prints the cost, which decreases at every
//! accepted iteration.
//!
//! Run with `cargo run --release --example panda_ilqr`.

use mechanism::nalgebra::{SMatrix, SVector};
use mechanism::prelude::*;

mechanism!(
    urdf = "mechanisms/urdf/panda.urdf",
    lock = ["panda_finger_joint1", "panda_finger_joint2"]
);

const N: usize = 7;
const X: usize = 2 * N;
/// Steps of the horizon (1 s at h = 10 ms).
const STEPS: usize = 100;
const H: f64 = 0.01;

type Q = SVector<f64, N>;
type State = SVector<f64, X>;
type A = SMatrix<f64, X, X>;
type B = SMatrix<f64, X, N>;

/// The ready pose and the goal (rad).
const START: [f64; N] = [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785];
const GOAL: [f64; N] = [0.6, -0.3, -0.4, -1.9, 0.3, 1.9, 0.2];

/// The quadratic cost's weights: per step on the state (position, rate) and the effort,
/// and at the end on the state.
const W_Q: f64 = 1.0;
const W_QD: f64 = 0.1;
const W_U: f64 = 1e-3;
const W_END_Q: f64 = 1e5;
const W_END_QD: f64 = 1e4;

fn split(x: &State) -> (Q, Q) {
    (x.fixed_rows::<N>(0).into(), x.fixed_rows::<N>(N).into())
}

fn join(q: &Q, qd: &Q) -> State {
    let mut x = State::zeros();
    x.fixed_rows_mut::<N>(0).copy_from(q);
    x.fixed_rows_mut::<N>(N).copy_from(qd);
    x
}

/// The state weights (diagonal) per step or at the end.
fn weights(end: bool) -> State {
    let (wq, wqd) = if end {
        (W_END_Q, W_END_QD)
    } else {
        (W_Q, W_QD)
    };
    State::from_fn(|i, _| if i < N { wq } else { wqd })
}

fn goal() -> State {
    join(&Q::from(GOAL), &Q::zeros())
}

/// One step of the discretised dynamics.
fn step(robot: &Panda, x: &State, u: &Q) -> State {
    let (q, qd) = split(x);
    let qdd = robot.forward_dynamics(0.0, &q, &qd, u).expect("M > 0");
    let qd = qd + qdd * H;
    join(&(q + qd * H), &qd)
}

/// A and B of one step at (x, u), from the forward dynamics' derivatives.
fn linearise(robot: &Panda, x: &State, u: &Q) -> (A, B) {
    let (q, qd) = split(x);
    let (f_q, f_qd, m_inv) = robot
        .forward_dynamics_derivatives(0.0, &q, &qd, u)
        .expect("M > 0");
    let eye = SMatrix::<f64, N, N>::identity();
    let mut a = A::zeros();
    // q'+ = q' + h f: rows N.. ; q+ = q + h q'+: rows ..N.
    a.fixed_view_mut::<N, N>(N, 0).copy_from(&(f_q * H));
    a.fixed_view_mut::<N, N>(N, N).copy_from(&(eye + f_qd * H));
    a.fixed_view_mut::<N, N>(0, 0)
        .copy_from(&(eye + f_q * (H * H)));
    a.fixed_view_mut::<N, N>(0, N)
        .copy_from(&(eye * H + f_qd * (H * H)));
    let mut b = B::zeros();
    b.fixed_view_mut::<N, N>(N, 0).copy_from(&(m_inv * H));
    b.fixed_view_mut::<N, N>(0, 0).copy_from(&(m_inv * (H * H)));
    (a, b)
}

/// The trajectory from `x0` under the efforts `us`, and its cost.
fn rollout(robot: &Panda, x0: &State, us: &[Q]) -> (Vec<State>, f64) {
    let mut xs = Vec::with_capacity(us.len() + 1);
    xs.push(*x0);
    let mut cost = 0.0;
    for u in us {
        let x = *xs.last().expect("x0");
        let e = x - goal();
        cost += 0.5 * e.component_mul(&weights(false)).dot(&e) + 0.5 * W_U * u.dot(u);
        xs.push(step(robot, &x, u));
    }
    let e = xs[us.len()] - goal();
    cost += 0.5 * e.component_mul(&weights(true)).dot(&e);
    (xs, cost)
}

/// The feedforward and feedback gains (k_t, K_t) of the backward pass, or `None` where
/// Q_uu is not positive definite at this regularisation `mu`.
fn backward(
    robot: &Panda,
    xs: &[State],
    us: &[Q],
    mu: f64,
) -> Option<Vec<(Q, SMatrix<f64, N, X>)>> {
    let end = weights(true);
    let mut v_x = (xs[STEPS] - goal()).component_mul(&end);
    let mut v_xx = A::from_diagonal(&end);
    let mut gains = vec![(Q::zeros(), SMatrix::<f64, N, X>::zeros()); STEPS];
    for t in (0..STEPS).rev() {
        let (a, b) = linearise(robot, &xs[t], &us[t]);
        let w = weights(false);
        let l_x = (xs[t] - goal()).component_mul(&w);
        let l_u = us[t] * W_U;
        let q_x = l_x + a.transpose() * v_x;
        let q_u = l_u + b.transpose() * v_x;
        let q_xx = A::from_diagonal(&w) + a.transpose() * v_xx * a;
        let q_ux = b.transpose() * v_xx * a;
        let q_uu = SMatrix::<f64, N, N>::identity() * (W_U + mu) + b.transpose() * v_xx * b;
        let chol = q_uu.cholesky()?;
        let k = -chol.solve(&q_u);
        let gain = -chol.solve(&q_ux);
        v_x = q_x + gain.transpose() * q_uu * k + gain.transpose() * q_u + q_ux.transpose() * k;
        v_xx = q_xx
            + gain.transpose() * q_uu * gain
            + gain.transpose() * q_ux
            + q_ux.transpose() * gain;
        v_xx = (v_xx + v_xx.transpose()) * 0.5;
        gains[t] = (k, gain);
    }
    Some(gains)
}

fn main() {
    let robot = Panda::default();
    let x0 = join(&Q::from(START), &Q::zeros());
    // Start from gravity compensation at the start pose: the arm holds still.
    let hold = robot.gravity(&Q::from(START));
    let mut us = vec![hold; STEPS];
    let (mut xs, mut cost) = rollout(&robot, &x0, &us);
    println!("iteration  0: cost {cost:12.4}");
    let mut mu = 1e-6;
    let started = std::time::Instant::now();
    for iteration in 1..=30 {
        let Some(gains) = backward(&robot, &xs, &us, mu) else {
            mu *= 10.0;
            continue;
        };
        // Forward pass with a backtracking line search on the feedforward step.
        let mut accepted = None;
        let mut alpha = 1.0;
        while alpha > 1e-4 {
            let mut x = x0;
            let mut trial = Vec::with_capacity(STEPS);
            for t in 0..STEPS {
                let (k, gain) = &gains[t];
                let u = us[t] + k * alpha + gain * (x - xs[t]);
                x = step(&robot, &x, &u);
                trial.push(u);
            }
            let (trial_xs, trial_cost) = rollout(&robot, &x0, &trial);
            if trial_cost < cost {
                accepted = Some((trial, trial_xs, trial_cost));
                break;
            }
            alpha *= 0.5;
        }
        match accepted {
            Some((u_new, x_new, c)) => {
                let decrease = cost - c;
                (us, xs, cost) = (u_new, x_new, c);
                mu = (mu * 0.3).max(1e-9);
                println!(
                    "iteration {iteration:2}: cost {cost:12.4}  (step {alpha}, decrease {decrease:.3e})"
                );
                if decrease < 1e-6 * cost {
                    break;
                }
            }
            None => mu *= 10.0,
        }
    }
    let (q_end, qd_end) = split(&xs[STEPS]);
    println!(
        "after {:.0} ms: |q(1 s) - q_goal| = {:.2e} rad, |q'(1 s)| = {:.2e} rad/s",
        started.elapsed().as_secs_f64() * 1e3,
        (q_end - Q::from(GOAL)).amax(),
        qd_end.amax()
    );
}
