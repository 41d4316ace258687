//! sin and cos of one argument, computed together inline: the function that the emitted code,
//! the codegen interpreter (`Tape`) and its expression evaluator all call for `sin`, `cos`
//! and `sin_cos`, so all three round the same way, bit for bit.
//!
//! Why not `f64::sin_cos`? In the small mechanisms evaluation is bound by those calls: glibc's
//! `sincos` costs about 10 ns a call and is opaque to the optimiser. [`sin_cos`] is
//! straight-line arithmetic that the compiler interleaves with the independent angles next to
//! it: five independent (sin, cos) pairs take about 0.6x the time of libm's (x86-64 baseline,
//! no FMA); one alone has about the same latency as libm's.

use crate::real::Real;

#[cfg(all(test, feature = "std"))]
mod fused_reduction;

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
/// pi/2 - P1 - P2 = R1 + R23 + e' with |e'| < 2^-142: R1 has 33 significant bits, so k R1
/// is exact for |k| < 2^20.
const R1: f64 = f64::from_bits(0xBC8C_B3B3_99D0_0000);
const R23: f64 = f64::from_bits(0xBA6D_1FC8_F8CB_B5BF);
/// Where products are fused ([`Real::FUSED`]): pi/2 = FRAC_PI_2 + Q2 + e with
/// |e| < 2^-109 (FRAC_PI_2 is pi/2 rounded to a double).
const Q2: f64 = f64::from_bits(0x3C91_A626_3314_5C07);
/// pi/2 - FRAC_PI_2 = Q21 + Q22 + e' with |e'| < 2^-141: Q21 has 33 significant bits, so
/// k Q21 is exact for |k| < 2^20.
const Q21: f64 = f64::from_bits(0x3C91_A626_3310_0000);
const Q22: f64 = f64::from_bits(0x3A71_701B_839A_2520);
/// The inline path takes |x| < 2^20 (so |k| < 2^20).
const BOUND: f64 = 1_048_576.0;
/// Below 2^-26, |r| is too small for the three-part reduction's 2^-86 (k != 0): the
/// reduction then takes pi/2 in four parts, [`reduce_near_multiple`].
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
///    pi/2): relative error <= 2^-60 for |r| >= 2^-26. Where |r| < 2^-26 and k != 0 (x
///    within 2^-26 of a nonzero multiple of pi/2, such as a crank at exactly 90 degrees),
///    the rest of pi/2 after P1 + P2 is taken in two more parts, R1 + R23, with an exact
///    product and a two-sum: |r - (hi + lo)| < 2^-119, small against the smallest |r| of
///    any double below 2^20 (about 2^-60.5, at k = 29). x 2/pi + SHIFT, a and s are
///    [`crate::mul_add`]s (a and s are exact either way).
///
///    Where the target fuses [`crate::mul_add`] (FMA), the reduction is one step shorter:
///    s = x - k FRAC_PI_2 (pi/2 rounded to 53 bits) in one fused step is exact, because
///    k FRAC_PI_2 and x are multiples of 2^-53 (of 2^-52 for |x| >= 1) and |s| < 1; then
///    hi = s - k Q2 (pi/2 = FRAC_PI_2 + Q2 to 2^-109) rounded once, and its rounding error
///    lo = (s - hi) - k Q2 (s - hi exact), so |r - (hi + lo)| <= 2^-88. Near the multiples
///    the rest after FRAC_PI_2 is taken as Q21 + Q22, as R1 + R23 above.
/// 2. Kernels on |r| <= pi/4, z = hi^2, with the first-order terms of lo:
///    - sin r = hi + (hi z S(z) + lo (1 - z/2)),
///    - cos r = w + (z^2 C(z) + (((1 - w) - z/2) - hi lo)), w = 1 - z/2 (the rounding error
///      of w is added back; the small terms are summed before z^2 C(z) arrives, so the
///      longest chain, the polynomial's, ends in one multiply-add and one sum),
///
///    the products hi z S(z), lo z/2 and z^2 C(z) fused with the sums that take them where
///    the target has FMA,
///
///    S and C of degree 5 in z, by Estrin's scheme: (c0 + z c1) + z^2 ((c2 + z c3) +
///    z^2 (c4 + z c5)), which halves the dependency chain of Horner's, each step a
///    [`crate::mul_add`] (fused where the target has FMA, the plain product and sum
///    elsewhere: never a libm call).
///
///    After the four-part reduction (|r| < 2^-26) the series' first two terms are exact
///    to far below an ulp, and the kernels are those: sin r = hi + (lo - hi z/6),
///    cos r = 1 - z/2.
/// 3. Quadrant k mod 4: (sin x, cos x) = (sin r, cos r), (cos r, -sin r), (-sin r, -cos r),
///    (-cos r, sin r), chosen with bit masks (no branch).
///
/// # Accuracy and range
/// The inline path is taken for |x| < 2^20 (about 1.05e6) except -0.0. Its largest error
/// against a double-double reference (3e6 random x in each of [-10, 10],
/// [-1000, 1000] and [-2^20, 2^20], every multiple of pi/2 and pi/4 up to 3000 with its
/// neighbours within 3 ulps, and the doubles nearest every k pi/2 below 2^20 with their
/// neighbours) is 0.80 ulp (0.78 where the target has FMA; 0.50 near the multiples of
/// pi/2): the result is one of the two doubles around the exact value, and differs from a
/// correctly rounded one (and from glibc's) by at most 1 ulp. Everything else, |x| >= 2^20,
/// -0.0, infinities and NaN, is the platform's `sin` and `cos` (`f64::sin_cos` with std,
/// libm's `sincos` without; one rarely taken branch): so sin(-0.0) = -0.0 and sin and cos
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
        return off_the_fast_path(x);
    }
    kernel(&r)
}

