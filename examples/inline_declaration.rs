//! Declaring a mechanism inline, in your own crate, with `mechanism!`.
//!
//! A double pendulum whose tip is held on the vertical line x = d by a slider (so it is a
//! closed loop: two angles, one constraint row, one degree of freedom). At build time the
//! macro derives M, C, g, Phi, Phi_q and gamma and emits allocation-free code for them.
//!
//! Run with `cargo run --example inline_declaration`.

use mechanism::prelude::*;

mechanism! {
    /// Double pendulum with its tip on the vertical guide x = d.
    ///
    /// Two uniform rods (lengths l1, l2 in m, masses m1, m2 in kg) hang from the origin;
    /// th1, th2 are absolute angles from the downward vertical, gravity g along -y.
    pub struct GuidedDoublePendulum;
    parameters {
        l1 = 0.5; l2 = 0.4;     // m
        m1 = 1.0; m2 = 0.8;     // kg
        d = 0.6; g = 9.81;      // m, m/s^2
    }
    coordinates { th1 = 0.9; th2 = 0.55; }
    independent { th1 = 0.9; der(th1) = 0.0; }
    kinetic = 1/2*(m1*l1^2/3)*der(th1)^2
        + 1/2*m2*((l1*cos(th1)*der(th1) + l2/2*cos(th2)*der(th2))^2
            + (l1*sin(th1)*der(th1) + l2/2*sin(th2)*der(th2))^2)
        + 1/2*(m2*l2^2/12)*der(th2)^2;
    potential = -g*(m1*l1/2*cos(th1) + m2*(l1*cos(th1) + l2/2*cos(th2)));
    constraints {
        l1*sin(th1) + l2*sin(th2) - d;
    }
}

fn main() {
    let pendulum = GuidedDoublePendulum::default();
    let q = SVector::<f64, 2>::from(GuidedDoublePendulum::INITIAL_GUESS);
    let qd = SVector::<f64, 2>::zeros();

    println!(
        "{} ({:?})",
        GuidedDoublePendulum::NAME,
        GuidedDoublePendulum::COORDINATES
    );
    println!("mass matrix at the guess:{}", pendulum.mass_matrix(&q));
    println!(
        "constraint residual at the guess: {:.3e}",
        pendulum.constraints(0.0, &q)[0]
    );
    let e = pendulum.evaluate(0.0, &q, &qd);
    println!("gravity g(q) = dPi/dq:{}", e.gravity);
    println!("constraint Jacobian Phi_q:{}", e.phi_q);
    println!(
        "\nDerived equations:\n{}",
        GuidedDoublePendulum::equations()
    );
}
