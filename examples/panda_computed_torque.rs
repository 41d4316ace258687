//! A 1 kHz computed-torque loop on the Franka Panda, declared straight from its URDF.
//!
//! Every millisecond the controller reads (q, q') and commands
//! u = tau_id(q, q', q_d'' + Kd (q_d' - q') + Kp (q_d - q)), the generated inverse dynamics
//! (Newton-Euler, allocation-free). The plant is the same generated model, advanced by RK4
//! on `forward_dynamics` (M q'' = u - b by a static Cholesky) with the command held over
//! the period. The reference swings every joint by 0.3 rad at 0.5 Hz around a ready pose;
//! the start is 0.05 rad off on every joint.
//!
//! Run with `cargo run --release --example panda_computed_torque`.

use mechanism::nalgebra::SVector;
use mechanism::prelude::*;

mechanism!(
    urdf = "mechanisms/urdf/panda.urdf",
    lock = ["panda_finger_joint1", "panda_finger_joint2"]
);

type V = SVector<f64, 7>;

/// The ready pose (rad).
const READY: [f64; 7] = [0.0, -0.785, 0.0, -2.356, 0.0, 1.571, 0.785];

/// q_d, q_d', q_d'' at t.
fn reference(t: f64) -> (V, V, V) {
    let w = std::f64::consts::PI; // 0.5 Hz
    let (s, c) = (w * t).sin_cos();
    let q = V::from_fn(|i, _| READY[i] + 0.3 * s);
    (q, V::repeat(0.3 * w * c), V::repeat(-0.3 * w * w * s))
}

fn main() {
    let robot = Panda::default();
    let (h, t_end) = (1e-3, 4.0);
    let (kp, kd) = (400.0, 40.0); // rad/s^2 per rad and per rad/s: critically damped at 20 rad/s
    let (mut q, mut qd) = (reference(0.0).0 + V::repeat(0.05), V::zeros());
    let accel = |q: &V, qd: &V, u: &V| robot.forward_dynamics(0.0, q, qd, u).expect("M > 0");
    let mut worst = 0.0_f64;
    let steps = (t_end / h) as usize;
    for k in 0..steps {
        let t = k as f64 * h;
        let (q_d, qd_d, qdd_d) = reference(t);
        let command = qdd_d + (qd_d - qd) * kd + (q_d - q) * kp;
        let u = robot.inverse_dynamics(t, &q, &qd, &command);
        // The plant: one RK4 step of the same dynamics with u held.
        let k1 = (qd, accel(&q, &qd, &u));
        let k2 = (
            qd + k1.1 * (h / 2.0),
            accel(&(q + k1.0 * (h / 2.0)), &(qd + k1.1 * (h / 2.0)), &u),
        );
        let k3 = (
            qd + k2.1 * (h / 2.0),
            accel(&(q + k2.0 * (h / 2.0)), &(qd + k2.1 * (h / 2.0)), &u),
        );
        let k4 = (qd + k3.1 * h, accel(&(q + k3.0 * h), &(qd + k3.1 * h), &u));
        q += (k1.0 + k2.0 * 2.0 + k3.0 * 2.0 + k4.0) * (h / 6.0);
        qd += (k1.1 + k2.1 * 2.0 + k3.1 * 2.0 + k4.1) * (h / 6.0);
        if t >= 1.0 {
            worst = worst.max((reference(t + h).0 - q).amax());
        }
        if (k + 1) % 1000 == 0 {
            let hand = Panda::frame_index("panda_hand_tcp").unwrap();
            let (_, p) = robot.frame_placement(hand, &q).unwrap();
            println!(
                "t = {:.1} s  |q_d - q| = {:.2e} rad  tcp = ({:.3}, {:.3}, {:.3}) m  u1 = {:+.2} N m",
                t + h,
                (reference(t + h).0 - q).amax(),
                p[0],
                p[1],
                p[2],
                u[0]
            );
        }
    }
    println!("largest tracking error after 1 s: {worst:.2e} rad");
}