/// [`sin_cos`] where its fast path does not apply, out of line: x near a nonzero multiple
/// of pi/2 by the four-part reduction and [`reduced_sin_cos_near_zero`] (the same route
/// as such a lane of [`sin_cos_lanes`], so the same bits), the rest (|x| >= 2^20, -0.0,
/// infinities, NaN) by the platform's functions.
#[cold]
#[inline(never)]
fn off_the_fast_path(x: f64) -> (f64, f64) {
    let in_range = (x.to_bits() << 1) < (BOUND.to_bits() << 1);
    if !in_range || x.to_bits() == (-0.0_f64).to_bits() {
        return crate::route::sin_cos(x);
    }
    let r = reduce(x);
    let (hi, lo) = reduce_near_multiple(&r);
    let (sin_r, cos_r) = reduced_sin_cos_near_zero(hi, lo);
    turn(r.t, sin_r, cos_r)
}

/// (sin x_i, cos x_i) for each of L arguments, each lane bit for bit [`sin_cos`]`(x_i)`:
/// the same operations lane by lane, several lanes per vector instruction. On x86-64 the
/// lanes go two to an SSE2 register, or (three or four of them) four to an AVX2 register
/// where the build enables `avx2`; elsewhere each lane is a [`sin_cos`] call. The generated
/// code calls it for the angles whose arguments are at hand together. Where a lane is off
/// [`sin_cos`]'s inline path (|x| >= 2^20, -0.0, infinities, NaN), one rarely taken
/// branch computes those lanes (with AVX-512, every lane) by [`sin_cos`] itself.
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
    in_lanes::<L, { cfg!(target_feature = "avx2") }>(x)
}

/// [`sin_cos_lanes`], four lanes to an AVX2 register where `WIDE` (x86-64 only: the caller
/// is compiled with `avx2` and runs on a CPU that has it), two to an SSE2 one otherwise.
#[inline(always)]
pub(crate) fn in_lanes<const L: usize, const WIDE: bool>(x: [f64; L]) -> ([f64; L], [f64; L]) {
    const { assert!(0 < L && L <= 64, "one to 64 lanes") };
    let mut s = [0.0; L];
    let mut c = [0.0; L];
    // Bit i set where lane i took the inline path.
    let inline = lanes::<L, WIDE>(&x, &mut s, &mut c);
    if inline != u64::MAX >> (64 - L) {
        // With AVX-512's 32 vector registers, recomputing every lane keeps the results in
        // registers on the common path; with 16, merging the recomputed lanes back costs a
        // body more stack reloads than the two stores it saves, so the lanes off the path
        // are patched in memory (the timings of both: docs/benchmark-history.md, "Off-path
        // lanes patched in memory where vector registers are 16").
        if cfg!(target_feature = "avx512f") {
            return lane_by_lane(x);
        }
        replace_platform_lanes(&x, inline, &mut s, &mut c);
    }
    (s, c)
}

