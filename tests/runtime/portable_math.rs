//! The generated code with the no-std math route (libm, as a `#![no_std]` user crate gets
//! it) against the same declaration with the std route. `crate = ...` points the second
//! expansion at a runtime whose `math` is the no-std one; everything else is the same crate.

use mechanism::Mechanism;
use nalgebra::SVector;

/// The paths the generated code uses, with the math of a build without std.
pub mod runtime {
    pub use mechanism::{
        __private, EvaluationSlices, Independent, Mechanism, ParameterError, ParameterRange,
        StaticEvaluation, StaticSparsity,
    };

    /// What `mechanism::math` is without the `std` feature.
    pub mod math {
        pub use mechanism::math::portable::{atan2, exp, ln, powf, powi, sqrt, tan};
        pub use mechanism::math::{Baseline, Isa, mul_add, read, sin_cos};

        /// The copy compiled with AVX2 calls the same functions (only its lanes differ).
        #[cfg(target_arch = "x86_64")]
        pub mod avx2 {
            pub use mechanism::math::avx2::Avx2;
        }
    }
}

mod with_std {
    mechanism::mechanism!(file = "tests/runtime/every_function.mech");
}

mod with_libm {
    mechanism::mechanism!(
        crate = crate::portable_math::runtime,
        file = "tests/runtime/every_function.mech"
    );
}

#[test]
fn the_no_std_route_agrees_with_the_std_route() {
    let (a, b) = (
        with_std::EveryFunction::default(),
        with_libm::EveryFunction::default(),
    );
    let mut worst = 0.0_f64;
    for i in 0..200 {
        let s = f64::from(i) * 0.031;
        let q = SVector::from([0.9 * s.sin(), 0.9 * (1.3 * s).cos()]);
        let qd = SVector::from([(0.7 * s).cos() - 0.2, 0.5 * s.sin()]);
        let (ea, eb) = (a.evaluate(s, &q, &qd), b.evaluate(s, &q, &qd));
        let pairs = [
            (ea.mass.as_slice(), eb.mass.as_slice()),
            (ea.coriolis.as_slice(), eb.coriolis.as_slice()),
            (ea.gravity.as_slice(), eb.gravity.as_slice()),
            (ea.phi.as_slice(), eb.phi.as_slice()),
            (ea.phi_q.as_slice(), eb.phi_q.as_slice()),
            (ea.gamma.as_slice(), eb.gamma.as_slice()),
            (
                &[ea.kinetic, ea.potential][..],
                &[eb.kinetic, eb.potential][..],
            ),
        ];
        for (x, y) in pairs {
            let scale = x.iter().fold(1e-300_f64, |m, v| m.max(v.abs()));
            for (u, v) in x.iter().zip(y) {
                worst = worst.max((u - v).abs() / scale);
            }
        }
    }
    // Each function differs by at most 1 ulp between the routes (math's own tests); a few
    // of them feed each entry through sums and products of size ~1: 1e-14 relative to the
    // largest entry of each output is 45 ulps. Measured: a few ulps.
    assert!(worst <= 1e-14, "largest relative difference {worst:e}");
    // Not trivially equal: the routes really are different functions.
    assert!(worst > 0.0, "the two routes gave identical bits everywhere");
}
