//! Shared inputs of the parser and printer tests.

/// The seed paper's spatial crank-slider as a declaration, verbatim (the part inside `mechanism! { ... }`).
pub const SEED: &str = r#"
    /// Spatial crank-slider of the seed paper (Section II), with ERRATA decisions.
    pub struct SpatialCrankSlider;
    parameters {
        h = 0.12; l1 = 0.08; l2 = 0.3; d = 0.1; alpha = 0.0;    // m, rad
        m1 = 0.12; m2 = 0.5; m3 = 2.0; J1 = 1e-4; a1 = 0.04;    // kg, kg m^2, m
        g = 9.81; tau0 = 0.005; Omega = 2*pi;
    }
    coordinates { phi = 0.0; beta = 0.46; gamma = 0.84; x_c = 0.2; }   // initial guesses
    independent { phi = 0.0; der(phi) = 2*pi; }                         // what the user sets
    kinetic = 1/2*(J1 + m2/2*l1^2)*der(phi)^2 + 1/2*(m2/2 + m3)*der(x_c)^2;
    potential = m1*g*(a1*cos(phi) + h) + m2/2*g*(l1*cos(phi) + h);
    constraints {
        l1*sin(phi)*sin(alpha) + l2*sin(gamma)*cos(beta) - x_c;
        -l1*sin(phi)*cos(alpha) + l2*sin(gamma)*sin(beta) - d;
        h + l1*cos(phi) - l2*cos(gamma);
    }
    forces { phi: tau0*sin(Omega*t); }
"#;
