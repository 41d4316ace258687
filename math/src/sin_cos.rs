//! sin and cos of one argument, computed together inline: the function that the emitted code,
//! the codegen interpreter (`Tape`) and its expression evaluator all call for `sin`, `cos`
//! and `sin_cos`, so all three round the same way, bit for bit.
//!
//! Why not `f64::sin_cos`? In the small mechanisms evaluation is bound by those calls: glibc's
//! `sincos` costs about 10 ns a call and is opaque to the optimiser. [`sin_cos`] is
//! straight-line arithmetic that the compiler interleaves with the independent angles next to
//! it: five independent (sin, cos) pairs take about 0.6x the time of libm's (x86-64 baseline,
//! no FMA); one alone has about the same latency as libm's.

/// 2/pi.
const FRAC_2_PI: f64 = core::f64::consts::FRAC_2_PI;
/// 1.5 * 2^52: for |y| < 2^51, `(y + SHIFT) - SHIFT` is y rounded to the nearest integer, and
/// the low bits of `y + SHIFT` are that integer modulo 4.
const SHIFT: f64 = 6_755_399_441_055_744.0;
/// pi/2 = P1 + P2 + P3 + e with |e| < 2^-109. P1 has 33 significant bits (a multiple of
/// 2^-32) and P2 20 bits (a multiple of 2^-53), so k P1 and k P2 are exact for |k| < 2^20.
const P1: f64 = f64::from_bits(0x3FF9_21FB_5440_0000);
const P2: f64 = f64::from_bits(0x3DD0_B462_0000_0000);
const P3: f64 = -4.978_996_250_514_799_4e-17;
/// The fast path takes |x| < 2^20 (so |k| < 2^20)...
const BOUND: f64 = 1_048_576.0;
/// ... and |r| >= 2^-26, where the reduction's relative error is at most 2^-60.
const TINY: f64 = 1.490_116_119_384_765_6e-8;

/// sin r = r + r z S(z), z = r^2: minimax coefficients for the relative error on
/// |r| <= pi/4 (fitted for this crate in multiple precision, rounded to doubles): 2^-57.8.
const S: [f64; 6] = [
    -0.166_666_666_666_666_3,
    0.008_333_333_333_321_84,
    -0.000_198_412_698_293_592_27,
    2.755_731_353_881_606_6e-6,
    -2.505_073_444_339_455_5e-8,
    1.589_543_674_157_892_4e-10,
];
/// cos r = 1 - z/2 + z^2 C(z): as for `S`, relative error 2^-62.7.
const C: [f64; 6] = [
    0.041_666_666_666_666_664,
    -0.001_388_888_888_888_358_6,
    2.480_158_729_461_703_4e-5,
    -2.755_731_567_044_053_4e-7,
    2.087_588_511_059_322_2e-9,
    -1.136_731_264_478_095_5e-11,
];

