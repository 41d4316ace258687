//! Numeric constants: exact rationals while they fit in i64, floats otherwise.

use std::cmp::Ordering;
use std::fmt;
use std::hash::{Hash, Hasher};

/// A numeric constant of an expression: an exact rational num/den (den > 0, reduced) or a
/// float (from a decimal literal or from mixing with one).
#[derive(Clone, Copy, Debug)]
pub enum Number {
    /// Exact rational num/den, reduced, den > 0.
    Rational(i64, i64),
    /// A finite floating-point value (never NaN or infinite; -0.0 is stored as 0.0).
    Float(f64),
}

fn gcd(mut a: i128, mut b: i128) -> i128 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a.abs()
}

impl Number {
    /// |self|.
    pub fn abs(self) -> Self {
        if self.is_negative() { -self } else { self }
    }

    /// The integer n.
    pub fn int(n: i64) -> Self {
        Number::Rational(n, 1)
    }

    /// num/den reduced; `None` when den is 0.
    pub fn rational(num: i64, den: i64) -> Option<Self> {
        Self::from_i128(num as i128, den as i128)
    }

    /// num/den reduced; a float when the reduced fraction does not fit in 64 bits; `None`
    /// when den is 0.
    pub(crate) fn from_i128(num: i128, den: i128) -> Option<Self> {
        if den == 0 {
            return None;
        }
        let g = gcd(num, den).max(1);
        let (mut n, mut d) = (num / g, den / g);
        if d < 0 {
            n = -n;
            d = -d;
        }
        match (i64::try_from(n), i64::try_from(d)) {
            (Ok(n), Ok(d)) => Some(Number::Rational(n, d)),
            _ => Some(Number::Float(n as f64 / d as f64)),
        }
    }

    /// num/den reduced, for den > 0 (64-bit arithmetic: the 128-bit division of
    /// [`Self::from_i128`] is several times slower, and most coefficients are small).
    fn from_i64(num: i64, den: i64) -> Option<Self> {
        debug_assert!(den > 0);
        let (mut a, mut b) = (num.unsigned_abs(), den.unsigned_abs());
        while b != 0 {
            (a, b) = (b, a % b);
        }
        // a = gcd(|num|, den) >= 1 divides den > 0, so it fits in i64.
        let g = a.max(1) as i64;
        Some(Number::Rational(num / g, den / g))
    }

    /// A float constant; `None` when not finite. -0.0 becomes 0.0.
    pub fn float(x: f64) -> Option<Self> {
        x.is_finite()
            .then_some(Number::Float(if x == 0.0 { 0.0 } else { x }))
    }

    /// The value as f64.
    pub fn to_f64(self) -> f64 {
        match self {
            Number::Rational(n, d) => n as f64 / d as f64,
            Number::Float(x) => x,
        }
    }

    /// True for exact or float zero.
    pub fn is_zero(self) -> bool {
        self.to_f64() == 0.0
    }

    /// True for exact or float one.
    pub fn is_one(self) -> bool {
        self.to_f64() == 1.0
    }

    /// True when the value is below zero.
    pub fn is_negative(self) -> bool {
        self.to_f64() < 0.0
    }

    /// The integer value, when this is an exact integer.
    pub fn as_integer(self) -> Option<i64> {
        match self {
            Number::Rational(n, 1) => Some(n),
            _ => None,
        }
    }

    /// 1/a; `None` for zero.
    pub fn recip(self) -> Option<Number> {
        match self {
            Number::Rational(n, d) => Self::from_i128(d as i128, n as i128),
            Number::Float(x) => Number::float(1.0 / x),
        }
    }

