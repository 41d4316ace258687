//! [`Real`] over the lanes of x86-64 vector registers, for [`crate::sin_cos_lanes`]: two
//! lanes in an SSE2 register (every x86-64 CPU has SSE2), four in an AVX2 one where the
//! build enables `avx2` (e.g. `-C target-cpu=native`) or the CPU has it
//! ([`crate::avx2::sin_cos_lanes`]). Written with `core::arch`'s
//! intrinsics rather than left to the auto-vectoriser, which split four lanes into pairs and
//! moved them between registers (the four lanes took as long as four scalar calls).
//!
//! Each operation is the lane-wise IEEE operation of the scalar code, fused exactly where
//! [`crate::mul_add`] is (the `fma` target feature), so each lane is bit for bit the scalar
//! [`crate::sin_cos`](fn@crate::sin_cos).
//!
//! Safety: the intrinsics are `unsafe` to call where the compiler cannot see that the CPU
//! has their instruction set. SSE2 is part of x86-64 itself. The FMA intrinsics are
//! compiled only where the build enables `fma` for all its code (`cfg(target_feature)`).
//! [`F64x4`] is used only where the build enables `avx2` for all its code, or inside
//! [`crate::avx2::sin_cos_lanes`], a function compiled with `avx2` that may be called only on
//! a CPU that has it; its operations are `#[inline(always)]`, so their instructions are
//! compiled into that function. Every call here thus runs on a CPU that has them.

use core::arch::x86_64::*;

use crate::real::Real;

/// Vectors of W lanes: construction, extraction and the fast-path test of `sin_cos`.
pub(crate) trait Vector: Real {
    /// Lanes per vector.
    const W: usize;
    /// The vector of `x[..W]`.
    fn from_lanes(x: &[f64; 4]) -> Self;
    /// The lanes, in `out[..W]`.
    fn to_lanes(self, out: &mut [f64; 4]);
    /// Bit i set where lane i is on `sin_cos`'s inline path: |x| < `bound` (false for NaN and
    /// infinities) and x is not -0.0.
    fn in_range(x: Self, bound: f64) -> u32;
    /// All ones where |hi| < `tiny` and k != 0 (x near a nonzero multiple of pi/2).
    fn near_multiple(hi: Self, k: Self, tiny: f64) -> Self;
    /// Bit i set where lane i is on `sin_cos`'s fast path: in range (as [`Vector::in_range`])
    /// and not near a nonzero multiple of pi/2 (as [`Vector::near_multiple`]).
    fn ordinary(x: Self, k: Self, hi: Self, bound: f64, tiny: f64) -> u32;
}

/// Two lanes in an SSE2 register.
#[derive(Clone, Copy)]
pub(crate) struct F64x2(__m128d);

impl Real for F64x2 {
    const FUSED: bool = cfg!(target_feature = "fma");
    #[inline(always)]
    fn splat(v: f64) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x2(_mm_set1_pd(v)) }
    }
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x2(_mm_add_pd(self.0, b.0)) }
    }
    #[inline(always)]
    fn sub(self, b: Self) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x2(_mm_sub_pd(self.0, b.0)) }
    }
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x2(_mm_mul_pd(self.0, b.0)) }
    }
    #[inline(always)]
    fn mul_add(self, b: Self, c: Self) -> Self {
        #[cfg(target_feature = "fma")]
        // SAFETY: see the module docs.
        unsafe {
            F64x2(_mm_fmadd_pd(self.0, b.0, c.0))
        }
        #[cfg(not(target_feature = "fma"))]
        {
            self.mul(b).add(c)
        }
    }
    #[inline(always)]
    fn select(mask: Self, a: Self, b: Self) -> Self {
        // SAFETY: see the module docs.
        unsafe {
            F64x2(_mm_or_pd(
                _mm_and_pd(mask.0, a.0),
                _mm_andnot_pd(mask.0, b.0),
            ))
        }
    }
    #[inline(always)]
    fn flip(self, sign: Self) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x2(_mm_xor_pd(self.0, sign.0)) }
    }
    #[inline(always)]
    fn quadrant(t: Self) -> (Self, Self, Self) {
        // SAFETY: see the module docs.
        unsafe {
            let q = _mm_castpd_si128(t.0);
            let (one, two) = (_mm_set1_epi64x(1), _mm_set1_epi64x(2));
            let odd = _mm_sub_epi64(_mm_setzero_si128(), _mm_and_si128(q, one));
            let sin_sign = _mm_slli_epi64::<62>(_mm_and_si128(q, two));
            let cos_sign = _mm_slli_epi64::<62>(_mm_and_si128(_mm_add_epi64(q, one), two));
            (
                F64x2(_mm_castsi128_pd(odd)),
                F64x2(_mm_castsi128_pd(sin_sign)),
                F64x2(_mm_castsi128_pd(cos_sign)),
            )
        }
    }
}

