//! A linear form in the rates, as M from the momenta reads it (`mass_matrix.rs`,
//! `running_rows.rs`), and the exact running sum of its coefficients.

use std::rc::Rc;

use crate::algebra::expr::Id;
use crate::number::Number;

/// A linear form in the rates: (rate index j, coefficient d, rate-free monomial s) per
/// term, s = `None` for 1; one term per rate, sorted by rate index.
pub(crate) type LinearForm = Rc<Vec<(usize, Number, Option<Id>)>>;

/// A running sum of coefficients equal to adding them one by one with
/// [`Number::checked_add`], without reducing a fraction at each addition: the numerator is
/// kept over a denominator that every rational added so far divides, and reduced when the
/// sum is read or when it leaves 64 bits (where `checked_add` would turn to a float).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Sum {
    Exact { num: i128, den: i64 },
    Float(f64),
}

impl Sum {
    fn new(x: Number) -> Sum {
        match x {
            Number::Rational(num, den) => Sum::Exact {
                num: num.into(),
                den,
            },
            Number::Float(f) => Sum::Float(f),
        }
    }

    /// Whether the sum has turned to a float.
    pub(crate) fn is_float(self) -> bool {
        matches!(self, Sum::Float(_))
    }

    /// The sum as `checked_add` would hold it.
    pub(crate) fn value(self) -> Option<Number> {
        match self {
            Sum::Exact { num, den } => Self::reduced(num, den),
            Sum::Float(f) => Number::float(f),
        }
    }

    /// num/den reduced, a float when that does not fit in 64 bits (as `checked_add`).
    fn reduced(num: i128, den: i64) -> Option<Number> {
        Number::from_i128(num, den.into())
    }

    /// The product c d of two coefficients as a sum (unreduced when both are rational and
    /// the products of numerators and denominators fit in 64 bits).
    pub(crate) fn product(c: Number, d: Number) -> Option<Sum> {
        match Self::parts(c, d) {
            Some((num, den)) => Some(Sum::Exact {
                num: num.into(),
                den,
            }),
            None => Some(Sum::new(c.checked_mul(d)?)),
        }
    }

    /// c d as an unreduced fraction p/q (q > 0) when both fit in 64 bits.
    fn parts(c: Number, d: Number) -> Option<(i64, i64)> {
        match (c, d) {
            (Number::Rational(a, b), Number::Rational(x, y)) => {
                Some((a.checked_mul(x)?, b.checked_mul(y)?))
            }
            _ => None,
        }
    }

    /// Adds c d; `None` when a float sum or product overflows (as `checked_mul` and
    /// `checked_add` report). The exact value added is that of `checked_mul(c, d)` whenever
    /// the unreduced fraction fits, so the sum is the one of adding those products.
    pub(crate) fn add_product(&mut self, c: Number, d: Number) -> Option<()> {
        match (*self, Self::parts(c, d)) {
            (Sum::Exact { num, den }, Some((p, q))) => {
                let (num, den) = if q == den {
                    (num + i128::from(p), den)
                } else if q == 1 {
                    (num + i128::from(p) * i128::from(den), den)
                } else if den % q == 0 {
                    (num + i128::from(p) * i128::from(den / q), den)
                } else {
                    let v = Self::reduced(num, den)?.checked_add(c.checked_mul(d)?)?;
                    *self = Sum::new(v);
                    return Some(());
                };
                *self = if i64::try_from(num).is_ok() {
                    Sum::Exact { num, den }
                } else {
                    // Outside 64 bits: reduce, as checked_add would have (a float if the
                    // reduced fraction does not fit either).
                    Sum::new(Self::reduced(num, den)?)
                };
            }
            (Sum::Exact { num, den }, None) => {
                *self = Sum::new(Self::reduced(num, den)?.checked_add(c.checked_mul(d)?)?);
            }
            (Sum::Float(f), _) => {
                *self = Sum::new(Number::Float(f).checked_add(c.checked_mul(d)?)?)
            }
        }
        Some(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The running sum gives what adding one by one with `checked_add` gives: over
    /// sequences of equal, dividing and coprime denominators, sums that leave 64 bits (and
    /// turn to floats there), and floats mixed in.
    #[test]
    fn running_sums_equal_sums_added_one_by_one() {
        let r = |n, d| Number::rational(n, d).unwrap();
        let big = Number::int(i64::MAX / 2);
        let sequences: Vec<Vec<Number>> = vec![
            vec![r(1, 2), r(1, 2), Number::int(1), r(3, 2), Number::int(-4)],
            vec![Number::int(3), r(1, 6), r(1, 3), r(5, 7), r(-2, 21)],
            vec![r(1, 4), r(1, 2), r(3, 4), r(1, 8), r(-7, 8)],
            vec![big, big, big, r(1, 2), Number::int(-1)],
            vec![r(i64::MAX, 3), r(i64::MAX, 3), r(1, 5)],
            vec![r(1, 3), Number::Float(0.25), r(1, 3), Number::int(2)],
            vec![Number::Float(1e308), Number::Float(1e308)],
        ];
        for seq in sequences {
            let want = seq[1..]
                .iter()
                .try_fold(seq[0], |acc, &x| acc.checked_add(x));
            let one = Number::int(1);
            let mut sum = Sum::product(seq[0], one).unwrap();
            let got = seq[1..]
                .iter()
                .try_for_each(|&x| sum.add_product(x, one))
                .and_then(|()| sum.value());
            assert_eq!(got, want, "{seq:?}");
            // The same sums as products c d with d = 1/2 (added unreduced).
            let half = Number::rational(1, 2).unwrap();
            let want = seq
                .iter()
                .map(|&x| x.checked_mul(half))
                .collect::<Option<Vec<_>>>()
                .and_then(|v| v[1..].iter().try_fold(v[0], |acc, &x| acc.checked_add(x)));
            let mut sum = Sum::product(seq[0], half).unwrap();
            let got = seq[1..]
                .iter()
                .try_for_each(|&x| sum.add_product(x, half))
                .and_then(|()| sum.value());
            assert_eq!(got, want, "{seq:?} halved");
        }
    }
}
