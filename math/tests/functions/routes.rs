//! The no-std route (`portable`, libm) against the platform's f64 methods: sqrt and powi
//! give the same bits; exp, ln, tan, powf, sin and cos are faithfully rounded on both
//! routes, so they differ by at most 1 ulp. libm's atan2 is not faithfully rounded
//! everywhere (see [`atan2_two_ulps_from_glibc`]), so atan2 may differ by 2.

use mechanism_math::portable;
use proptest::prelude::*;

use crate::ulps::ulps_apart;

fn within_one_ulp(name: &str, x: f64, ours: f64, platform: f64) {
    within_ulps(name, x, ours, platform, 1);
}

fn within_ulps(name: &str, x: f64, ours: f64, platform: f64, ulps: u64) {
    assert!(
        ulps_apart(ours, platform) <= ulps,
        "{name}({x:e}): libm {ours:e}, platform {platform:e}"
    );
}

/// The input where proptest found the two atan2s 2 ulps apart. Against the exact value
/// (300-bit mpmath, -0.12498110518750559640...), libm's result is 1.50 ulp off and glibc's
/// 0.50 ulp: libm's atan2 is not faithfully rounded here, and 2 ulps is the bound.
#[test]
fn atan2_two_ulps_from_glibc() {
    let (y, x) = (-30.509_487_473_908_9, 242.840_437_459_907_5);
    assert!(ulps_apart(portable::atan2(y, x), y.atan2(x)) <= 2);
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20_000))]

    #[test]
    fn sqrt_is_bit_for_bit(x in 0.0..1e300_f64) {
        prop_assert_eq!(portable::sqrt(x).to_bits(), x.sqrt().to_bits());
    }

    #[test]
    fn powi_is_bit_for_bit(x in -1e3..1e3_f64, k in -12..=12_i32) {
        prop_assert_eq!(portable::powi(x, k).to_bits(), x.powi(k).to_bits());
    }

    #[test]
    fn transcendental_functions_within_one_ulp(x in -700.0..700.0_f64, y in -50.0..50.0_f64) {
        within_one_ulp("exp", x, portable::exp(x), x.exp());
        within_one_ulp("tan", y, portable::tan(y), y.tan());
        within_ulps("atan2", x, portable::atan2(y, x), y.atan2(x), 2);
        let a = x.abs() + 1e-300;
        within_one_ulp("ln", a, portable::ln(a), a.ln());
        let b = y.abs() / 10.0;
        within_one_ulp("powf", b, portable::powf(b, 1.5), b.powf(1.5));
        let (s, c) = portable::sin_cos(y);
        within_one_ulp("sin", y, s, y.sin());
        within_one_ulp("cos", y, c, y.cos());
    }
}

/// With the std feature (on in the workspace build) the public functions are the platform's,
/// bit for bit: hand-written `x.sqrt()` code and the generated code agree.
#[cfg(feature = "std")]
#[test]
fn the_std_route_is_the_f64_methods() {
    for x in [0.3_f64, 1.7, 12.5, 1e-5] {
        assert_eq!(mechanism_math::sqrt(x).to_bits(), x.sqrt().to_bits());
        assert_eq!(mechanism_math::exp(x).to_bits(), x.exp().to_bits());
        assert_eq!(mechanism_math::ln(x).to_bits(), x.ln().to_bits());
        assert_eq!(
            mechanism_math::powf(x, 0.7).to_bits(),
            x.powf(0.7).to_bits()
        );
        assert_eq!(
            mechanism_math::atan2(x, 0.4).to_bits(),
            x.atan2(0.4).to_bits()
        );
        assert_eq!(mechanism_math::abs(-x).to_bits(), x.to_bits());
    }
}

/// Without it (`cargo test -p mechanism-math`) they are libm's.
#[cfg(not(feature = "std"))]
#[test]
fn the_no_std_route_is_libm() {
    for x in [0.3_f64, 1.7, 12.5, 1e-5] {
        assert_eq!(mechanism_math::exp(x).to_bits(), portable::exp(x).to_bits());
        assert_eq!(mechanism_math::ln(x).to_bits(), portable::ln(x).to_bits());
        assert_eq!(mechanism_math::tan(x).to_bits(), portable::tan(x).to_bits());
        assert_eq!(
            mechanism_math::powf(x, 0.7).to_bits(),
            portable::powf(x, 0.7).to_bits()
        );
    }
}
