//! The ranges a URDF's numbers are held to at import, by the quantity each one is.
//!
//! A number that parses is not yet a number the derivation can use: a mass of 1e300 kg, an
//! inertia of 1e300 kg m^2 or a centre of mass 1e200 m away overflow the products the
//! derivation and the solvers form (m r^2 in the mass matrix, the squares of the inertia's
//! entries in its principal moments, sqrt(x^2 + y^2 + z^2) of an axis), and come back as a
//! misleading diagnosis far from the typo ("no mass or inertia", "the zero vector", "the
//! kinetic energy can be negative"). Each number is therefore held, where it is read, to a
//! bound far beyond any machine and far below the f64 range (1.8e308):
//!
//! | quantity | attributes | at most | why this bound |
//! |---|---|---|---|
//! | mass | `<mass value>` | 1e12 kg | a mountain's mass |
//! | length | `<origin xyz>`, a prismatic `<mimic offset>` | 1e6 m | 1000 km; m r^2 <= 1e24 |
//! | inertia | `<inertia ixx ... izz>` | 1e24 kg m^2 | the largest mass at the largest length |
//! | angle | `<origin rpy>`, a revolute `<mimic offset>` | 1e6 rad | f64 angles there are 1.2e-10 rad apart |
//! | direction | `<axis xyz>` | 1e6 | a direction written about unit length, normalised on import |
//! | ratio | `<mimic multiplier>` | 1e6 | a gear ratio of a million |
//! | damping, friction | `<dynamics damping friction>` | 1e12 (N s/m, N m s/rad; N, N m) | times a rate of at most 1e9 (the `--init` bound), a force below 1e21 |
//!
//! With every quantity within its bound, the products the derivation forms (m r^2 q'^2 of
//! the kinetic energy, at most 1e12 * 1e12 * 1e18 = 1e42; the inertia's squared entries, at
//! most 1e48) stay hundreds of orders of magnitude below overflow. `<limit>` values are
//! only compared, never multiplied, and need only be finite (URDFs write 1e16 for "none").

/// A kind of URDF number and the largest magnitude it may have.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Bound {
    /// The quantity, as the refusal names it (`mass`).
    pub what: &'static str,
    /// Largest magnitude accepted.
    pub max: f64,
    /// The unit, with a leading space (` kg`), or empty.
    pub unit: &'static str,
    /// Why the bound is where it is, for the refusal.
    pub why: &'static str,
}

/// `<mass value>`.
pub(crate) const MASS: Bound = Bound {
    what: "mass",
    max: 1e12,
    unit: " kg",
    why: "a mountain's",
};

/// `<origin xyz>` and the offset of a prismatic joint's `<mimic>`.
pub(crate) const LENGTH: Bound = Bound {
    what: "length",
    max: 1e6,
    unit: " m",
    why: "1000 km",
};

/// `<inertia>`'s six entries.
pub(crate) const INERTIA: Bound = Bound {
    what: "moment of inertia",
    max: 1e24,
    unit: " kg m^2",
    why: "the largest mass, 1e12 kg, at the largest length, 1e6 m",
};

/// `<origin rpy>` and the offset of a revolute joint's `<mimic>`.
pub(crate) const ANGLE: Bound = Bound {
    what: "angle",
    max: 1e6,
    unit: " rad",
    why: "beyond it f64 angles lose their digits to whole turns",
};

/// `<axis xyz>`.
pub(crate) const DIRECTION: Bound = Bound {
    what: "axis component",
    max: 1e6,
    unit: "",
    why: "an axis is a direction, written about unit length and normalised on import",
};

/// `<mimic multiplier>`.
pub(crate) const RATIO: Bound = Bound {
    what: "mimic multiplier",
    max: 1e6,
    unit: "",
    why: "a gear ratio of a million",
};

/// `<dynamics damping>` and `<dynamics friction>`.
pub(crate) const DAMPING: Bound = Bound {
    what: "damping or friction coefficient",
    max: 1e12,
    unit: "",
    why: "times a rate of at most 1e9, a force below 1e21",
};

/// `<limit>` values: finite, nothing more (they are compared, never multiplied).
pub(crate) const LIMIT: Bound = Bound {
    what: "limit",
    max: f64::MAX,
    unit: "",
    why: "",
};

// The table's arithmetic, checked when the crate compiles: an inertia at its bound is the
// largest mass at the largest length, and a damping force at its bound times the largest
// rate is 1e21.
const _: () = assert!(INERTIA.max >= MASS.max * LENGTH.max * LENGTH.max);
const _: () = assert!(DAMPING.max * 1e9 <= 1e21);

