//! The rolling disc (`mechanisms/rolling_disc.mech`): steady rolling on a circle against its
//! closed form, energy conserved, the rolling constraints held.

use mechanism::{Dynamics, InitialState, Kinematic, simulate};

use crate::common::{drifts, load, tight};

const R: f64 = 0.1;
const G: f64 = 9.81;

/// (q, q') of steady rolling with the centre on a circle of radius rho at lean phi, the
/// yaw rate scaled by `factor` (1: the closed form g tan(phi) = W^2 (3/2 rho + r/4 sin(phi)),
/// derived from the angular momentum about the centre, H' = W e_z x H, and the contact
/// force that keeps the centre on its circle). The disc heads along -x: its centre's
/// velocity is W rho e_t with e_t = e_z x e_y.
fn circle(phi: f64, rho: f64, factor: f64) -> (Vec<f64>, Vec<f64>) {
    let w = factor * (G * phi.tan() / (1.5 * rho + 0.25 * R * phi.sin())).sqrt();
    let spin = -w * (rho / R + phi.sin());
    let q = vec![0.0, 0.0, R * phi.cos(), 0.0, phi, 0.0];
    let qd = vec![-w * rho, 0.0, 0.0, w, 0.0, spin];
    (q, qd)
}

#[test]
fn steady_circle_matches_the_closed_form() {
    let system = load("rolling_disc", &[]);
    let mut dynamics = Dynamics::new(system.info());
    for (phi, rho) in [(0.3, 0.5), (0.1, 2.0), (0.6, 0.2)] {
        let (q, qd) = circle(phi, rho, 1.0);
        // The closed-form rates satisfy our rolling rows (an independent check of the
        // contact point and of the material velocity there).
        dynamics.solve(&system, 0.0, &q, &qd).unwrap();
        let slip = dynamics.velocity_constraint_error(&qd);
        assert!(slip < 1e-14, "phi {phi}, rho {rho}: |A q' + a| = {slip:e}");
        // Steady: the lean, yaw rate and spin do not change.
        let qdd = dynamics.accelerations();
        for k in [3, 4, 5] {
            assert!(
                qdd[k].abs() < 1e-11,
                "phi {phi}, rho {rho}: q''[{k}] = {:e}",
                qdd[k]
            );
        }
        // A yaw rate 1 % off the closed form tips the disc: the test can fail.
        let (q, qd) = circle(phi, rho, 1.01);
        dynamics.solve(&system, 0.0, &q, &qd).unwrap();
        let lean = dynamics.accelerations()[4];
        assert!(
            lean.abs() > 1e-3,
            "phi {phi}, rho {rho}: lean'' {lean:e} off the closed form"
        );
    }
}

#[test]
fn wobbling_disc_conserves_energy_and_rolls() {
    let system = load("rolling_disc", &[]);
    let tr = simulate(&system, &tight(3.0, InitialState::Declared)).unwrap();
    let (energy, velocity) = drifts(&tr);
    println!("rolling disc 3 s: energy drift {energy:e} (relative), max |A q' + a| {velocity:e}");
    assert!(energy < 1e-9, "relative energy drift {energy:e}");
    assert!(
        velocity < 1e-12,
        "velocity constraint residual {velocity:e}"
    );
}
