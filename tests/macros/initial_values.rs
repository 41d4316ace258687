//! The declared initial values follow the parameters (issue 53, item 1): a guess or an
//! independent value written with parameters (`x = l/2; der(x) = w;`) is evaluated at the
//! parameters as they are now, whether they were changed through a field, `set_parameter`,
//! `Compiled` or the interpreter route, and both routes give the same bits. Before, the
//! emitted constants, evaluated once at the defaults, were all there was.
//!
//! The truth: with y = 2 x, x(0) = l/2 and x'(0) = w, the assembled state is
//! (x, y) = (l/2, l) and (x', y') = (w, 2 w).

use mechanism::{
    AssemblyOptions, Compiled, Independent, Interpreted, Mechanism, ParameterError, ParameterRange,
    System, assemble,
};

mechanism::mechanism!(file = "tests/macros/follows.mech");

const SOURCE: &str = include_str!("follows.mech");

/// The independent coordinate of the declaration at position `x` and rate `rate`.
fn x_at(x: f64, rate: f64) -> Independent {
    Independent {
        coordinate: 0,
        position: x,
        velocity: rate,
    }
}

#[test]
fn at_the_defaults_the_methods_give_the_constants() {
    let s = FollowingSlider::default();
    assert_eq!(s.initial_guess(), FollowingSlider::INITIAL_GUESS);
    assert_eq!(FollowingSlider::INITIAL_GUESS, [1.0, 2.0]);
    assert_eq!(s.independent(0), Some(FollowingSlider::INDEPENDENT[0]));
    assert_eq!(s.independent(0), Some(x_at(1.0, 1.0)));
    assert_eq!(s.independent(1), None);
}

#[test]
#[allow(clippy::field_reassign_with_default)] // the change through a field is the point
fn a_field_changed_without_refresh_is_followed() {
    let mut s = FollowingSlider::default();
    s.l = 5.0;
    s.w = -3.0;
    assert!(!s.is_cached());
    assert_eq!(s.initial_guess(), [2.5, 5.0]);
    assert_eq!(s.independent(0), Some(x_at(2.5, -3.0)));
    // The constants keep the defaults' values, as documented.
    assert_eq!(FollowingSlider::INITIAL_GUESS, [1.0, 2.0]);
}

#[test]
fn set_parameter_is_followed_and_a_value_out_of_range_refused() {
    let mut s = FollowingSlider::default();
    assert_eq!(s.set_parameter(1, 4.0), Ok(()));
    assert_eq!(s.independent(0), Some(x_at(1.0, 4.0)));
    // l is declared `positive`, m `nonnegative`: refused with the reason, value kept.
    assert_eq!(
        s.set_parameter(0, -0.5),
        Err(ParameterError::OutOfRange {
            index: 0,
            value: -0.5,
            range: ParameterRange::Positive,
        })
    );
    assert!(s.set_parameter(0, 0.0).is_err());
    assert!(s.set_parameter(0, f64::NAN).is_err());
    assert_eq!(s.l, 2.0);
    assert_eq!(s.set_parameter(2, 0.0), Ok(()));
    assert!(s.set_parameter(2, -1e-300).is_err());
    assert_eq!(
        s.set_parameter(3, 1.0),
        Err(ParameterError::NoSuchParameter { index: 3, count: 3 })
    );
    let shown = s.set_parameter(0, -0.5).unwrap_err().to_string();
    assert_eq!(
        shown,
        "parameter 0 must be greater than 0 (declared `positive`), got -0.5"
    );
    assert_eq!(
        <FollowingSlider as Mechanism<2, 1>>::PARAMETER_RANGES,
        [
            ParameterRange::Positive,
            ParameterRange::Any,
            ParameterRange::NonNegative
        ]
    );
}