/// (sin x, cos x), faithfully rounded (error below 1 ulp), for inlining into generated code.
///
/// # Method
/// 1. Reduction (Cody–Waite, three parts): k = round(x 2/pi), r = x - k pi/2 with
///    pi/2 = P1 + P2 + P3. For |x| < 2^20, |k| < 2^20, k P1 and k P2 are exact, and so are
///    a = x - k P1 and s = a - k P2 (multiples of 2^-53 smaller than 1). Then
///    hi = s - k P3, lo = (s - hi) - k P3 (a fast two-sum, as |s| >= |k P3|) represent r as a
///    double-double with |r - (hi + lo)| <= 2^-86 (the rounding of k P3 and the rest of
///    pi/2): relative error <= 2^-60 for |r| >= 2^-26.
/// 2. Kernels on |r| <= pi/4, z = hi^2, with the first-order terms of lo:
///    - sin r = hi + (hi z S(z) + lo (1 - z/2)),
///    - cos r = w + (((1 - w) - z/2) + (z^2 C(z) - hi lo)), w = 1 - z/2 (the rounding error
///      of w is added back),
///
///    S and C of degree 5 in z, by Estrin's scheme: (c0 + z c1) + z^2 ((c2 + z c3) +
///    z^2 (c4 + z c5)), which halves the dependency chain of Horner's, each step a
///    [`crate::mul_add`] (fused where the target has FMA, the plain product and sum
///    elsewhere: never a libm call).
/// 3. Quadrant k mod 4: (sin x, cos x) = (sin r, cos r), (cos r, -sin r), (-sin r, -cos r),
///    (-cos r, sin r), chosen with bit masks (no branch).
///
/// # Accuracy and range
/// The fast path is taken for |x| < 2^20 (about 1.05e6) when 2^-26 <= |r| or k = 0 (then
/// r = x exactly). Its largest error
/// measured against a double-double reference (1e7 random x in each of [-10, 10],
/// [-1000, 1000] and [-2^20, 2^20], and every multiple of pi/2 and pi/4 with its neighbours
/// within 3 ulps) is 0.82 ulp: the result is one of the two doubles around the exact value,
/// and differs from a correctly rounded one (and from glibc's) by at most 1 ulp. Everything
/// else, |x| >= 2^20, x within 2^-26 of a nonzero multiple of pi/2, -0.0, infinities and
/// NaN, is the platform's `sin` and `cos` (`f64::sin_cos` with std, libm's `sincos`
/// without; one rarely taken branch): so sin(-0.0) = -0.0 and sin and cos
/// of infinities and NaN are NaN.
///
/// # Example
/// ```
/// use mechanism_math::sin_cos;
/// let (s, c) = sin_cos(0.5);
/// assert!((s - 0.5_f64.sin()).abs() <= f64::EPSILON && (c - 0.5_f64.cos()).abs() <= f64::EPSILON);
/// assert_eq!(sin_cos(-0.0).0.to_bits(), (-0.0_f64).to_bits());
/// assert!(sin_cos(f64::INFINITY).0.is_nan() && sin_cos(f64::NAN).1.is_nan());
/// ```
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    let r = reduce(x);
    // |x| < BOUND and |hi| >= TINY, on the bits (sign shifted out): NaN and infinities fail
    // the first. Integer compares keep the floating-point units free for the arithmetic.
    // With k = 0 the reduction is exact (r = x), so small |x| (0 included: a parameter
    // such as the seed's alpha = 0 is evaluated on every call) stays on the fast path, except
    // -0.0, whose sign the subtraction of k P3 = -0.0 would lose.
    let fast = ((x.to_bits() << 1) < (BOUND.to_bits() << 1))
        & (((r.hi.to_bits() << 1) >= (TINY.to_bits() << 1))
            | ((r.k == 0.0) & (x.to_bits() != (-0.0_f64).to_bits())));
    if !fast {
        return libm_sin_cos(x);
    }
    kernel(&r)
}

/// (sin x_i, cos x_i) for each of L arguments, each lane bit for bit [`sin_cos`]`(x_i)`:
/// the same operations lane by lane, written over arrays so that the compiler computes
/// the lanes together in vector registers (two per SSE2 instruction, four or eight with
/// AVX). The generated code calls it for the angles whose arguments are at hand together
/// (the coordinates' angles, at the top of an evaluation). Every lane runs the fast path's
/// arithmetic; one rarely taken branch then recomputes the lanes off the fast path with
/// the platform's functions, as [`sin_cos`] does for them.
///
/// # Example
/// ```
/// use mechanism_math::{sin_cos, sin_cos_lanes};
/// let x = [0.5, -3.0, 1e7, -0.0];
/// let (s, c) = sin_cos_lanes(x);
/// for i in 0..4 {
///     assert_eq!((s[i].to_bits(), c[i].to_bits()), (sin_cos(x[i]).0.to_bits(), sin_cos(x[i]).1.to_bits()));
/// }
/// ```
#[inline(always)]
pub fn sin_cos_lanes<const L: usize>(x: [f64; L]) -> ([f64; L], [f64; L]) {
    let r: [Reduced; L] = core::array::from_fn(|i| reduce(x[i]));
    // The fast-path test of `sin_cos` with floating-point compares, which vectorise
    // (64-bit integer compares do not before SSE4.2); the same for every input: |x| < BOUND
    // fails for NaN and infinities as the bit compare does, hi is then finite, and x is
    // -0.0 exactly when it equals 0 with its sign bit set.
    let mut fast = [true; L];
    for i in 0..L {
        let negative_zero = (x[i] == 0.0) & x[i].is_sign_negative();
        fast[i] =
            (x[i].abs() < BOUND) & ((r[i].hi.abs() >= TINY) | ((r[i].k == 0.0) & !negative_zero));
    }
    let mut s = [0.0; L];
    let mut c = [0.0; L];
    for i in 0..L {
        (s[i], c[i]) = kernel(&r[i]);
    }
    if !fast.iter().all(|f| *f) {
        replace_slow_lanes(&x, &fast, &mut s, &mut c);
    }
    (s, c)
}

