//! The macro's pass cases (they were trybuild's `tests/ui/pass`; here they share the test
//! build's dependencies, and trybuild, left with compile-fail cases only, runs `cargo check`
//! instead of a full build). Each module is what a user's crate writes; its test is the
//! case's `main`.

/// An inline declaration: the struct, its defaults, the constants and every method.
mod inline_pendulum {
    use mechanism::prelude::*;

    mechanism! {
        /// A point mass on a rod, in Cartesian coordinates.
        pub struct Pendulum;
        parameters { m = 2.0; l = 1.5; g = 9.81; }
        coordinates { x = 0.5; y = -1.4; }
        independent { x = 0.5; der(x) = 0.0; }
        kinetic = 1/2*m*(der(x)^2 + der(y)^2);
        potential = m*g*y;
        constraints { x^2 + y^2 - l^2; }
        forces { x: -0.1*der(x); }
    }

    #[test]
    fn inline_pendulum() {
        let mut p = Pendulum::default();
        assert_eq!(
            *p.parameters(),
            PendulumParameters {
                m: 2.0,
                l: 1.5,
                g: 9.81
            }
        );
        assert_eq!(
            p,
            Pendulum::from(PendulumParameters {
                m: 2.0,
                l: 1.5,
                g: 9.81
            })
        );
        assert!(p.is_cached());
        // Through the fields: the cache is stale (the methods compute the values themselves)
        // until `refresh`, and the new value is what the methods use either way.
        p.l = 1.0;
        assert!(!p.is_cached());
        assert_eq!(p.l, 1.0);
        assert_eq!(
            p.constraints(0.0, &SVector::<f64, 2>::new(1.0, 0.0))[0],
            0.0
        );
        p.refresh();
        assert!(p.is_cached());
        assert_eq!(
            p.constraints(0.0, &SVector::<f64, 2>::new(1.0, 0.0))[0],
            0.0
        );
        p.l = 1.5;
        p.refresh();
        assert_eq!(format!("{p:?}"), "Pendulum { m: 2.0, l: 1.5, g: 9.81 }");
        assert_eq!(Pendulum::COORDINATES, ["x", "y"]);
        assert_eq!(<Pendulum as Mechanism<2, 1>>::PARAMETERS, &["m", "l", "g"]);
        assert_eq!((Pendulum::N, Pendulum::M), (2, 1));
        let q = SVector::<f64, 2>::new(0.3, -0.4);
        let qd = SVector::<f64, 2>::new(1.0, 2.0);
        // M = diag(m, m), g = [0, m g], Phi = x^2 + y^2 - l^2, Phi_q = [2x, 2y].
        assert_eq!(
            p.mass_matrix(&q),
            SMatrix::<f64, 2, 2>::new(2.0, 0.0, 0.0, 2.0)
        );
        assert_eq!(p.gravity(&q), SVector::<f64, 2>::new(0.0, 2.0 * 9.81));
        assert!((p.constraints(0.0, &q)[0] - (0.25 - 2.25)).abs() < 1e-15);
        assert_eq!(
            p.constraint_jacobian(0.0, &q),
            SMatrix::<f64, 1, 2>::new(0.6, -0.8)
        );
        // gamma = -2 (x'^2 + y'^2).
        assert!((p.constraint_gamma(0.0, &q, &qd)[0] + 10.0).abs() < 1e-14);
        assert_eq!(
            p.generalized_forces(0.0, &q, &qd),
            SVector::<f64, 2>::new(-0.1, 0.0)
        );
        let e = p.evaluate(0.0, &q, &qd);
        assert_eq!(e.mass, p.mass_matrix(&q));
        assert!((e.kinetic - 5.0).abs() < 1e-14);
        assert!(Pendulum::equations().contains("Phi"));
    }
}

/// A private struct, no constraints, no forces, no independent block: an angle pendulum.
mod private_unconstrained {
    use mechanism::prelude::*;

    mechanism! {
        struct AnglePendulum;
        parameters { m = 1.0; l = 2.0; g = 9.81; }
        coordinates { th = 0.1; }
        independent { th = 0.1; der(th) = 0.0; }
        kinetic = 1/2*m*l^2*der(th)^2;
        potential = -m*g*l*cos(th);
    }

    #[test]
    fn private_unconstrained() {
        let p = AnglePendulum::default();
        let q = SVector::<f64, 1>::new(0.3);
        let qd = SVector::<f64, 1>::new(0.0);
        assert_eq!(p.mass_matrix(&q)[(0, 0)], 4.0);
        assert!((p.gravity(&q)[0] - 9.81 * 2.0 * 0.3f64.sin()).abs() < 1e-14);
        let e = p.evaluate(0.0, &q, &qd);
        assert_eq!(e.phi.len(), 0);
    }
}