    /// a^e for an integer e, exact for rationals while it fits; `None` for 0^negative or
    /// an overflowing float.
    pub fn powi(self, e: i64) -> Option<Number> {
        if e < 0 {
            return self.recip()?.powi(-e);
        }
        match self {
            Number::Rational(n, d) => {
                let e32 = u32::try_from(e).ok()?;
                match ((n as i128).checked_pow(e32), (d as i128).checked_pow(e32)) {
                    (Some(a), Some(b)) => Self::from_i128(a, b),
                    _ => Number::float((n as f64 / d as f64).powf(e as f64)),
                }
            }
            Number::Float(x) => {
                Number::float(x.powi(e.clamp(i32::MIN as i64, i32::MAX as i64) as i32))
            }
        }
    }

    /// True when this is a float (inexact) constant.
    pub fn is_float(self) -> bool {
        matches!(self, Number::Float(_))
    }
}

impl Number {
    /// a + b, exact when both are rational and the result fits; `None` when the sum of
    /// floats overflows to infinity (never a silent value: the arena reports it).
    pub fn checked_add(self, o: Number) -> Option<Number> {
        match (self, o) {
            // Integers (the common case) need no reduction.
            (Number::Rational(a, 1), Number::Rational(c, 1)) if a.checked_add(c).is_some() => {
                Some(Number::Rational(a + c, 1))
            }
            // In 64 bits when the cross products fit (most coefficients are small), else in 128.
            (Number::Rational(a, b), Number::Rational(c, d)) => {
                let narrow = if b == d {
                    a.checked_add(c).map(|num| (num, b))
                } else {
                    a.checked_mul(d)
                        .zip(c.checked_mul(b))
                        .and_then(|(x, y)| x.checked_add(y))
                        .zip(b.checked_mul(d))
                };
                match narrow {
                    Some((num, den)) => Self::from_i64(num, den),
                    None => Self::from_i128(
                        a as i128 * d as i128 + c as i128 * b as i128,
                        b as i128 * d as i128,
                    ),
                }
            }
            _ => Number::float(self.to_f64() + o.to_f64()),
        }
    }

    /// a * b, exact when both are rational and the result fits; `None` when the product
    /// of floats overflows to infinity.
    pub fn checked_mul(self, o: Number) -> Option<Number> {
        match (self, o) {
            (Number::Rational(a, 1), Number::Rational(c, 1)) if a.checked_mul(c).is_some() => {
                Some(Number::Rational(a * c, 1))
            }
            (Number::Rational(a, b), Number::Rational(c, d)) => {
                match (a.checked_mul(c), b.checked_mul(d)) {
                    (Some(n), Some(m)) => Self::from_i64(n, m),
                    _ => Self::from_i128(a as i128 * c as i128, b as i128 * d as i128),
                }
            }
            _ => Number::float(self.to_f64() * o.to_f64()),
        }
    }
}

impl std::ops::Neg for Number {
    type Output = Number;
    /// -a (exact: negation cannot overflow; -0.0 stays 0.0).
    fn neg(self) -> Number {
        match self {
            Number::Rational(n, d) => Self::from_i128(-(n as i128), d as i128)
                .expect("the denominator of a Number is never 0"),
            Number::Float(x) => Number::Float(if x == 0.0 { 0.0 } else { -x }),
        }
    }
}

impl PartialEq for Number {
    fn eq(&self, o: &Self) -> bool {
        match (self, o) {
            (Number::Rational(a, b), Number::Rational(c, d)) => a == c && b == d,
            (Number::Float(a), Number::Float(b)) => a.to_bits() == b.to_bits(),
            _ => false,
        }
    }
}
impl Eq for Number {}

impl Hash for Number {
    fn hash<H: Hasher>(&self, h: &mut H) {
        match self {
            Number::Rational(a, b) => (0u8, a, b).hash(h),
            Number::Float(x) => (1u8, x.to_bits()).hash(h),
        }
    }
}