/// The lanes off the inline path (bit i of `inline` clear) by [`sin_cos`], out of line,
/// written into `s` and `c` (the other lanes keep their values).
#[cold]
#[inline(never)]
fn replace_platform_lanes<const L: usize>(
    x: &[f64; L],
    inline: u64,
    s: &mut [f64; L],
    c: &mut [f64; L],
) {
    for i in 0..L {
        if inline & (1 << i) == 0 {
            (s[i], c[i]) = sin_cos(x[i]);
        }
    }
}

/// Every lane by [`sin_cos`], out of line: the rare case of [`sin_cos_lanes`] where a lane
/// is off the inline path. Computing all of them again here, rather than replacing the
/// lanes off the path in the vector results ([`replace_platform_lanes`]), keeps those
/// results in registers on the common path (a call that writes into them needs them in
/// memory first).
#[cold]
#[inline(never)]
fn lane_by_lane<const L: usize>(x: [f64; L]) -> ([f64; L], [f64; L]) {
    let (mut s, mut c) = ([0.0; L], [0.0; L]);
    for i in 0..L {
        (s[i], c[i]) = sin_cos(x[i]);
    }
    (s, c)
}

/// The lanes of [`sin_cos_lanes`] in x86-64 vector registers: four to a register for three
/// or more lanes where `WIDE` (AVX2), two otherwise. Returns the inline lanes' bits.
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn lanes<const L: usize, const WIDE: bool>(
    x: &[f64; L],
    s: &mut [f64; L],
    c: &mut [f64; L],
) -> u64 {
    if WIDE && L >= 3 {
        return in_vectors::<crate::x86::F64x4, L>(x, s, c);
    }
    in_vectors::<crate::x86::F64x2, L>(x, s, c)
}

/// `x` in vectors of W lanes (the last one padded with `x[0]`, its results dropped). The
/// first four vectors are written out, so that their offsets are constants for the
/// compiler (loops over them were not unrolled: the lanes were copied through the stack).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn in_vectors<V: crate::x86::Vector, const L: usize>(
    x: &[f64; L],
    s: &mut [f64; L],
    c: &mut [f64; L],
) -> u64 {
    let mut inline = in_vector::<V, L>(x, s, c, 0);
    if V::W < L {
        inline |= in_vector::<V, L>(x, s, c, V::W);
    }
    if 2 * V::W < L {
        inline |= in_vector::<V, L>(x, s, c, 2 * V::W);
    }
    if 3 * V::W < L {
        inline |= in_vector::<V, L>(x, s, c, 3 * V::W);
    }
    let mut i = 4 * V::W;
    while i < L {
        inline |= in_vector::<V, L>(x, s, c, i);
        i += V::W;
    }
    inline
}

/// Lanes i to i + W - 1 of [`in_vectors`] in one vector; returns their inline bits (at
/// their positions).
#[cfg(target_arch = "x86_64")]
#[inline(always)]
fn in_vector<V: crate::x86::Vector, const L: usize>(
    x: &[f64; L],
    s: &mut [f64; L],
    c: &mut [f64; L],
    i: usize,
) -> u64 {
    let mut a = [0.0; 4];
    for (j, a) in a.iter_mut().enumerate().take(V::W) {
        *a = if i + j < L { x[i + j] } else { x[0] };
    }
    let used = (1u64 << V::W.min(L - i)) - 1;
    let v = V::from_lanes(&a);
    let r = reduce(v);
    let fast = V::ordinary(v, r.k, r.hi, BOUND, TINY) as u64 & used;
    let mut inline = used;
    let (mut sin_r, mut cos_r) = reduced_sin_cos(r.hi, r.lo);
    if fast != used {
        // Rare: the lanes near a nonzero multiple of pi/2 take the four-part reduction and
        // the short kernels, computed beside the kernels above (which do not wait for
        // them) and blended in; those out of range (or -0.0) are left to the platform's
        // functions.
        let near = V::near_multiple(r.hi, r.k, TINY);
        let (hi, lo) = reduce_near_multiple(&r);
        let (s, c) = reduced_sin_cos_near_zero(hi, lo);
        sin_r = V::select(near, s, sin_r);
        cos_r = V::select(near, c, cos_r);
        inline = V::in_range(v, BOUND) as u64 & used;
    }
    let (vs, vc) = turn(r.t, sin_r, cos_r);
    let (mut ls, mut lc) = ([0.0; 4], [0.0; 4]);
    vs.to_lanes(&mut ls);
    vc.to_lanes(&mut lc);
    for j in 0..V::W {
        if i + j < L {
            s[i + j] = ls[j];
            c[i + j] = lc[j];
        }
    }
    inline << i
}