/// The lanes off the fast path by the platform's functions, out of line: the rare case of
/// [`sin_cos_lanes`] (the fast lanes keep their values).
#[cold]
#[inline(never)]
fn replace_slow_lanes<const L: usize>(
    x: &[f64; L],
    fast: &[bool; L],
    s: &mut [f64; L],
    c: &mut [f64; L],
) {
    for i in 0..L {
        if !fast[i] {
            (s[i], c[i]) = libm_sin_cos(x[i]);
        }
    }
}

/// x = k pi/2 + (hi + lo), and the bits of x 2/pi + SHIFT (k mod 4 in the low bits).
struct Reduced {
    k: f64,
    hi: f64,
    lo: f64,
    q: u64,
}

/// Step 1 of [`sin_cos`] (valid on its fast path).
#[inline(always)]
fn reduce(x: f64) -> Reduced {
    let t = x * FRAC_2_PI + SHIFT;
    let k = t - SHIFT;
    let a = x - k * P1;
    let s = a - k * P2;
    let c = k * P3;
    let hi = s - c;
    Reduced {
        k,
        hi,
        lo: (s - hi) - c,
        q: t.to_bits(),
    }
}

/// Steps 2 and 3 of [`sin_cos`]: the kernels on the reduced argument and the quadrant.
#[inline(always)]
fn kernel(r: &Reduced) -> (f64, f64) {
    let (hi, lo, q) = (r.hi, r.lo, r.q);
    let z = hi * hi;
    let z2 = z * z;
    let ps = estrin(&S, z, z2);
    let pc = estrin(&C, z, z2);
    let hz = 0.5 * z;
    let sin_r = hi + ((z * hi) * ps + (lo - lo * hz));
    let w = 1.0 - hz;
    let cos_r = w + (((1.0 - w) - hz) + (z2 * pc - hi * lo));
    // Quadrant: swap when k is odd, negate sin when k mod 4 is 2 or 3, cos when it is 1 or 2.
    let swap = (q & 1).wrapping_neg();
    let (sb, cb) = (sin_r.to_bits(), cos_r.to_bits());
    let sin_bits = ((sb & !swap) | (cb & swap)) ^ ((q & 2) << 62);
    let cos_bits = ((cb & !swap) | (sb & swap)) ^ ((q.wrapping_add(1) & 2) << 62);
    (f64::from_bits(sin_bits), f64::from_bits(cos_bits))
}

/// p0 + z p1 + ... + z^5 p5 by Estrin's scheme, (p0 + z p1) + z^2 ((p2 + z p3) +
/// z^2 (p4 + z p5)), each step a [`crate::mul_add`] (one rounding where the target has
/// FMA, which shortens the dependency chain; exactly the unfused value elsewhere).
#[inline(always)]
fn estrin(p: &[f64; 6], z: f64, z2: f64) -> f64 {
    use crate::mul_add;
    let inner = mul_add(z2, mul_add(z, p[5], p[4]), mul_add(z, p[3], p[2]));
    mul_add(z2, inner, mul_add(z, p[1], p[0]))
}

/// The rare cases, out of line so that the inlined fast path stays small.
#[cold]
#[inline(never)]
fn libm_sin_cos(x: f64) -> (f64, f64) {
    crate::route::sin_cos(x)
}