/// More constraint rows than coordinates compiles (redundant rows: an overconstrained
/// mechanism; the runtime reports the rank of Phi_q). A point mass on a circle in the plane
/// z = 0, with both the plane and the circle written twice: n = 3, m = 4, rank 2, one degree
/// of freedom. The rows are labelled by statement and component.
mod redundant_rows {
    use mechanism::prelude::*;

    mechanism! {
        pub struct RedundantCircle;
        parameters { m = 1.0; l = 1.0; g = 9.81; }
        coordinates { x = 0.6; y = -0.8; z = 0.0; }
        independent { x = 0.6; der(x) = 0.0; }
        kinetic = 1/2*m*(der(x)^2 + der(y)^2 + der(z)^2);
        potential = m*g*y;
        constraints {
            x^2 + y^2 - l^2;
            [z, 2*(x^2 + y^2 - l^2)] = [0, 0];
            3*z;
        }
    }

    #[test]
    fn redundant_rows() {
        assert_eq!((RedundantCircle::N, RedundantCircle::M), (3, 4));
        assert_eq!(
            <RedundantCircle as Mechanism<3, 4>>::CONSTRAINT_ROWS,
            &[
                ("constraint 1", ""),
                ("constraint 2", "x"),
                ("constraint 2", "y"),
                ("constraint 3", ""),
            ]
        );
        let p = RedundantCircle::default();
        let q = SVector::<f64, 3>::new(0.6, -0.8, 0.0);
        let jac = p.constraint_jacobian(0.0, &q);
        assert_eq!(jac.rank(1e-12), 2);
        let info = Compiled::new(p).info().clone();
        assert_eq!(info.constraint_label(2), "constraint 2 y");
    }
}

/// The file form, and a parameter changed at run time without rebuilding.
mod file_form {
    use mechanism::prelude::*;

    mechanism!(file = "../../mechanisms/cartesian_pendulum.mech");

    #[test]
    fn file_form() {
        let mut p = CartesianPendulum::default();
        assert!(p.set_parameter(0, 3.0).is_ok());
        assert_eq!(p.m, 3.0);
        assert!(p.set_parameter(99, 1.0).is_err());
        let q = SVector::<f64, 2>::new(0.6, -0.8);
        assert_eq!(p.mass_matrix(&q)[(1, 1)], 3.0);
        assert_eq!(CartesianPendulum::INDEPENDENT[0].coordinate, 0);
    }
}

/// `crate = path,` names the runtime crate through a re-export.
mod crate_path {
    mod reexport {
        pub use mechanism;
    }

    reexport::mechanism::mechanism! {
        crate = crate::pass_cases::crate_path::reexport::mechanism,
        pub struct Free;
        parameters { m = 1.0; }
        coordinates { x = 0.0; }
        independent { x = 0.0; der(x) = 1.0; }
        kinetic = 1/2*m*der(x)^2;
        potential = 0;
    }

    #[test]
    fn crate_path() {
        use reexport::mechanism::Mechanism;
        let q = reexport::mechanism::nalgebra::SVector::<f64, 1>::new(0.0);
        assert_eq!(Free::default().mass_matrix(&q)[(0, 0)], 1.0);
    }
}

/// A crate that forbids unsafe code can still declare a mechanism: the emitted call into
/// the AVX2 copy of `evaluate_into` (an `unsafe` block, in x86-64 builds without AVX2) comes
/// from the macro, which the `unsafe_code` lint does not hold against the user's crate.
mod forbid_unsafe_code {
    #![forbid(unsafe_code)]
    use mechanism::prelude::*;

    mechanism!(file = "../../mechanisms/planar_four_bar.mech");

    #[test]
    fn forbid_unsafe_code() {
        let m = PlanarFourBar::default();
        let q = SVector::<f64, 3>::new(0.4, 1.1, 2.0);
        let qd = SVector::<f64, 3>::new(1.0, -0.5, 0.25);
        let mut out = StaticEvaluation::<3, 2>::zeros();
        m.evaluate_into(0.0, &q, &qd, &mut out);
        let mass = m.mass_matrix(&q);
        // Two programs (the combined one and the mass matrix's own) of the same expressions:
        // equal up to rounding.
        assert!((out.mass - mass).abs().max() <= 1e-12 * mass.abs().max());
    }
}