impl Bound {
    /// `Ok` when |`value`| is within the bound, else the reason: the value, the bound and
    /// why, for the element's error.
    pub fn check(&self, value: f64) -> Result<(), String> {
        if value.abs() <= self.max {
            return Ok(());
        }
        Err(format!(
            "{value:e}{unit} is beyond {max:e}{unit}, the largest {what} the import takes \
             ({why}; larger values overflow the products the derivation forms): check the \
             number and its units",
            unit = self.unit,
            max = self.max,
            what = self.what,
            why = self.why,
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{UrdfOptions, urdf_to_mech};

    /// A link `a` and a link `b` on line 3 with `inertial` (its own line breaks: the
    /// `<mass>` on line 4, the `<inertia>` on line 5), joined by a revolute joint on the
    /// next line whose children are `joint`.
    fn arm(inertial: [&str; 3], joint: &str) -> String {
        let [origin, mass, inertia] = inertial;
        format!(
            "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"><inertial>{origin}\n\
             <mass value=\"{mass}\"/>\n\
             <inertia ixx=\"{inertia}\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/>\n\
             </inertial></link>\n\
             <joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>{joint}</joint>\n\
             </robot>\n"
        )
    }

    /// The import of `xml`, which must be refused at `line`, `element`, with `phrase`.
    fn refused(case: &str, xml: &str, line: usize, element: &str, phrase: &str) {
        let options = UrdfOptions {
            file_name: "t.urdf".into(),
            ..UrdfOptions::default()
        };
        let e = urdf_to_mech(xml, &options).expect_err(case);
        let text = e.to_string();
        assert_eq!(text.lines().count(), 1, "{case}: {text}");
        assert!(
            text.starts_with(&format!("t.urdf:{line}:")),
            "{case}: {text}"
        );
        assert_eq!(e.element, element, "{case}: {text}");
        assert!(text.contains(phrase), "{case}: `{phrase}` in {text}");
    }

    const FINE: [&str; 3] = ["<origin xyz=\"0 0 0.1\"/>", "2", "1"];

    #[test]
    fn numbers_beyond_their_bound_are_refused_naming_the_element_the_line_and_the_bound() {
        let origin = |xyz: &str| format!("<origin xyz=\"{xyz}\"/>");
        let cases: Vec<(&str, String, usize, &str, &str)> = vec![
            (
                "mass",
                arm([FINE[0], "1e300", "1"], ""),
                4,
                "<mass>",
                "value: 1e300 kg is beyond 1e12 kg, the largest mass the import takes",
            ),
            (
                "inertia",
                arm([FINE[0], "2", "1e300"], ""),
                5,
                "<inertia>",
                "ixx: 1e300 kg m^2 is beyond 1e24 kg m^2, the largest moment of inertia",
            ),
            (
                "inertial origin",
                arm([&origin("0 0 1e200"), "2", "1"], ""),
                3,
                "<origin>",
                "xyz: 1e200 m is beyond 1e6 m, the largest length",
            ),
            (
                "joint origin",
                arm(FINE, "<origin xyz=\"0 -2e6 0\"/>"),
                7,
                "<origin>",
                "xyz: -2e6 m is beyond 1e6 m",
            ),
            (
                "rpy",
                arm(FINE, "<origin rpy=\"0 1e7 0\"/>"),
                7,
                "<origin>",
                "rpy: 1e7 rad is beyond 1e6 rad, the largest angle",
            ),
            (
                "axis",
                arm(FINE, "<axis xyz=\"1e308 0 0\"/>"),
                7,
                "<axis>",
                "xyz: 1e308 is beyond 1e6, the largest axis component",
            ),
            (
                "damping",
                arm(FINE, "<dynamics damping=\"1e300\"/>"),
                7,
                "<dynamics>",
                "damping: 1e300 is beyond 1e12",
            ),
            (
                "NaN",
                arm([FINE[0], "NaN", "1"], ""),
                4,
                "<mass>",
                "value: `NaN` is not a finite number",
            ),
            (
                "inf",
                arm([FINE[0], "2", "inf"], ""),
                5,
                "<inertia>",
                "ixx: `inf` is not a finite number",
            ),
            (
                "1e400",
                arm([&origin("1e400 0 0"), "2", "1"], ""),
                3,
                "<origin>",
                "xyz: `1e400` is not a finite number (at most about 1.8e308)",
            ),
        ];
        for (case, xml, line, element, phrase) in cases {
            refused(case, &xml, line, element, phrase);
        }
    }

    #[test]
    fn numbers_at_their_bound_and_large_limits_are_imported() {
        let options = UrdfOptions::default();
        // The largest of each (an inertia of 1e24 meets I1 + I2 >= I3 with 1e24 on the
        // other two as well).
        let xml = arm(
            ["<origin xyz=\"1e6 0 0\" rpy=\"0 0 1e6\"/>", "1e12", "1e24"],
            "",
        )
        .replace("iyy=\"1\"", "iyy=\"1e24\"")
        .replace("izz=\"1\"", "izz=\"1e24\"");
        let text = urdf_to_mech(&xml, &options).expect("imported");
        // ... and derived: no product of the derivation overflows at the bounds (the
        // derivation refuses constants that do: `number::checked_mul`).
        let derived = crate::parse_model_str(&text).and_then(|mut m| crate::derive(&mut m));
        assert!(derived.is_ok(), "{:?}", derived.err());
        // Limits are compared, never multiplied: 1e16 ("none") stays importable.
        let xml = arm(
            FINE,
            "<limit lower=\"-1e16\" upper=\"1e16\" effort=\"1e300\"/>",
        );
        assert!(urdf_to_mech(&xml, &options).is_ok());
    }

    #[test]
    fn the_bounds_keep_the_derivation_s_products_finite() {
        // The kinetic energy of a point mass at the largest length moving at the largest
        // rate (1e9 per second): 1/2 m r^2 q'^2.
        let energy = 0.5 * MASS.max * LENGTH.max * LENGTH.max * 1e9 * 1e9;
        assert!(energy < 1e50, "{energy:e}");
        // An inertia at its bound: the parallel-axis term and the squares the principal
        // moments are computed through.
        assert!((INERTIA.max * INERTIA.max).is_finite() && INERTIA.max * INERTIA.max < 1e50);
        // An axis at its bound has a finite length.
        let axis = DIRECTION.max;
        assert!((3.0 * axis * axis).sqrt().is_finite());
    }

    #[test]
    fn a_value_beyond_its_bound_is_named_with_the_bound() {
        assert!(MASS.check(1e12).is_ok() && MASS.check(-3.0).is_ok());
        let e = MASS.check(1e300).unwrap_err();
        assert!(
            e.starts_with("1e300 kg is beyond 1e12 kg, the largest mass"),
            "{e}"
        );
        assert!(LIMIT.check(1e16).is_ok());
    }
}
