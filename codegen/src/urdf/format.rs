//! Numbers as the declaration writes them: the shortest text that reads back as the same
//! f64, and angles at multiples of pi/2 as `pi/2`, `pi`, ... so that the algebra folds
//! their cosines and sines to exact 0 and +-1.

use std::f64::consts::FRAC_PI_2;

/// How far an angle may be from a multiple of pi/2 to be written as one, rad (URDF files
/// print 1.5707963267948966, or 1.570796326795 rounded to 12 decimals).
pub(crate) const ANGLE_SNAP: f64 = 1e-12;

/// Largest multiple of pi/2 written symbolically (larger angles are written as numbers).
const MAX_QUARTER_TURNS: f64 = 64.0;

/// `x` as the shortest decimal that parses back to the same f64 (Rust's `{:?}`, without a
/// trailing `.0`): `0.333`, `87`, `1e-5`; both zeros are `0`.
pub(crate) fn number(x: f64) -> String {
    if x == 0.0 {
        return "0".to_string();
    }
    let s = format!("{x:?}");
    match s.strip_suffix(".0") {
        Some(integer) => integer.to_string(),
        None => s,
    }
}

/// An angle: within [`ANGLE_SNAP`] of a nonzero multiple k of pi/2, `pi/2`, `-pi/2`, `pi`,
/// `3*pi/2`, `2*pi`, ...; otherwise [`number`].
pub(crate) fn angle(x: f64) -> String {
    let k = (x / FRAC_PI_2).round();
    if k == 0.0 || k.abs() > MAX_QUARTER_TURNS || (x - k * FRAC_PI_2).abs() > ANGLE_SNAP {
        return number(x);
    }
    // |k| <= 64: exact as an integer.
    let k = k as i64;
    match (k % 2 == 0, k / 2) {
        (true, 1) => "pi".to_string(),
        (true, -1) => "-pi".to_string(),
        (true, half) => format!("{half}*pi"),
        (false, _) if k == 1 => "pi/2".to_string(),
        (false, _) if k == -1 => "-pi/2".to_string(),
        (false, _) => format!("{k}*pi/2"),
    }
}

/// `[a, b, c]` of [`number`]s.
pub(crate) fn vector(v: &[f64]) -> String {
    list(v.iter().map(|&x| number(x)))
}

/// `[a, b, c]` of [`angle`]s.
pub(crate) fn angles(v: &[f64]) -> String {
    list(v.iter().map(|&x| angle(x)))
}

/// `[a, b, ...]`.
fn list(items: impl Iterator<Item = String>) -> String {
    format!("[{}]", items.collect::<Vec<_>>().join(", "))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn numbers_round_trip_in_their_shortest_form() {
        for (x, text) in [
            (0.333, "0.333"),
            (87.0, "87"),
            (-0.0, "0"),
            (1e-5, "1e-5"),
            (-2.8973, "-2.8973"),
            (0.1 + 0.2, "0.30000000000000004"),
            (1e300, "1e300"),
        ] {
            assert_eq!(number(x), text);
            assert_eq!(text.parse::<f64>().unwrap(), x, "{text}");
        }
    }

    // The approximations of pi/2 are the inputs under test.
    #[allow(clippy::approx_constant)]
    #[test]
    fn quarter_turns_are_symbolic() {
        for (x, text) in [
            (PI / 2.0, "pi/2"),
            (-PI / 2.0, "-pi/2"),
            (1.570796326795, "pi/2"),
            (PI, "pi"),
            (-PI, "-pi"),
            (3.0 * PI / 2.0, "3*pi/2"),
            (-3.0 * PI / 2.0, "-3*pi/2"),
            (2.0 * PI, "2*pi"),
            (0.0, "0"),
            (1.5707963, "1.5707963"),
            (0.5, "0.5"),
        ] {
            assert_eq!(angle(x), text, "{x}");
        }
    }
}
