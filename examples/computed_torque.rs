//! A control loop around a generated solver: computed-torque feedforward from inverse
//! dynamics plus PD feedback, on a crank-rocker four-bar whose crank torque is a parameter.
//!
//! 1. Offline, `inverse_dynamics` (the run-time library) gives the crank torque tau_ff(t)
//!    that makes the crank follow th1_d(t) = pi/2 + 2 pi t + 0.3 sin(2 pi t) exactly.
//! 2. Online, every h = 1 ms the controller sets the parameter `u` (the declared crank
//!    torque) to tau_ff(t + h/2) + Kp (th1_d - th1) + Kd (th1_d' - th1') and advances the
//!    generated equations by one `FixedStep` (RK4 with projection; allocation-free, no std
//!    needed). The start is 0.05 rad behind the reference.
//!
//! Run with `cargo run --release --example computed_torque`.

use mechanism::prelude::*;

// The crank-rocker of `mechanisms/planar_four_bar.mech` with a crank torque parameter u:
// `forces { th1: u; }`. The runtime test of the fixed step uses the same file.
mechanism!(file = "examples/driven_four_bar.mech");

/// The reference crank angle and rate at t.
fn reference(t: f64) -> (f64, f64) {
    let w = 2.0 * std::f64::consts::PI;
    (
        std::f64::consts::FRAC_PI_2 + w * t + 0.3 * (w * t).sin(),
        w + 0.3 * w * (w * t).cos(),
    )
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (h, t_end) = (1e-3, 2.0);
    let steps = (t_end / h) as usize;
    let mut model = DrivenFourBar::default();

    // Offline: the feedforward torque at the middle of every control period.
    let system = Compiled::new(model.clone());
    let drive = parse_drive(&system, "th1 = pi/2 + 2*pi*t + 0.3*sin(2*pi*t)")?;
    let mid: Vec<f64> = (0..steps).map(|k| (k as f64 + 0.5) * h).collect();
    let start = inverse_dynamics(
        &system,
        vec![drive.clone()],
        &[0.0],
        &AssemblyOptions::default(),
    )?;
    let feedforward = inverse_dynamics(&system, vec![drive], &mid, &AssemblyOptions::default())?;

    // Online: start 0.05 rad behind, on the constraints.
    let s0 = &start.samples[0];
    let mut state = State {
        t: 0.0,
        q: Coordinates::from_column_slice(&s0.q),
        qd: Coordinates::from_column_slice(&s0.qd),
    };
    state.q[0] -= 0.05;
    let stepper = FixedStep::new(h);
    stepper.project(&model, &mut state)?;

    let (kp, kd) = (40.0, 1.8); // N m/rad, N m s/rad: about critically damped
    println!("    t (s)   th1 - th1_d (rad)   u (N m)");
    for (k, sample) in feedforward.samples.iter().enumerate() {
        let (angle, rate) = reference(state.t);
        let error = angle - state.q[0];
        model.u = sample.driving[0] + kp * error + kd * (rate - state.qd[0]);
        if k % 200 == 0 {
            println!("{:9.3} {:19.3e} {:9.4}", state.t, -error, model.u);
        }
        stepper.step(&model, &mut state)?;
    }
    let (angle, _) = reference(state.t);
    println!(
        "{:9.3} {:19.3e}   (feedback has removed the initial offset)",
        state.t,
        state.q[0] - angle
    );
    Ok(())
}
