//! The arithmetic that [`crate::sin_cos`](fn@crate::sin_cos)'s reduction and kernels are
//! written in, over one `f64` or several lanes of a vector register at once
//! ([`crate::sin_cos_lanes`]): each operation rounds the same way in every implementation,
//! so a lane's result is bit for bit the scalar one.

/// A real number or a vector of them, with the operations `sin_cos` needs.
pub(crate) trait Real: Copy {
    /// Whether [`Real::mul_add`] rounds once (fused), as [`crate::mul_add`] does on this
    /// target.
    const FUSED: bool;
    /// v in every lane.
    fn splat(v: f64) -> Self;
    /// a + b.
    fn add(self, b: Self) -> Self;
    /// a - b.
    fn sub(self, b: Self) -> Self;
    /// a b.
    fn mul(self, b: Self) -> Self;
    /// a b + c, rounded once exactly where [`crate::mul_add`] is (FMA targets).
    fn mul_add(self, b: Self, c: Self) -> Self;
    /// `a` in the lanes where `mask` is all ones, `b` where it is all zeros (every mask
    /// here is one or the other in each lane: comparisons, and the quadrant's odd mask).
    fn select(mask: Self, a: Self, b: Self) -> Self;
    /// a with its sign bit flipped where `sign` is -0.0 (`sign` is 0.0 or -0.0: the bits of
    /// the two are xor-ed).
    fn flip(self, sign: Self) -> Self;
    /// From the bits of t = x 2/pi + 1.5 2^52, whose low bits hold k mod 4: (an all-ones
    /// mask where k is odd, the sign bit where k mod 4 is 2 or 3, the sign bit where
    /// k mod 4 is 1 or 2).
    fn quadrant(t: Self) -> (Self, Self, Self);
}

impl Real for f64 {
    const FUSED: bool = crate::FUSED;
    #[inline(always)]
    fn splat(v: f64) -> f64 {
        v
    }
    #[inline(always)]
    fn add(self, b: f64) -> f64 {
        self + b
    }
    #[inline(always)]
    fn sub(self, b: f64) -> f64 {
        self - b
    }
    #[inline(always)]
    fn mul(self, b: f64) -> f64 {
        self * b
    }
    #[inline(always)]
    fn mul_add(self, b: f64, c: f64) -> f64 {
        crate::mul_add(self, b, c)
    }
    #[inline(always)]
    fn select(mask: f64, a: f64, b: f64) -> f64 {
        let m = mask.to_bits();
        f64::from_bits((a.to_bits() & m) | (b.to_bits() & !m))
    }
    #[inline(always)]
    fn flip(self, sign: f64) -> f64 {
        f64::from_bits(self.to_bits() ^ sign.to_bits())
    }
    #[inline(always)]
    fn quadrant(t: f64) -> (f64, f64, f64) {
        let q = t.to_bits();
        (
            f64::from_bits((q & 1).wrapping_neg()),
            f64::from_bits((q & 2) << 62),
            f64::from_bits((q.wrapping_add(1) & 2) << 62),
        )
    }
}
