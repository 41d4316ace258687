//! Distance between doubles, in units in the last place.

/// The number of doubles between a and b (0 for two NaNs, u64::MAX for a NaN and a number).
pub fn ulps_apart(a: f64, b: f64) -> u64 {
    if a.is_nan() || b.is_nan() {
        return if a.is_nan() && b.is_nan() {
            0
        } else {
            u64::MAX
        };
    }
    let ord = |x: f64| {
        let b = x.to_bits() as i64;
        if b < 0 { i64::MIN - b } else { b }
    };
    (i128::from(ord(a)) - i128::from(ord(b))).unsigned_abs() as u64
}
