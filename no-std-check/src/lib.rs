//! A `#![no_std]` library that declares the seed's spatial crank-slider with `mechanism!`
//! and advances it with the fixed-size solvers. CI builds it for `thumbv7em-none-eabihf`,
//! a target without std, so a dependency or a generated path that needs std fails there.
#![no_std]

use mechanism::fixed::{FixedError, FixedStep, KktSolution, State, kkt_solve};
use mechanism::{Coordinates, Mechanism, Velocities, mechanism};

mechanism!(file = "mechanisms/spatial_crank_slider.mech");

/// The crank-slider assembled near its declared guess, the crank turning at about `rate`
/// rad/s (guess and rate projected onto the constraints).
pub fn start(rate: f64) -> Result<State<4>, FixedError> {
    let mut qd = Velocities::<4>::zeros();
    qd[SpatialCrankSlider::INDEPENDENT[0].coordinate] = rate;
    let q = Coordinates::from(SpatialCrankSlider::INITIAL_GUESS);
    let mut state = State { t: 0.0, q, qd };
    FixedStep::new(1e-3).project(&SpatialCrankSlider::default(), &mut state)?;
    Ok(state)
}

/// Advances the crank-slider by `steps` fixed steps of `h` seconds (RK4 + projection).
pub fn run(state: &mut State<4>, h: f64, steps: usize) -> Result<(), FixedError> {
    let (model, stepper) = (SpatialCrankSlider::default(), FixedStep::new(h));
    for _ in 0..steps {
        stepper.step(&model, state)?;
    }
    Ok(())
}

/// q'' and lambda at (t, q, q'): the KKT solve alone, for a controller's model.
pub fn accelerations(t: f64, state: &State<4>) -> Result<KktSolution<4, 3>, FixedError> {
    let e = SpatialCrankSlider::default().evaluate(t, &state.q, &state.qd);
    kkt_solve(&e, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_book_shows_this_file() {
        let this = include_str!("lib.rs");
        let code = &this[..this.find("#[cfg(test)]").unwrap()];
        assert!(include_str!("../../docs/src/embedding.md").contains(code.trim_end()));
    }

    #[test]
    fn a_second_of_steps_keeps_the_constraints_and_the_energy_balance() {
        let model = SpatialCrankSlider::default();
        let energy =
            |s: &State<4>| model.kinetic_energy(&s.q, &s.qd) + model.potential_energy(&s.q);
        let power = |s: &State<4>| model.generalized_forces(s.t, &s.q, &s.qd).dot(&s.qd);
        let mut state = start(2.0 * core::f64::consts::PI).unwrap();
        let (e0, mut work) = (energy(&state), 0.0);
        for _ in 0..1000 {
            let p0 = power(&state);
            run(&mut state, 1e-3, 1).unwrap();
            work += 0.5 * (p0 + power(&state)) * 1e-3;
            assert!(model.constraints(state.t, &state.q).amax() <= 1e-12);
        }
        // Work of tau = change of T + Pi (the constraints are scleronomic and do no work).
        // The trapezoidal work has an O(h^2) error (h^2/12 |P''| per unit time, below 1e-7 J
        // here) and RK4's drift is far below; measured 1.1e-8 J against T + Pi = 0.76 J.
        let balance = energy(&state) - e0 - work;
        assert!(balance.abs() < 1e-6, "energy balance off by {balance:e} J");
        let a = accelerations(state.t, &state).unwrap();
        let e = model.evaluate(state.t, &state.q, &state.qd);
        assert!((e.phi_q * a.qdd - e.gamma).amax() < 1e-9);
    }
}

pub mod arm;
pub mod constrained;
pub mod legged;
