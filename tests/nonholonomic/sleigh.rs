//! The Chaplygin sleigh (`mechanisms/chaplygin_sleigh.mech`): a `velocity_constraints`
//! row; energy conserved and the forward speed tending to its closed-form limit.

use mechanism::{InitialState, Kinematic, simulate};

use crate::common::{drifts, load, tight};

#[test]
fn sleigh_straightens_out_at_the_closed_form_speed() {
    let system = load("chaplygin_sleigh", &[]);
    let (m, inertia, a, u0, w0) = (1.0, 0.1, 0.2, 0.1_f64, 1.0_f64);
    let tr = simulate(&system, &tight(40.0, InitialState::Declared)).unwrap();
    let (energy, velocity) = drifts(&tr);
    let last = tr.sample(tr.len() - 1);
    let (theta, xd, yd, wd) = (last.q[2], last.qd[0], last.qd[1], last.qd[2]);
    let u = theta.cos() * xd + theta.sin() * yd;
    // u' = a w^2 and w' = -m a u w / (I + m a^2) conserve u^2 + (I + m a^2) w^2 / m, and w
    // decays like exp(-m a u t / (I + m a^2)) (e^-22 by t = 40 s).
    let limit = (u0 * u0 + (inertia + m * a * a) * w0 * w0 / m).sqrt();
    println!(
        "sleigh 40 s: u = {u:.12} (limit {limit:.12}), w = {wd:e}, energy drift {energy:e}, max |A q' + a| {velocity:e}"
    );
    assert!(system.info().velocity_rows == 1);
    assert!(wd.abs() < 1e-8, "still turning: w = {wd:e}");
    assert!((u - limit).abs() < 1e-9, "u = {u}, limit {limit}");
    assert!(energy < 1e-9, "relative energy drift {energy:e}");
    assert!(
        velocity < 1e-12,
        "velocity constraint residual {velocity:e}"
    );
}