/// Both routes, through `System`: `info()` follows `set_parameter`, with the same bits,
/// and the state assembled from it is the closed form.
#[test]
fn both_routes_follow_set_parameter_in_info_and_assembly() {
    let mut compiled = Compiled::new(FollowingSlider::default());
    let mut interpreted = Interpreted::from_source(SOURCE).expect("declaration");
    let systems: [&mut dyn System; 2] = [&mut compiled, &mut interpreted];
    let mut infos = Vec::new();
    for system in systems {
        assert_eq!(system.info().initial_guess, [1.0, 2.0]);
        assert!(system.set_parameter(0, 3.0).is_ok());
        assert!(system.set_parameter(1, 2.0).is_ok());
        assert!(system.set_parameter(0, -1.0).is_err());
        let info = system.info();
        assert_eq!(info.initial_guess, [1.5, 3.0]);
        assert_eq!(info.independent, [x_at(1.5, 2.0)]);
        assert_eq!(info.parameter_range(0), ParameterRange::Positive);
        let state = assemble(&*system, 0.0, &AssemblyOptions::default()).expect("assembles");
        // The constraint y = 2 x is linear: Newton lands on the closed form to round-off
        // of one step (a few ulp of 3).
        assert!((state.q[1] - 3.0).abs() < 1e-14, "{:?}", state.q);
        assert_eq!(state.qd[0], 2.0);
        assert!((state.qd[1] - 4.0).abs() < 1e-14, "{:?}", state.qd);
        infos.push(info.clone());
    }
    assert_eq!(infos[0].initial_guess, infos[1].initial_guess);
    assert_eq!(infos[0].independent, infos[1].independent);
}

/// `initial_guess()` and `independent(k)` at the defaults equal the constants, bit for bit:
/// the program and the build-time evaluation compute the same expressions.
fn defaults_agree<T: Mechanism<N, M> + Default, const N: usize, const M: usize>(name: &str) {
    let m = T::default();
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&m.initial_guess()), bits(&T::INITIAL_GUESS), "{name}");
    for (k, declared) in T::INDEPENDENT.iter().enumerate() {
        let now = m.independent(k).expect("an entry");
        assert_eq!(now.coordinate, declared.coordinate, "{name}");
        assert_eq!(
            now.position.to_bits(),
            declared.position.to_bits(),
            "{name}"
        );
        assert_eq!(
            now.velocity.to_bits(),
            declared.velocity.to_bits(),
            "{name}"
        );
    }
    assert_eq!(m.independent(T::INDEPENDENT.len()), None, "{name}");
}

#[test]
fn every_library_mechanism_gives_its_constants_at_the_defaults() {
    use mechanism::builtin::*;
    defaults_agree::<SpatialCrankSlider, _, _>("SpatialCrankSlider");
    defaults_agree::<PlanarFourBar, _, _>("PlanarFourBar");
    defaults_agree::<SpatialFourBar, _, _>("SpatialFourBar");
    defaults_agree::<ClosedChain4, _, _>("ClosedChain4");
    defaults_agree::<PlanarSliderCrank, _, _>("PlanarSliderCrank");
    defaults_agree::<CartesianPendulum, _, _>("CartesianPendulum");
    defaults_agree::<SpatialFourBarBodies, _, _>("SpatialFourBarBodies");
    defaults_agree::<SpatialCrankSliderRigid, _, _>("SpatialCrankSliderRigid");
    defaults_agree::<NFourBar40, _, _>("NFourBar40");
    defaults_agree::<Bricard, _, _>("Bricard");
    defaults_agree::<PlanarFourBarBodies, _, _>("PlanarFourBarBodies");
    defaults_agree::<Panda, _, _>("Panda");
    defaults_agree::<FiveBar, _, _>("FiveBar");
    defaults_agree::<WhippleBicycle, _, _>("WhippleBicycle");
    defaults_agree::<RollingDisc, _, _>("RollingDisc");
    defaults_agree::<ChaplyginSleigh, _, _>("ChaplyginSleigh");
}
