//! The macro and the interpreter run one set of routines: for every library mechanism, the
//! fingerprint of the `Routines` that `mechanism!` emitted its methods from (`__ROUTINES`,
//! computed at build time) equals that of a second compilation here, whose every role has
//! a program and whose parameter cache reads parameters only; the `Routines` the
//! interpreter built its tapes from (at run time, from the same file) are those routines
//! cut down to the roles it runs (`Routines::restricted`, `Role::interpreted`).

use mechanism::Interpreted;
use mechanism::builtin::{
    Bricard, CartesianPendulum, ChaplyginSleigh, ClosedChain4, FiveBar, NFourBar40, Panda,
    PlanarFourBar, PlanarFourBarBodies, PlanarSliderCrank, RollingDisc, SpatialCrankSlider,
    SpatialCrankSliderRigid, SpatialFourBar, SpatialFourBarBodies, WhippleBicycle, builtin_names,
    builtin_source,
};
use mechanism_codegen::{Role, Source, Tangents, compile, derive, full_tangent, parse_model_str};

/// The fingerprint `mechanism!` emitted for each library mechanism, by file stem.
const EMITTED: [(&str, u64); 16] = [
    ("spatial_crank_slider", SpatialCrankSlider::__ROUTINES),
    ("planar_four_bar", PlanarFourBar::__ROUTINES),
    ("spatial_four_bar", SpatialFourBar::__ROUTINES),
    ("closed_chain", ClosedChain4::__ROUTINES),
    ("planar_slider_crank", PlanarSliderCrank::__ROUTINES),
    ("cartesian_pendulum", CartesianPendulum::__ROUTINES),
    ("spatial_four_bar_bodies", SpatialFourBarBodies::__ROUTINES),
    (
        "spatial_crank_slider_rigid",
        SpatialCrankSliderRigid::__ROUTINES,
    ),
    ("n_four_bar", NFourBar40::__ROUTINES),
    ("bricard", Bricard::__ROUTINES),
    ("planar_four_bar_bodies", PlanarFourBarBodies::__ROUTINES),
    ("panda", Panda::__ROUTINES),
    ("five_bar", FiveBar::__ROUTINES),
    ("whipple_bicycle", WhippleBicycle::__ROUTINES),
    ("rolling_disc", RollingDisc::__ROUTINES),
    ("chaplygin_sleigh", ChaplyginSleigh::__ROUTINES),
];

#[test]
fn macro_and_interpreter_come_from_one_routines() {
    let mut names: Vec<&str> = EMITTED.iter().map(|(name, _)| *name).collect();
    let mut library = builtin_names().to_vec();
    names.sort_unstable();
    library.sort_unstable();
    assert_eq!(names, library, "the table lists every library mechanism");
    let mut fingerprints: Vec<u64> = EMITTED.iter().map(|(_, f)| *f).collect();
    fingerprints.sort_unstable();
    fingerprints.dedup();
    assert_eq!(
        fingerprints.len(),
        EMITTED.len(),
        "one fingerprint per mechanism"
    );
    for (name, emitted) in EMITTED {
        let source = builtin_source(name).expect("registered");
        let mut model = parse_model_str(source).expect("parses");
        let eqs = derive(&mut model).expect("derives");
        let tangent = full_tangent(&mut model, &eqs).expect("every tangent");
        let routines = compile(&mut model, &eqs, &tangent).expect("compiles");
        assert_eq!(routines.fingerprint(), emitted, "{name}: compiled again");

        // The interpreter runs the first roles of the same routines (the constraint rows'
        // tangent among them for a mechanism with velocity rows).
        let with_rows = eqs.velocity_rows > 0;
        let tangents = if with_rows {
            Tangents::WithConstraints
        } else {
            Tangents::Residual
        };
        let interpreted = Interpreted::from_source(source).expect("a library file");
        assert_eq!(
            interpreted.routines_fingerprint(),
            routines
                .restricted(&Role::interpreted(&model.drawing, tangents))
                .fingerprint(),
            "{name}: the interpreter's tapes and the emitted methods come from different routines"
        );
        // With every derivative (`for_derivatives`), the roles of the macro's tangents.
        let derivatives =
            Interpreted::for_derivatives(parse_model_str(source).unwrap()).expect("a library file");
        assert_eq!(
            derivatives.routines_fingerprint(),
            routines
                .restricted(&Role::interpreted(&model.drawing, Tangents::Derivatives))
                .fingerprint(),
            "{name}: the interpreter's routines with the derivatives"
        );
        // Without the tangent (the command-line tool's explicit runs), a prefix of them.
        let mut again = parse_model_str(source).expect("parses");
        let eqs_again = derive(&mut again).expect("derives");
        let lean = Interpreted::from_equations_with(again, eqs_again, Tangents::None)
            .expect("a library file");
        assert_eq!(
            lean.routines_fingerprint(),
            routines
                .restricted(&Role::interpreted(&model.drawing, Tangents::None))
                .fingerprint(),
            "{name}: the interpreter's routines without the tangent"
        );

        let mut roles: Vec<Role> = Role::compiled(&eqs, &model.drawing, Tangents::Derivatives);
        roles.extend([Role::ParameterCache, Role::InitialValues]);
        let compiled: Vec<Role> = routines.iter().map(|(role, _)| role).collect();
        assert_eq!(compiled, roles, "{name}: one program per role, in order");
        let frames = eqs.frames.len();
        assert!(routines.get(Role::FramePlacement(frames)).is_none());
        let cache = routines.program(Role::ParameterCache).expect("a cache");
        assert_eq!(cache.outputs()[0].rows, routines.cache_len(), "{name}");
        for (symbol, _) in cache.symbols() {
            let source = routines.sources().get(*symbol);
            assert!(
                matches!(source, Some(Source::Parameter(_))),
                "{name}: the cache reads {source:?}"
            );
        }
    }
}
