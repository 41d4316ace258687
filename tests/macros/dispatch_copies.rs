//! Every generated method has two copies on an x86-64 build without AVX2: its body generic
//! over the instruction set, compiled for the baseline and (called where the CPU has AVX2)
//! inside a function compiled with `avx2`. The two must give the same bits, method by
//! method, at states on and off the sines' fast path: the five-bar leg (constraint rows,
//! link frames, small bodies) and the Whipple bicycle (velocity rows; its evaluation and
//! tangent past `LEAN_ABOVE`, in the lean form). Declared here, so that this module reaches
//! the copies (private inherent functions of the emitted struct).

#![cfg(all(target_arch = "x86_64", not(target_feature = "avx2")))]

use mechanism::math::Baseline;
use mechanism::math::avx2::Avx2;
use mechanism::nalgebra::SVector;
use mechanism::{Mechanism, StaticEvaluation};

mechanism::mechanism!(file = "mechanisms/five_bar.mech");
mechanism::mechanism!(file = "mechanisms/whipple_bicycle.mech");

/// Calls `$method` through both copies and compares the values' debug text (f64's is its
/// shortest round-trip decimal: equal text, equal bits, the sign of zero included).
macro_rules! same_bits {
    ($m:expr, $isa:expr, $method:ident, $avx2:ident, $what:expr, ($($arg:expr),*)) => {{
        let base = $m.$method(Baseline, $($arg),*);
        // SAFETY: `$isa` proves the CPU has AVX2.
        let wide = unsafe { $m.$avx2($isa, $($arg),*) };
        assert_eq!(format!("{base:?}"), format!("{wide:?}"), "{} at {}", stringify!($method), $what);
    }};
}

/// Coordinates on and off the fast path of `sin_cos`: ordinary angles, multiples of pi/2, a
/// large angle, negative zero.
fn state<const N: usize>(k: usize) -> [SVector<f64, N>; 3] {
    let q = SVector::<f64, N>::from_fn(|i, _| match (i + k) % 5 {
        0 => 0.3 + 0.7 * i as f64 - 0.11 * k as f64,
        1 => std::f64::consts::FRAC_PI_2 * (k as f64 - 2.0),
        2 => -2.5e6 + 0.37 * k as f64,
        3 => -0.0,
        _ => -1.3 + 0.45 * (i * k) as f64,
    });
    let qd = SVector::<f64, N>::from_fn(|i, _| -1.1 + 0.4 * (i + k) as f64);
    let qdd = SVector::<f64, N>::from_fn(|i, _| 0.8 - 0.3 * (i + 2 * k) as f64);
    [q, qd, qdd]
}

/// Every dispatched method of one mechanism, both copies, at a few states.
macro_rules! check_mechanism {
    ($ty:ident) => {{
        const N: usize = $ty::N;
        const M: usize = $ty::M;
        let Some(isa) = Avx2::detected() else {
            return;
        };
        let r = $ty::default();
        for k in 0..6 {
            let [q, qd, qdd] = state::<N>(k);
            let lambda = SVector::<f64, M>::from_fn(|i, _| 2.0 - 0.5 * (i + k) as f64);
            let t = 0.25 * k as f64;
            let w = format!("state {k}");
            same_bits!(r, isa, __mass_matrix, __mass_matrix_avx2, w, (&q));
            same_bits!(
                r,
                isa,
                __coriolis_matrix,
                __coriolis_matrix_avx2,
                w,
                (&q, &qd)
            );
            same_bits!(
                r,
                isa,
                __coriolis_forces,
                __coriolis_forces_avx2,
                w,
                (&q, &qd)
            );
            same_bits!(r, isa, __gravity, __gravity_avx2, w, (&q));
            same_bits!(
                r,
                isa,
                __generalized_forces,
                __generalized_forces_avx2,
                w,
                (t, &q, &qd)
            );
            same_bits!(r, isa, __constraints, __constraints_avx2, w, (t, &q));
            same_bits!(
                r,
                isa,
                __constraint_jacobian,
                __constraint_jacobian_avx2,
                w,
                (t, &q)
            );
            same_bits!(
                r,
                isa,
                __constraint_gamma,
                __constraint_gamma_avx2,
                w,
                (t, &q, &qd)
            );
            same_bits!(
                r,
                isa,
                __kinetic_energy,
                __kinetic_energy_avx2,
                w,
                (&q, &qd)
            );
            same_bits!(r, isa, __potential_energy, __potential_energy_avx2, w, (&q));
            same_bits!(
                r,
                isa,
                __mass_and_bias,
                __mass_and_bias_avx2,
                w,
                (t, &q, &qd)
            );
            same_bits!(
                r,
                isa,
                __inverse_dynamics,
                __inverse_dynamics_avx2,
                w,
                (t, &q, &qd, &qdd)
            );
            same_bits!(
                r,
                isa,
                __residual_tangent,
                __residual_tangent_avx2,
                w,
                (t, &q, &qd, &qdd, &lambda)
            );
            for frame in 0..<$ty as Mechanism<N, M>>::FRAMES.len() {
                same_bits!(
                    r,
                    isa,
                    __frame_placement,
                    __frame_placement_avx2,
                    w,
                    (frame, &q)
                );
                same_bits!(
                    r,
                    isa,
                    __frame_jacobian,
                    __frame_jacobian_avx2,
                    w,
                    (frame, &q)
                );
            }
            let (mut a, mut b) = (StaticEvaluation::<N, M>::zeros(), StaticEvaluation::zeros());
            r.__evaluate_into(Baseline, t, &q, &qd, &mut a);
            // SAFETY: `isa` proves the CPU has AVX2.
            unsafe { r.__evaluate_into_avx2(isa, t, &q, &qd, &mut b) };
            assert_eq!(format!("{a:?}"), format!("{b:?}"), "evaluate_into at {w}");
        }
    }};
}

#[test]
fn both_copies_of_every_method_give_the_same_bits() {
    check_mechanism!(FiveBar);
    check_mechanism!(WhippleBicycle);
}
