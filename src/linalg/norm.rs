//! Maximum norms for convergence and accuracy tests that never hide a NaN.
//!
//! `f64::max` returns the other operand when one is NaN, so the usual
//! `fold(0.0, |a, v| a.max(v.abs()))` skips a NaN entry: a residual with one NaN row reads as
//! small, and a Newton iteration or an error estimate "converges" on it. These propagate NaN
//! instead (and infinity, as `max` does), so that a test `norm <= tolerance` fails and a
//! test `!norm.is_finite()` catches it.

/// The larger of `a` and `b`, NaN when either is NaN.
#[inline]
pub fn max_nan(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// |x|_inf = max_i |x_i| (0 for an empty slice), NaN when any entry is NaN.
#[inline]
pub fn inf_norm(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |a, v| max_nan(a, v.abs()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_nan_is_never_hidden() {
        assert_eq!(max_nan(1.0, 2.0), 2.0);
        assert!(max_nan(1.0, f64::NAN).is_nan() && max_nan(f64::NAN, 1.0).is_nan());
        assert_eq!(inf_norm(&[1.0, -3.0, 2.0]), 3.0);
        assert_eq!(inf_norm(&[]), 0.0);
        assert!(inf_norm(&[1e-20, f64::NAN, 0.0]).is_nan());
        // f64::max would skip the NaN and return 0.
        assert_eq!(
            [f64::NAN, 0.0].iter().fold(0.0_f64, |a, v| a.max(v.abs())),
            0.0
        );
    }
}
