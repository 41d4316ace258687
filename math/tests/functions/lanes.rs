//! `sin_cos_lanes` against `sin_cos`, lane by lane and bit for bit: every lane count the
//! generated code uses, fast lanes mixed with lanes off the fast path (near multiples of
//! pi/2, -0.0, beyond 2^20, infinities, NaN) in every position. On an x86-64 CPU with AVX2,
//! `avx2::sin_cos_lanes` (four lanes to a register even where the build does not enable
//! AVX2) too.

use mechanism_math::{sin_cos, sin_cos_lanes};
use proptest::prelude::*;

fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

fn check<const L: usize>(x: [f64; L]) {
    compare(x, sin_cos_lanes(x));
    #[cfg(target_arch = "x86_64")]
    if mechanism_math::avx2::detected() {
        // SAFETY: the CPU has AVX2.
        compare(x, unsafe { mechanism_math::avx2::sin_cos_lanes(x) });
    }
}

/// Each lane of (s, c) against `sin_cos` of its argument.
fn compare<const L: usize>(x: [f64; L], (s, c): ([f64; L], [f64; L])) {
    for i in 0..L {
        let (ws, wc) = sin_cos(x[i]);
        assert!(
            same(s[i], ws) && same(c[i], wc),
            "lane {i} of {x:?}: ({}, {}) vs ({ws}, {wc})",
            s[i],
            c[i]
        );
    }
}

/// Inputs off the fast path (near multiples of pi/2, -0.0, out of range, not finite), and
/// the fast path's edges.
const SPECIAL: [f64; 15] = [
    0.0,
    -0.0,
    std::f64::consts::FRAC_PI_2,
    // The double nearest 29 pi/2: the smallest |x - k pi/2| below 2^20.
    45.553_093_477_052,
    -std::f64::consts::PI,
    1.4e-8,
    1.490_116_119_384_765_6e-8,
    1_048_575.999_999_999_9,
    1_048_576.0,
    1e300,
    f64::INFINITY,
    f64::NEG_INFINITY,
    f64::NAN,
    5e-324,
    0.7,
];

#[test]
fn special_values_in_every_lane() {
    for &a in &SPECIAL {
        for &b in &SPECIAL {
            check([a]);
            check([a, b]);
            check([a, 0.3, b]);
            check([0.3, a, -2.0, b]);
            check([b, 1.0, 2.0, a]);
            // Past one AVX2 vector, and past the four vectors written out (nine lanes in
            // SSE2 pairs): the padded last vector and the loop after them.
            check([1.0, a, 2.0, 3.0, b]);
            check([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, a, b]);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(5_000))]

    #[test]
    fn lanes_are_sin_cos_bit_for_bit(
        a in -1e3..1e3_f64,
        b in -10.0..10.0_f64,
        c in -3e6..3e6_f64,
        d in prop::sample::select(SPECIAL.to_vec()),
    ) {
        check([a, b]);
        check([a, b, c]);
        check([a, b, c, d]);
        check([d, c, b, a]);
    }
}