impl PartialOrd for Number {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Number {
    fn cmp(&self, o: &Self) -> Ordering {
        self.to_f64().total_cmp(&o.to_f64())
    }
}

impl fmt::Display for Number {
    /// Rationals as `n` or `n/d`; floats in Rust's shortest round-trip form, always with a
    /// decimal point or exponent so they read back as floats.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Number::Rational(n, 1) => write!(f, "{n}"),
            Number::Rational(n, d) => write!(f, "{n}/{d}"),
            Number::Float(x) => {
                let s = format!("{x:?}");
                write!(f, "{s}")
            }
        }
    }
}

#[cfg(test)]
mod overflow_tests {
    use super::Number;

    /// The checked operations agree with f64 arithmetic where it is finite, stay exact for
    /// rationals, and refuse (None) exactly where the f64 result is infinite.
    #[test]
    fn checked_operations_refuse_exactly_the_infinite_results() {
        let values = [
            Number::int(0),
            Number::int(-3),
            Number::rational(7, 2).unwrap(),
            Number::int(i64::MAX),
            Number::Float(1.5),
            Number::Float(-2.5e-300),
            Number::Float(1e154),
            Number::Float(1e200),
            Number::Float(-1.7e308),
            Number::Float(f64::MAX),
        ];
        for &a in &values {
            for &b in &values {
                let (s, p) = (a.to_f64() + b.to_f64(), a.to_f64() * b.to_f64());
                match a.checked_add(b) {
                    Some(r) => assert_eq!(r.to_f64(), s, "{a} + {b}"),
                    None => assert!(s.is_infinite(), "{a} + {b} refused but is {s}"),
                }
                assert_eq!(a.checked_add(b).is_none(), s.is_infinite(), "{a} + {b}");
                match a.checked_mul(b) {
                    Some(r) => assert_eq!(r.to_f64(), p, "{a} * {b}"),
                    None => assert!(p.is_infinite(), "{a} * {b} refused but is {p}"),
                }
                assert_eq!(a.checked_mul(b).is_none(), p.is_infinite(), "{a} * {b}");
            }
        }
        // Rationals stay exact: 7/2 + (-3) = 1/2.
        let half = Number::rational(7, 2).unwrap().checked_add(Number::int(-3));
        assert_eq!(half, Number::rational(1, 2));
        assert_eq!(
            -Number::rational(1, 2).unwrap(),
            Number::rational(-1, 2).unwrap()
        );
        assert_eq!(-Number::Float(0.0), Number::Float(0.0));
    }
}

#[cfg(test)]
mod fast_path_tests {
    use super::Number;

    /// The 64-bit fast paths of addition and multiplication give the reduced fraction the
    /// 128-bit route gives, over a grid of signs, equal and unequal denominators, common
    /// factors and values at the edge of i64.
    #[test]
    fn fast_paths_agree_with_the_128_bit_route() {
        let parts = [
            0,
            1,
            -1,
            2,
            -3,
            4,
            6,
            -9,
            12,
            1 << 31,
            -(1 << 40),
            i64::MAX,
            i64::MIN + 1,
        ];
        let dens = [1, 2, 3, 4, 6, 12, 1 << 31, i64::MAX];
        let mut values = Vec::new();
        for &n in &parts {
            for &d in &dens {
                values.push(Number::rational(n, d).unwrap());
            }
        }
        let wide = |a: Number, b: Number, add: bool| match (a, b) {
            (Number::Rational(p, q), Number::Rational(r, s)) => {
                let (num, den) = if add {
                    (
                        p as i128 * s as i128 + r as i128 * q as i128,
                        q as i128 * s as i128,
                    )
                } else {
                    (p as i128 * r as i128, q as i128 * s as i128)
                };
                Number::from_i128(num, den)
            }
            _ => unreachable!("the grid is rational"),
        };
        for &a in &values {
            for &b in &values {
                assert_eq!(a.checked_add(b), wide(a, b, true), "{a:?} + {b:?}");
                assert_eq!(a.checked_mul(b), wide(a, b, false), "{a:?} * {b:?}");
            }
        }
    }
}
