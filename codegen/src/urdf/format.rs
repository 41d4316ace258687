//! Numbers as the declaration writes them: the shortest text that reads back as the same
//! f64, and angles at multiples of pi/2 as `pi/2`, `pi`, ... so that the algebra folds
//! their cosines and sines to exact 0 and +-1.

use std::f64::consts::FRAC_PI_2;

/// How far an angle may be from a nonzero multiple of pi/2 to be written as one by
/// default, rad (URDF files print 1.5707963267948966, or 1.570796326795 rounded to 12
/// decimals). Files rounded to fewer decimals (`1.57079632679`, 4.9e-12 from pi/2) stay
/// numbers unless the import is given a tolerance of its own ([`Snap::within`]).
pub(crate) const ANGLE_SNAP: f64 = 1e-12;

/// Largest multiple of pi/2 written symbolically (larger angles are written as numbers).
const MAX_QUARTER_TURNS: f64 = 64.0;

/// Which angles are written as multiples k pi/2 of a quarter turn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Snap {
    /// Largest |x - k pi/2| written as k pi/2, rad.
    tolerance: f64,
    /// Whether angles near 0 are written as 0 (k = 0) too.
    zero: bool,
}

impl Default for Snap {
    /// Nonzero multiples within [`ANGLE_SNAP`]; near-zero angles stay numbers.
    fn default() -> Self {
        Snap {
            tolerance: ANGLE_SNAP,
            zero: false,
        }
    }
}

impl Snap {
    /// Every multiple of pi/2, 0 included, within `tolerance` rad (the caller checks that
    /// the tolerance is finite, at least 0 and small).
    pub(crate) fn within(tolerance: f64) -> Self {
        Snap {
            tolerance,
            zero: true,
        }
    }

    /// The quarter turns k and the deviation |x - k pi/2| when `x` is written as k pi/2.
    pub(crate) fn quarter_turns(self, x: f64) -> Option<(i64, f64)> {
        let k = (x / FRAC_PI_2).round();
        // The deviation in f64: k pi/2 is exact to 1 ulp for |k| <= 64, far below any
        // tolerance that matters.
        let deviation = (x - k * FRAC_PI_2).abs();
        let snapped =
            (self.zero || k != 0.0) && k.abs() <= MAX_QUARTER_TURNS && deviation <= self.tolerance;
        // |k| <= 64: exact as an integer.
        snapped.then_some((k as i64, deviation))
    }
}

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

/// An angle: a multiple k of pi/2 that `snap` accepts as `0`, `pi/2`, `-pi/2`, `pi`,
/// `3*pi/2`, `2*pi`, ...; otherwise [`number`].
pub(crate) fn angle(x: f64, snap: Snap) -> String {
    let Some((k, _)) = snap.quarter_turns(x) else {
        return number(x);
    };
    match (k % 2 == 0, k / 2) {
        (true, 0) => "0".to_string(),
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
pub(crate) fn angles(v: &[f64], snap: Snap) -> String {
    list(v.iter().map(|&x| angle(x, snap)))
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
            assert_eq!(angle(x, Snap::default()), text, "{x}");
        }
    }

    // The 11-decimal roundings of pi/2 and pi, as UR5's URDF writes them.
    #[allow(clippy::approx_constant)]
    #[test]
    fn a_tolerance_of_its_own_snaps_rounded_quarter_turns_and_zero() {
        // By default 1.57079632679 (4.9e-12 from pi/2) stays a number, while
        // 3.14159265359 (2.1e-13 from pi) is within ANGLE_SNAP.
        assert_eq!(angle(1.57079632679, Snap::default()), "1.57079632679");
        assert_eq!(angle(3.14159265359, Snap::default()), "pi");
        assert_eq!(angle(1e-13, Snap::default()), "1e-13");
        let snap = Snap::within(1e-9);
        for (x, text) in [
            (1.57079632679, "pi/2"),
            (-1.57079632679, "-pi/2"),
            (3.14159265359, "pi"),
            (1e-13, "0"),
            (-1e-10, "0"),
            (1.5707963, "1.5707963"),
            (1e-8, "1e-8"),
        ] {
            assert_eq!(angle(x, snap), text, "{x}");
        }
        let (k, deviation) = snap.quarter_turns(1.57079632679).unwrap();
        assert_eq!(k, 1);
        assert!((deviation - 4.8966e-12).abs() < 1e-15, "{deviation:e}");
    }
}
