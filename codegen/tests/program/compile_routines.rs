//! The compile stage: on the five-bar leg (constraints, link frames, a drawing), every
//! role's routine, fed the parameter cache, gives the bits of the plain program of the same
//! outputs; the source table covers what each routine reads; and compiling twice gives the
//! same routines.

use mechanism_codegen::internals::frame_jacobian;
use mechanism_codegen::{
    Equations, Matrix, Model, Program, ResidualTangent, Role, Routines, Source, Tangents, Tape,
    compile, compile_interpreted, derive, full_tangent, parse_model_str, residual_tangent,
};

const FIVE_BAR: &str = include_str!("../../../mechanisms/five_bar.mech");

fn compiled() -> (Model, Equations, ResidualTangent, Routines) {
    let mut model = parse_model_str(FIVE_BAR).expect("the five-bar parses");
    let eqs = derive(&mut model).expect("derives");
    let tangent = full_tangent(&mut model, &eqs).expect("a tangent");
    let routines = compile(&mut model, &eqs, &tangent).expect("compiles");
    (model, eqs, tangent, routines)
}

/// The value of every symbol a routine may read, indexed by symbol id: a state off the
/// constraint manifold, the parameter defaults, and the cache computed from them.
fn inputs(model: &Model, routines: &Routines) -> Vec<f64> {
    let mut values = vec![0.0; model.arena.symbols().len()];
    for (symbol, source) in routines.sources().iter() {
        values[symbol.index()] = match source {
            Source::Coordinate(i) => 0.3 + 0.41 * i as f64,
            Source::Rate(i) => -0.7 + 0.23 * i as f64,
            Source::Acceleration(i) => 1.1 - 0.37 * i as f64,
            Source::Parameter(k) => model.parameters[k].default,
            Source::Time => 0.45,
            Source::Multiplier(k) => 2.0 - 0.5 * k as f64,
            Source::Effort(k) => 0.8 + 0.3 * k as f64,
            Source::Cache(_) => 0.0,
        };
    }
    let cache = routines.program(Role::ParameterCache).expect("a cache");
    let mut slots = vec![0.0; routines.cache_len()];
    Tape::new(cache)
        .eval(&values, &mut slots)
        .expect("the cache evaluates");
    for (symbol, source) in routines.sources().iter() {
        if let Source::Cache(k) = source {
            values[symbol.index()] = slots[k];
        }
    }
    values
}

