//! A body declaration written inline in `mechanism!` (the token-stream route of the same
//! grammar): a mass on a spring, whose emitted M, g and equations text are the closed forms.

use mechanism::Mechanism;
use nalgebra::SVector;

mechanism::mechanism! {
    /// A mass on a spring, hanging from the origin.
    pub struct InlineSpringMass;
    parameters { m = 2.0; k = 50.0; L0 = 0.5; g = 9.81; }
    coordinates { z = -0.9; }
    independent { z = -0.9; der(z) = 0.0; }
    gravity = [0, 0, -g];
    point O = [0, 0, 0];
    body bob { mass = m; position = [0, 0, z]; }
    spring s { between = O, bob; stiffness = k; free_length = L0; }
}

/// M = [m]; g(z) = dPi/dz = m g + k z (|z| - L0)/|z| (z < 0 here: m g - k (-z - L0)), which
/// vanishes at the static deflection z = -(L0 + m g / k). To 1e-12 (a handful of roundings).
#[test]
fn inline_spring_mass_has_the_closed_form_terms() {
    let s = InlineSpringMass::default();
    let z_eq = -(s.L0 + s.m * s.g / s.k);
    let q = SVector::<f64, 1>::new(z_eq);
    assert_eq!(s.mass_matrix(&q)[(0, 0)], s.m);
    assert!(
        s.gravity(&q)[0].abs() < 1e-12,
        "g(z_eq) = {}",
        s.gravity(&q)[0]
    );
    let z = -1.1;
    let g = s.gravity(&SVector::<f64, 1>::new(z))[0];
    let expected = s.m * s.g - s.k * (-z - s.L0);
    assert!((g - expected).abs() < 1e-12, "g = {g}, expected {expected}");
    assert!(InlineSpringMass::equations().contains("M[1] = m"));
}
