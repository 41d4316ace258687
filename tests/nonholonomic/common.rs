//! Loading the mechanisms of `mechanisms/`, their states, and the checks of a run.

use mechanism::{
    AssemblyOptions, Independent, InitialState, IntegratorOptions, Interpreted, Kinematic,
    KinematicState, Method, SimulationOptions, System, Trajectory, assemble_from,
};

/// The text of `mechanisms/{name}.mech`.
pub fn source(name: &str) -> String {
    let path = format!("{}/mechanisms/{name}.mech", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// `name` built for linearisation, with the parameters `set` (name, value).
pub fn load(name: &str, set: &[(&str, f64)]) -> Interpreted {
    let model = mechanism_codegen::parse_model_str(&source(name)).expect("parses");
    let mut system = Interpreted::for_linearization(model).expect("derives");
    for (p, value) in set {
        let k = system.info().parameter_index(p).expect("a parameter");
        assert!(system.set_parameter(k, *value).is_ok());
    }
    system
}

/// The state assembled from the declared independent coordinates, with the rates
/// `rates` (coordinate name, rate) in place of the declared ones.
pub fn assemble_with(system: &dyn System, rates: &[(&str, f64)]) -> KinematicState {
    let independent = independent_with(system, rates);
    let guess = &system.info().initial_guess;
    assemble_from(
        system,
        0.0,
        &independent,
        guess,
        &AssemblyOptions::default(),
    )
    .expect("assembles")
}

/// The forward-dynamics options of these tests: DOP853 at rtol = atol = 1e-12 with the
/// default projection, `t_end` seconds, 100 samples a second.
pub fn tight(t_end: f64, initial: InitialState) -> SimulationOptions {
    SimulationOptions {
        t_end,
        initial,
        integrator: IntegratorOptions {
            method: Method::Dop853,
            rtol: 1e-12,
            atol: 1e-12,
            ..Default::default()
        },
        ..Default::default()
    }
}

/// The largest |T + Pi - E0| over the run, relative to the largest |T| + |Pi|, and the
/// largest velocity-constraint residual |Phi_q q' + Phi_t|_inf.
pub fn drifts(tr: &Trajectory) -> (f64, f64) {
    let s0 = tr.sample(0);
    let e0 = s0.kinetic + s0.potential;
    let scale = tr
        .samples()
        .map(|s| s.kinetic.abs() + s.potential.abs())
        .fold(0.0, f64::max);
    let energy = tr
        .samples()
        .map(|s| (s.kinetic + s.potential - e0).abs())
        .fold(0.0, f64::max);
    let velocity = tr
        .samples()
        .map(|s| s.velocity_constraint_error)
        .fold(0.0, f64::max);
    (energy / scale, velocity)
}

/// The declared independent coordinates with the rates `rates` (name, rate) replaced.
pub fn independent_with(system: &dyn System, rates: &[(&str, f64)]) -> Vec<Independent> {
    let info = system.info();
    info.independent
        .iter()
        .map(|i| {
            let name = &info.coordinates[i.coordinate];
            let velocity = rates
                .iter()
                .find(|r| r.0 == name)
                .map_or(i.velocity, |r| r.1);
            Independent { velocity, ..*i }
        })
        .collect()
}
