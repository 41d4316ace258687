//! The cache of parameter-only values is never read stale: after a change through a field
//! (`DerefMut`), through `set_parameter`, after `refresh` and inside `Compiled`, every method
//! gives the bits of a mechanism built with those parameters from scratch.

use mechanism::builtin::{SpatialCrankSlider, SpatialCrankSliderParameters};
use mechanism::nalgebra::SVector;
use mechanism::{Compiled, Evaluation, Mechanism, StaticEvaluation, System};

/// Every output of `a` and `b` at one state, as bits.
fn same_bits(a: &SpatialCrankSlider, b: &SpatialCrankSlider) {
    let q = SVector::<f64, 4>::new(0.4, 0.5, 0.8, 0.21);
    let qd = SVector::<f64, 4>::new(6.0, 2.0, -0.5, -0.3);
    let t = 0.7;
    let bits = |e: &StaticEvaluation<4, 3>| -> Vec<u64> {
        let mut v: Vec<f64> = Vec::new();
        v.extend(e.mass.iter());
        v.extend(e.coriolis.iter());
        v.extend(e.gravity.iter());
        v.extend(e.forces.iter());
        v.extend(e.phi.iter());
        v.extend(e.phi_q.iter());
        v.extend(e.phi_t.iter());
        v.extend(e.gamma.iter());
        v.extend([e.kinetic, e.potential]);
        v.iter().map(|x| x.to_bits()).collect()
    };
    assert_eq!(bits(&a.evaluate(t, &q, &qd)), bits(&b.evaluate(t, &q, &qd)));
    let mut out = StaticEvaluation::zeros();
    a.evaluate_into(t, &q, &qd, &mut out);
    assert_eq!(bits(&out), bits(&b.evaluate(t, &q, &qd)));
    assert_eq!(a.mass_matrix(&q), b.mass_matrix(&q));
    assert_eq!(a.gravity(&q), b.gravity(&q));
    assert_eq!(a.constraints(t, &q), b.constraints(t, &q));
    assert_eq!(a.constraint_jacobian(t, &q), b.constraint_jacobian(t, &q));
    assert_eq!(
        a.constraint_gamma(t, &q, &qd),
        b.constraint_gamma(t, &q, &qd)
    );
    assert_eq!(
        a.generalized_forces(t, &q, &qd),
        b.generalized_forces(t, &q, &qd)
    );
    assert_eq!(a.potential_energy(&q), b.potential_energy(&q));
    assert_eq!(a.kinetic_energy(&q, &qd), b.kinetic_energy(&q, &qd));
}

/// The seed with the crank plane tilted (alpha, whose sine and cosine are cached) and a
/// longer rod, built from scratch.
fn changed() -> SpatialCrankSlider {
    SpatialCrankSlider::new(SpatialCrankSliderParameters {
        alpha: 0.3,
        l2: 0.35,
        ..Default::default()
    })
}

#[test]
fn a_field_change_is_never_read_stale() {
    let mut m = SpatialCrankSlider::default();
    assert!(m.is_cached());
    m.alpha = 0.3;
    m.l2 = 0.35;
    assert!(!m.is_cached());
    same_bits(&m, &changed());
    m.refresh();
    assert!(m.is_cached());
    same_bits(&m, &changed());
    assert_eq!(m, changed());
}

#[test]
fn set_parameter_and_compiled_refresh_the_cache() {
    let mut m = SpatialCrankSlider::default();
    let alpha = SpatialCrankSlider::PARAMETERS
        .iter()
        .position(|p| *p == "alpha");
    let l2 = SpatialCrankSlider::PARAMETERS
        .iter()
        .position(|p| *p == "l2");
    assert!(m.set_parameter(alpha.unwrap(), 0.3).is_ok());
    assert!(m.set_parameter(l2.unwrap(), 0.35).is_ok());
    assert!(m.is_cached());
    same_bits(&m, &changed());

    // A stale mechanism handed to Compiled, and a parameter set through System.
    let mut stale = SpatialCrankSlider::default();
    stale.alpha = 0.3;
    let mut system = Compiled::new(stale);
    assert!(system.mechanism().is_cached());
    assert!(system.set_parameter(l2.unwrap(), 0.35).is_ok());
    let (q, qd) = ([0.4, 0.5, 0.8, 0.21], [6.0, 2.0, -0.5, -0.3]);
    let mut got = Evaluation::zeros(4, 3);
    let mut want = Evaluation::zeros(4, 3);
    system.evaluate(0.7, &q, &qd, &mut got);
    Compiled::new(changed()).evaluate(0.7, &q, &qd, &mut want);
    assert_eq!(got, want);
}
