//! Loading the mechanisms of `mechanisms/` and their steady states.

use mechanism::{AssemblyOptions, Independent, Interpreted, KinematicState, System, assemble_from};

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
        assert!(system.set_parameter(k, *value));
    }
    system
}

/// The state assembled from the declared independent coordinates, with the rates
/// `rates` (coordinate name, rate) in place of the declared ones.
pub fn assemble_with(system: &dyn System, rates: &[(&str, f64)]) -> KinematicState {
    let info = system.info();
    let independent: Vec<Independent> = info
        .independent
        .iter()
        .map(|i| {
            let name = &info.coordinates[i.coordinate];
            let velocity = rates
                .iter()
                .find(|r| r.0 == name)
                .map_or(i.velocity, |r| r.1);
            Independent { velocity, ..*i }
        })
        .collect();
    assemble_from(
        system,
        0.0,
        &independent,
        &info.initial_guess,
        &AssemblyOptions::default(),
    )
    .expect("assembles")
}