/// The lanes of [`sin_cos_lanes`] on targets other than x86-64: one [`sin_cos`] each.
#[cfg(not(target_arch = "x86_64"))]
#[inline(always)]
fn lanes<const L: usize, const WIDE: bool>(
    x: &[f64; L],
    s: &mut [f64; L],
    c: &mut [f64; L],
) -> u64 {
    for i in 0..L {
        (s[i], c[i]) = sin_cos(x[i]);
    }
    u64::MAX >> (64 - L)
}

/// x = k pi/2 + (hi + lo), s = x - k (P1 + P2) exactly (x - k FRAC_PI_2 where fused), and
/// t = x 2/pi + SHIFT (k mod 4 in the low bits of its bits).
struct Reduced<R> {
    k: R,
    s: R,
    hi: R,
    lo: R,
    t: R,
}

/// Step 1 of [`sin_cos`] (valid on its fast path), in every lane of `x`.
#[inline(always)]
fn reduce<R: Real>(x: R) -> Reduced<R> {
    let t = x.mul_add(R::splat(FRAC_2_PI), R::splat(SHIFT));
    let k = t.sub(R::splat(SHIFT));
    if R::FUSED {
        // s = x - k FRAC_PI_2 in one fused step, exact; hi = s - k Q2 rounded once, and lo
        // its rounding error (s - hi is exact on the fast path: |k Q2| < 2^-33 is far below
        // |hi| >= 2^-26, so s and hi are within a factor of two).
        let s = k.mul_add(R::splat(-core::f64::consts::FRAC_PI_2), x);
        let hi = k.mul_add(R::splat(-Q2), s);
        let lo = k.mul_add(R::splat(-Q2), s.sub(hi));
        return Reduced { k, s, hi, lo, t };
    }
    // Exact products and differences: the same value fused or not, one rounding step
    // shorter where fused.
    let a = k.mul_add(R::splat(-P1), x);
    let s = k.mul_add(R::splat(-P2), a);
    let c = k.mul(R::splat(P3));
    let hi = s.sub(c);
    Reduced {
        k,
        s,
        hi,
        lo: s.sub(hi).sub(c),
        t,
    }
}

/// r = x - k pi/2 as (hi, lo) to within 2^-119 for |x| < 2^20, in every lane, from
/// [`reduce`]'s exact s = x - k P1 - k P2: the rest of pi/2 is R1 + R23 (to 2^-142), k R1
/// is exact and subtracted from s by a two-sum (exact), k R23 (below 2^-68, rounded to
/// within 2^-121) from its error term, and a fast two-sum normalises. Where fused, s is
/// x - k FRAC_PI_2 and the rest Q21 + Q22, with the same bounds. For the lanes within
/// 2^-26 of a nonzero multiple of pi/2, where [`reduce`]'s 2^-86 is too large against
/// |r| (at least 2^-60.5 for doubles below 2^20: relative error below 2^-58.5).
#[inline(always)]
fn reduce_near_multiple<R: Real>(r: &Reduced<R>) -> (R, R) {
    let (r1, r23) = if R::FUSED { (Q21, Q22) } else { (R1, R23) };
    let (h, e) = two_diff(r.s, r.k.mul(R::splat(r1)));
    let e = e.sub(r.k.mul(R::splat(r23)));
    let hi = h.add(e);
    (hi, e.sub(hi.sub(h)))
}

