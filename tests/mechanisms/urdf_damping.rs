//! A URDF joint's `<dynamics damping>`, imported as the force -b q', damps the motion as a
//! viscous damper: a pendulum's small swing against the damped oscillator's closed form, and
//! the energy the damper takes out equal to its work.

use mechanism::{InitialState, IntegratorOptions, Interpreted, SimulationOptions, simulate};
use mechanism_codegen::{UrdfOptions, urdf_to_mech};

/// A hinge about y carrying 1 kg at 1 m below it (I_yy = 0.01 kg m^2 about its centre),
/// damped by b = 0.3 N m s/rad; the friction is not imported.
const PENDULUM: &str = r#"<robot name="damped">
  <link name="base"/>
  <link name="arm"><inertial><origin xyz="0 0 -1"/><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <joint name="hinge" type="continuous"><parent link="base"/><child link="arm"/>
    <axis xyz="0 1 0"/><dynamics damping="0.3" friction="0.05"/></joint>
</robot>"#;

/// I th'' + b th' + m g l sin(th) = 0 with I = m l^2 + I_yy = 1.01 kg m^2: released at rest
/// from th0 = 1e-3 rad, th(t) = th0 e^(-s t) (cos(w t) + s/w sin(w t)) with s = b / (2 I)
/// and w = sqrt(m g l / I - s^2). Over 4 s the sine's cubic term shifts the phase by about
/// th0^2/16 w t = 1e-6 of th0, and DOP853 at 1e-12 adds less: 1e-5 th0 bounds both. T + Pi
/// - W, with W the damper's work, holds to 1e-12 J (the swing's energy is 5e-6 J).
#[test]
fn an_imported_damping_decays_a_swing_as_the_closed_form() {
    let options = UrdfOptions {
        file_name: "damped.urdf".into(),
        damping: true,
        ..Default::default()
    };
    let text = urdf_to_mech(PENDULUM, &options).expect("imported");
    let system = Interpreted::from_source(&text).expect("derived");
    let th0 = 1e-3;
    let run = simulate(
        &system,
        &SimulationOptions {
            t_end: 4.0,
            output_rate: 50.0,
            integrator: IntegratorOptions::dop853(1e-12),
            initial: InitialState::Consistent {
                q: vec![th0],
                qd: vec![0.0],
            },
            ..Default::default()
        },
    )
    .expect("simulated");
    let (inertia, mgl, b): (f64, f64, f64) = (1.01, 9.81, 0.3);
    let s = b / (2.0 * inertia);
    let w = (mgl / inertia - s * s).sqrt();
    let exact = |t: f64| th0 * (-s * t).exp() * ((w * t).cos() + s / w * (w * t).sin());
    let first = run.samples().next().unwrap();
    let energy0 = first.kinetic + first.potential;
    let (mut worst, mut balance, mut work) = (0.0_f64, 0.0_f64, 0.0_f64);
    for sample in run.samples() {
        worst = worst.max((sample.q[0] - exact(sample.t)).abs());
        balance = balance.max((sample.kinetic + sample.potential - sample.work - energy0).abs());
        work = sample.work;
    }
    println!("|th - closed form| {worst:e} rad, T + Pi - W drift {balance:e} J, W {work:e} J");
    assert!(worst < 1e-5 * th0, "|th - closed form| = {worst:e} rad");
    assert!(balance < 1e-12, "T + Pi - W drifted by {balance:e} J");
    // The damper took out most of the swing's energy m g l (1 - cos th0) = 4.9e-6 J:
    // e^(-2 s t) = 0.30 of it is left after 4 s.
    assert!(work < -0.6 * mgl * (1.0 - th0.cos()), "W = {work:e} J");
}