fn run(program: &Program, inputs: &[f64]) -> Vec<u64> {
    let mut tape = Tape::new(program);
    let mut out = vec![0.0; tape.output_len()];
    tape.eval(inputs, &mut out).expect("evaluates");
    out.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn hoisted_routines_give_the_plain_programs_bits() {
    let (mut model, eqs, tangent, routines) = compiled();
    assert!(!eqs.frames.is_empty() && !model.drawing.points.is_empty());
    let values = inputs(&model, &routines);
    let column = |ids| Matrix::column(ids);
    let draw = column(
        model
            .drawing
            .points
            .iter()
            .flat_map(|p| p.position)
            .collect(),
    );
    let frame = &eqs.frames[1];
    let jacobian = {
        let n = eqs.n;
        frame_jacobian(&mut model.arena, &model.links, 1, n)
    };
    let dynamics = &tangent.dynamics;
    let rows = tangent.constraints.as_ref().expect("every tangent");
    let parameters = dynamics.parameters.as_ref().expect("dtau/dp");
    let cases: Vec<(Role, Vec<&Matrix>)> = vec![
        (Role::Mass, vec![&eqs.mass]),
        (Role::ConstraintJacobian, vec![&eqs.phi_q]),
        (Role::Gamma, vec![&eqs.gamma]),
        (Role::Tangent, vec![&tangent.stiffness, &tangent.damping]),
        (Role::InverseDynamics, vec![&eqs.inverse_dynamics]),
        (Role::Bias, vec![&eqs.bias]),
        (Role::MassAndBias, vec![&eqs.mass, &eqs.bias]),
        (
            Role::ConstraintTangent,
            vec![&rows.velocity, &rows.stiffness, &rows.damping],
        ),
        (
            Role::InverseDynamicsDerivatives,
            vec![&dynamics.position, &dynamics.velocity],
        ),
        (Role::ParameterDerivatives, vec![parameters]),
        (
            Role::FramePlacement(1),
            vec![&frame.rotation, &frame.position],
        ),
        (Role::FrameJacobian(1), vec![&jacobian]),
        (Role::Draw, vec![&draw]),
    ];
    for (role, outputs) in cases {
        let plain = Program::new(&model.arena, &outputs).expect("a program");
        let routine = routines.program(role).expect("compiled");
        assert_eq!(run(routine, &values), run(&plain, &values), "{role:?}");
    }
    let evaluation = eqs.evaluation_outputs();
    let plain = Program::new(&model.arena, &evaluation.iter().collect::<Vec<_>>()).unwrap();
    let routine = routines.program(Role::Evaluation).unwrap();
    assert_eq!(run(routine, &values), run(&plain, &values), "Evaluation");
}

#[test]
fn every_read_has_a_source_its_role_provides() {
    let (_, _, _, routines) = compiled();
    for (role, program) in routines.iter() {
        for (symbol, name) in program.symbols() {
            let source = routines.sources().get(*symbol);
            assert!(
                source.is_some_and(|s| role.provides(s)),
                "{role:?} reads {name} from {source:?}"
            );
        }
    }
    assert!(!Role::Mass.provides(Source::Multiplier(0)));
    assert!(!Role::ParameterCache.provides(Source::Cache(0)));
    assert!(Role::InverseDynamics.provides(Source::Acceleration(0)));
    assert!(Role::InverseDynamicsDerivatives.provides(Source::Acceleration(0)));
    assert!(!Role::InverseDynamicsDerivatives.provides(Source::Multiplier(0)));
    assert!(routines.get(Role::FrameJacobian(99)).is_none());
    assert!(routines.program(Role::FrameJacobian(99)).is_err());
}

#[test]
fn compiling_twice_gives_the_same_routines() {
    let (_, _, _, first) = compiled();
    let (_, _, _, second) = compiled();
    assert_eq!(first, second);
    assert_eq!(first.fingerprint(), second.fingerprint());
}

/// The interpreter's routines are the macro's cut down to the roles it runs, for every
/// library mechanism, without a tangent, with the residual's and with every derivative: the
/// same programs role by role, the same cache instructions for the slots they read, the
/// same sources.
#[test]
fn the_interpreted_routines_are_the_compiled_ones_cut_down() {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../mechanisms");
    let mut checked = 0;
    for entry in std::fs::read_dir(dir).expect("the library folder") {
        let path = entry.expect("an entry").path();
        if path.extension().is_none_or(|e| e != "mech") {
            continue;
        }
        let source = std::fs::read_to_string(&path).expect("readable");
        // `None`: the macro's routines; `Some(tangents)`: the interpreter's.
        let routines = |interpreted: Option<Tangents>| {
            let mut model = parse_model_str(&source).expect("parses");
            let eqs = derive(&mut model).expect("derives");
            let tangent = match interpreted {
                None | Some(Tangents::Derivatives) => full_tangent(&mut model, &eqs),
                _ => residual_tangent(&mut model, &eqs),
            };
            let tangent = tangent.expect("a tangent");
            let tangents = match interpreted {
                Some(Tangents::None) => Tangents::None,
                _ => Tangents::of(&tangent),
            };
            let roles = Role::interpreted(&model.drawing, tangents);
            let routines = match interpreted {
                Some(Tangents::None) => compile_interpreted(&mut model, &eqs, None),
                Some(_) => compile_interpreted(&mut model, &eqs, Some(&tangent)),
                None => compile(&mut model, &eqs, &tangent),
            };
            (routines.expect("compiles"), roles)
        };
        let (all, _) = routines(None);
        for tangents in [Tangents::None, Tangents::Residual, Tangents::Derivatives] {
            let (interpreted, roles) = routines(Some(tangents));
            let cut = all.restricted(&roles);
            assert_eq!(interpreted, cut, "{}", path.display());
            assert_eq!(interpreted.fingerprint(), cut.fingerprint());
            // The macro-only roles are really left out, and the cache is a proper prefix
            // only where they hoist values of their own.
            assert!(interpreted.get(Role::Mass).is_none());
            let with_tangent = tangents != Tangents::None;
            assert_eq!(interpreted.get(Role::Tangent).is_some(), with_tangent);
            let derivatives = tangents == Tangents::Derivatives;
            assert_eq!(
                interpreted.get(Role::InverseDynamicsDerivatives).is_some(),
                derivatives
            );
            assert!(interpreted.cache_len() <= all.cache_len());
        }
        checked += 1;
    }
    assert!(checked >= 16, "{checked} library mechanisms");
}