/// a - b = d + e exactly, d = fl(a - b) (Knuth's two-sum, any magnitudes).
#[inline(always)]
fn two_diff<R: Real>(a: R, b: R) -> (R, R) {
    let d = a.sub(b);
    let av = d.add(b);
    let bv = av.sub(d);
    (d, a.sub(av).sub(b.sub(bv)))
}

/// Steps 2 and 3 of [`sin_cos`]: the kernels on the reduced argument and the quadrant.
#[inline(always)]
fn kernel<R: Real>(r: &Reduced<R>) -> (R, R) {
    let (sin_r, cos_r) = reduced_sin_cos(r.hi, r.lo);
    turn(r.t, sin_r, cos_r)
}

/// Step 2 of [`sin_cos`]: (sin r, cos r) for r = hi + lo, |r| <= pi/4.
#[inline(always)]
fn reduced_sin_cos<R: Real>(hi: R, lo: R) -> (R, R) {
    let z = hi.mul(hi);
    let z2 = z.mul(z);
    let ps = estrin(&S, z, z2);
    let pc = estrin(&C, z, z2);
    // -z/2 and -lo (exact) let the products fuse with the sums where the target has FMA;
    // unfused, every value is the same as with the subtractions written out.
    let nhz = R::splat(-0.5).mul(z);
    let nlo = R::splat(-1.0).mul(lo);
    let sin_r = hi.add(z.mul(hi).mul_add(ps, lo.mul_add(nhz, lo)));
    let one = R::splat(1.0);
    let w = one.add(nhz);
    let cos_r = w.add(z2.mul_add(pc, one.sub(w).add(nhz).add(hi.mul(nlo))));
    (sin_r, cos_r)
}

/// (sin r, cos r) for r = hi + lo, |r| < 2^-26 (x near a nonzero multiple of pi/2): the
/// series to their second terms, sin r = hi + (lo - hi z/6) and cos r = 1 - z/2, z = hi^2.
/// The next terms, r^5/120 and r^4/24, are below 2^-104 relative and absolute, far under
/// half an ulp; so are the roundings of hi z/6 (below 2^-52 |hi|/6) and of z. Both results
/// are rounded once from values within a hundredth of an ulp of exact. Four operations
/// deep, against [`reduced_sin_cos`]'s dozen: in [`sin_cos_lanes`] they run beside the
/// other lanes' kernels, which do not wait for the four-part reduction (a crank at exactly
/// 90 degrees would otherwise lengthen its whole vector's chain by that reduction).
#[inline(always)]
fn reduced_sin_cos_near_zero<R: Real>(hi: R, lo: R) -> (R, R) {
    let z = hi.mul(hi);
    let sin_r = hi.add(hi.mul(z).mul_add(R::splat(-1.0 / 6.0), lo));
    (sin_r, z.mul_add(R::splat(-0.5), R::splat(1.0)))
}

/// Step 3 of [`sin_cos`]: (sin x, cos x) from (sin r, cos r) by the quadrant k mod 4 held in
/// t's bits: swap when k is odd, negate sin when k mod 4 is 2 or 3, cos when it is 1 or 2.
#[inline(always)]
fn turn<R: Real>(t: R, sin_r: R, cos_r: R) -> (R, R) {
    let (odd, sin_sign, cos_sign) = R::quadrant(t);
    (
        R::select(odd, cos_r, sin_r).flip(sin_sign),
        R::select(odd, sin_r, cos_r).flip(cos_sign),
    )
}

/// p0 + z p1 + ... + z^5 p5 by Estrin's scheme, (p0 + z p1) + z^2 ((p2 + z p3) +
/// z^2 (p4 + z p5)), each step a [`crate::mul_add`] (one rounding where the target has
/// FMA, which shortens the dependency chain; exactly the unfused value elsewhere).
#[inline(always)]
fn estrin<R: Real>(p: &[f64; 6], z: R, z2: R) -> R {
    let c = |i: usize| R::splat(p[i]);
    let inner = z2.mul_add(z.mul_add(c(5), c(4)), z.mul_add(c(3), c(2)));
    z2.mul_add(inner, z.mul_add(c(1), c(0)))
}
