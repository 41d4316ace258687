//! The fused reduction (targets whose `mul_add` rounds once) against the unfused one, in
//! every build: `Fused` and `Plain` are [`Real`]s over one f64 whose `mul_add` is
//! `f64::mul_add` (one rounding, in software where the CPU has no FMA) and the plain product
//! and sum. The two routes take pi/2 in different parts, so they agree only if both are
//! right: each represents r = x - k pi/2 to within 2^-86 on the fast path (the fused one to
//! 2^-89) and to 2^-119 near a nonzero multiple of pi/2.

use super::{BOUND, Reduced, TINY, reduce, reduce_near_multiple, reduced_sin_cos, turn};
use crate::real::Real;

macro_rules! scalar_real {
    ($name:ident, $fused:expr, $mul_add:expr) => {
        #[derive(Clone, Copy)]
        struct $name(f64);

        impl Real for $name {
            const FUSED: bool = $fused;
            fn splat(v: f64) -> Self {
                Self(v)
            }
            fn add(self, b: Self) -> Self {
                Self(self.0 + b.0)
            }
            fn sub(self, b: Self) -> Self {
                Self(self.0 - b.0)
            }
            fn mul(self, b: Self) -> Self {
                Self(self.0 * b.0)
            }
            fn mul_add(self, b: Self, c: Self) -> Self {
                let f: fn(f64, f64, f64) -> f64 = $mul_add;
                Self(f(self.0, b.0, c.0))
            }
            fn select(mask: Self, a: Self, b: Self) -> Self {
                Self(f64::select(mask.0, a.0, b.0))
            }
            fn flip(self, sign: Self) -> Self {
                Self(self.0.flip(sign.0))
            }
            fn quadrant(t: Self) -> (Self, Self, Self) {
                let (a, b, c) = f64::quadrant(t.0);
                (Self(a), Self(b), Self(c))
            }
        }
    };
}

scalar_real!(Fused, true, |a, b, c| a.mul_add(b, c));
scalar_real!(Plain, false, |a, b, c| a * b + c);

/// (hi, lo) of both routes at x: the fast path's, or the four-part reduction's where x is
/// within 2^-26 of a nonzero multiple of pi/2 (as `sin_cos` chooses, by the plain route).
fn both(x: f64) -> ((f64, f64), (f64, f64), bool) {
    let f: Reduced<Fused> = reduce(Fused(x));
    let p: Reduced<Plain> = reduce(Plain(x));
    assert_eq!(f.k.0, p.k.0, "k at {x:e}");
    assert_eq!(f.t.0.to_bits(), p.t.0.to_bits(), "t at {x:e}");
    let near = p.hi.0.abs() < TINY && p.k.0 != 0.0;
    if near {
        let ((fh, fl), (ph, pl)) = (reduce_near_multiple(&f), reduce_near_multiple(&p));
        ((fh.0, fl.0), (ph.0, pl.0), true)
    } else {
        ((f.hi.0, f.lo.0), (p.hi.0, p.lo.0), false)
    }
}

/// |(a.0 + a.1) - (b.0 + b.1)|, the his' difference exact (they are within a factor of 2).
fn gap(a: (f64, f64), b: (f64, f64)) -> f64 {
    ((a.0 - b.0) + (a.1 - b.1)).abs()
}

/// Doubles in [-a, a] (xorshift64*, fixed seed), and near every multiple of pi/2 up to
/// 3000: the nearest doubles and those 1e-8 and 1.4e-8 away.
fn arguments() -> impl Iterator<Item = f64> {
    let mut seed = 7_u64;
    let uniform = [10.0, 1000.0, BOUND * (1.0 - f64::EPSILON)]
        .into_iter()
        .flat_map(move |a| {
            (0..100_000).map(move |_| {
                seed ^= seed >> 12;
                seed ^= seed << 25;
                seed ^= seed >> 27;
                let u = (seed.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64;
                (2.0 * u / (1u64 << 53) as f64 - 1.0) * a
            })
        });
    let near = (1..=3000).flat_map(|k| {
        let m = f64::from(k) * core::f64::consts::FRAC_PI_2;
        let next = |d: i64| f64::from_bits((m.to_bits() as i64 + d) as u64);
        [
            next(-1),
            m,
            next(1),
            m - 1.4e-8,
            m - 1e-8,
            m + 1e-8,
            m + 1.4e-8,
        ]
    });
    uniform.chain(near)
}

#[test]
fn the_fused_and_plain_reductions_agree() {
    let (mut fast, mut near) = (0.0_f64, 0.0_f64);
    for x in arguments() {
        let (f, p, is_near) = both(x);
        if is_near {
            near = near.max(gap(f, p));
        } else {
            fast = fast.max(gap(f, p));
        }
    }
    // The bounds of the two routes added: 2^-86 + 2^-89 on the fast path, 2^-119 each
    // near the multiples. A wrong constant or an inexact fused step is off by 2^-70 or more.
    assert!(fast <= 2f64.powi(-85), "fast path: {fast:e}");
    assert!(near <= 2f64.powi(-118), "near multiples: {near:e}");
}

#[test]
fn the_fused_kernels_are_faithful_beside_the_plain_ones() {
    // Both results are faithful (within 1 ulp of the exact value, on the same side or
    // not), so they are the same double or neighbours.
    for x in arguments() {
        let (f, p, is_near) = both(x);
        if is_near {
            continue; // The short kernels are checked near the multiples in tests/.
        }
        let (fs, fc) = reduced_sin_cos(Fused(f.0), Fused(f.1));
        let (ps, pc) = reduced_sin_cos(Plain(p.0), Plain(p.1));
        let t = reduce(Plain(x)).t;
        let ((fs, fc), (ps, pc)) = (turn(Fused(t.0), fs, fc), turn(t, ps, pc));
        for (a, b) in [(fs.0, ps.0), (fc.0, pc.0)] {
            let apart = (a.to_bits() as i64 - b.to_bits() as i64).unsigned_abs();
            assert!(apart <= 1 || a == b, "{a:e} and {b:e} at x = {x:e}");
        }
    }
}