impl Vector for F64x2 {
    const W: usize = 2;
    #[inline(always)]
    fn from_lanes(x: &[f64; 4]) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x2(_mm_set_pd(x[1], x[0])) }
    }
    #[inline(always)]
    fn to_lanes(self, out: &mut [f64; 4]) {
        // SAFETY: see the module docs.
        unsafe {
            out[0] = _mm_cvtsd_f64(self.0);
            out[1] = _mm_cvtsd_f64(_mm_unpackhi_pd(self.0, self.0));
        }
    }
    #[inline(always)]
    fn in_range(x: Self, bound: f64) -> u32 {
        // SAFETY: see the module docs.
        unsafe {
            let sign = _mm_set1_pd(-0.0);
            let in_range = _mm_cmplt_pd(_mm_andnot_pd(sign, x.0), _mm_set1_pd(bound));
            // Sign bit set exactly where x is -0.0 (x == 0 leaves x's own bits).
            let negative_zero = _mm_and_pd(_mm_cmpeq_pd(x.0, _mm_setzero_pd()), x.0);
            _mm_movemask_pd(_mm_andnot_pd(negative_zero, in_range)) as u32
        }
    }
    #[inline(always)]
    fn near_multiple(hi: Self, k: Self, tiny: f64) -> Self {
        // SAFETY: see the module docs.
        unsafe {
            let sign = _mm_set1_pd(-0.0);
            let small = _mm_cmplt_pd(_mm_andnot_pd(sign, hi.0), _mm_set1_pd(tiny));
            F64x2(_mm_andnot_pd(_mm_cmpeq_pd(k.0, _mm_setzero_pd()), small))
        }
    }
    #[inline(always)]
    fn ordinary(x: Self, k: Self, hi: Self, bound: f64, tiny: f64) -> u32 {
        // SAFETY: see the module docs.
        unsafe {
            let sign = _mm_set1_pd(-0.0);
            let in_range = _mm_cmplt_pd(_mm_andnot_pd(sign, x.0), _mm_set1_pd(bound));
            let far = _mm_cmpge_pd(_mm_andnot_pd(sign, hi.0), _mm_set1_pd(tiny));
            let zero = _mm_setzero_pd();
            let negative_zero = _mm_and_pd(_mm_cmpeq_pd(x.0, zero), x.0);
            // k = 0: r = x exactly, small or not (except -0.0).
            let exact = _mm_andnot_pd(negative_zero, _mm_cmpeq_pd(k.0, zero));
            _mm_movemask_pd(_mm_and_pd(in_range, _mm_or_pd(far, exact))) as u32
        }
    }
}

/// Four lanes in an AVX2 register.
#[derive(Clone, Copy)]
pub(crate) struct F64x4(__m256d);

impl Real for F64x4 {
    const FUSED: bool = cfg!(target_feature = "fma");
    #[inline(always)]
    fn splat(v: f64) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x4(_mm256_set1_pd(v)) }
    }
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x4(_mm256_add_pd(self.0, b.0)) }
    }
    #[inline(always)]
    fn sub(self, b: Self) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x4(_mm256_sub_pd(self.0, b.0)) }
    }
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x4(_mm256_mul_pd(self.0, b.0)) }
    }
    #[inline(always)]
    fn mul_add(self, b: Self, c: Self) -> Self {
        #[cfg(target_feature = "fma")]
        // SAFETY: see the module docs.
        unsafe {
            F64x4(_mm256_fmadd_pd(self.0, b.0, c.0))
        }
        #[cfg(not(target_feature = "fma"))]
        {
            self.mul(b).add(c)
        }
    }
    #[inline(always)]
    fn select(mask: Self, a: Self, b: Self) -> Self {
        // SAFETY: see the module docs.
        // Every mask here is all ones or all zeros per lane, so blending on the sign bit is
        // the same selection, one instruction instead of three (two steps).
        unsafe { F64x4(_mm256_blendv_pd(b.0, a.0, mask.0)) }
    }
    #[inline(always)]
    fn flip(self, sign: Self) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x4(_mm256_xor_pd(self.0, sign.0)) }
    }
    #[inline(always)]
    fn quadrant(t: Self) -> (Self, Self, Self) {
        // SAFETY: see the module docs.
        unsafe {
            let q = _mm256_castpd_si256(t.0);
            let (one, two) = (_mm256_set1_epi64x(1), _mm256_set1_epi64x(2));
            let odd = _mm256_sub_epi64(_mm256_setzero_si256(), _mm256_and_si256(q, one));
            let sin_sign = _mm256_slli_epi64::<62>(_mm256_and_si256(q, two));
            let cos_sign = _mm256_slli_epi64::<62>(_mm256_and_si256(_mm256_add_epi64(q, one), two));
            (
                F64x4(_mm256_castsi256_pd(odd)),
                F64x4(_mm256_castsi256_pd(sin_sign)),
                F64x4(_mm256_castsi256_pd(cos_sign)),
            )
        }
    }
}

impl Vector for F64x4 {
    const W: usize = 4;
    #[inline(always)]
    fn from_lanes(x: &[f64; 4]) -> Self {
        // SAFETY: see the module docs.
        unsafe { F64x4(_mm256_set_pd(x[3], x[2], x[1], x[0])) }
    }
    #[inline(always)]
    fn to_lanes(self, out: &mut [f64; 4]) {
        // SAFETY: see the module docs.
        unsafe {
            let (low, high) = (
                _mm256_castpd256_pd128(self.0),
                _mm256_extractf128_pd::<1>(self.0),
            );
            F64x2(low).to_lanes(out);
            out[2] = _mm_cvtsd_f64(high);
            out[3] = _mm_cvtsd_f64(_mm_unpackhi_pd(high, high));
        }
    }
    #[inline(always)]
    fn in_range(x: Self, bound: f64) -> u32 {
        // SAFETY: see the module docs.
        unsafe {
            let sign = _mm256_set1_pd(-0.0);
            let in_range =
                _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_andnot_pd(sign, x.0), _mm256_set1_pd(bound));
            let zero = _mm256_cmp_pd::<_CMP_EQ_OQ>(x.0, _mm256_setzero_pd());
            let negative_zero = _mm256_and_pd(zero, x.0);
            _mm256_movemask_pd(_mm256_andnot_pd(negative_zero, in_range)) as u32
        }
    }
    #[inline(always)]
    fn near_multiple(hi: Self, k: Self, tiny: f64) -> Self {
        // SAFETY: see the module docs.
        unsafe {
            let sign = _mm256_set1_pd(-0.0);
            let small =
                _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_andnot_pd(sign, hi.0), _mm256_set1_pd(tiny));
            let k_zero = _mm256_cmp_pd::<_CMP_EQ_OQ>(k.0, _mm256_setzero_pd());
            F64x4(_mm256_andnot_pd(k_zero, small))
        }
    }
    #[inline(always)]
    fn ordinary(x: Self, k: Self, hi: Self, bound: f64, tiny: f64) -> u32 {
        // SAFETY: see the module docs.
        unsafe {
            let sign = _mm256_set1_pd(-0.0);
            let in_range =
                _mm256_cmp_pd::<_CMP_LT_OQ>(_mm256_andnot_pd(sign, x.0), _mm256_set1_pd(bound));
            let far =
                _mm256_cmp_pd::<_CMP_GE_OQ>(_mm256_andnot_pd(sign, hi.0), _mm256_set1_pd(tiny));
            let zero = _mm256_setzero_pd();
            let negative_zero = _mm256_and_pd(_mm256_cmp_pd::<_CMP_EQ_OQ>(x.0, zero), x.0);
            // k = 0: r = x exactly, small or not (except -0.0).
            let exact = _mm256_andnot_pd(negative_zero, _mm256_cmp_pd::<_CMP_EQ_OQ>(k.0, zero));
            _mm256_movemask_pd(_mm256_and_pd(in_range, _mm256_or_pd(far, exact))) as u32
        }
    }
}
