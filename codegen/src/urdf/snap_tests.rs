//! Angle snapping under a tolerance of the caller's (`UrdfOptions::snap_angles`): the
//! angles it writes as multiples of pi/2, the header line stating how far they moved, and
//! the default left as it was.

use super::{SnappedAngles, UrdfOptions, urdf_import};

/// A joint origin and an inertia axis rounded to 11 decimals, as UR5's URDF writes them:
/// pi/2 (4.9e-12 off), pi (2.1e-13 off), and a near-zero roll of 1e-13.
const ROUNDED: &str = r#"<robot name="r">
<link name="a"/>
<link name="b"><inertial><origin xyz="0 0 0.1" rpy="1e-13 0 3.14159265359"/><mass value="1"/>
<inertia ixx="0.02" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.04"/></inertial></link>
<joint name="j" type="revolute"><parent link="a"/><child link="b"/>
<origin xyz="0 0.1 0" rpy="0 1.57079632679 0"/><axis xyz="0 0 1"/></joint>
</robot>
"#;

fn options(snap_angles: Option<f64>) -> UrdfOptions {
    UrdfOptions {
        file_name: "t.urdf".into(),
        snap_angles,
        ..Default::default()
    }
}

#[test]
fn by_default_only_angles_within_1e_12_of_a_nonzero_multiple_are_snapped() {
    let import = urdf_import(ROUNDED, &options(None)).expect("imported");
    assert!(
        import.text.contains("rpy = [0, 1.57079632679, 0];"),
        "{}",
        import.text
    );
    assert!(
        import.text.contains("com_rpy = [1e-13, 0, pi];"),
        "{}",
        import.text
    );
    assert!(!import.text.contains("Angles within"), "{}", import.text);
    assert_eq!(import.snapped, None);
    assert!(import.notes.is_empty(), "{:?}", import.notes);
}

// The 11-decimal roundings of pi/2 and pi are the inputs under test.
#[allow(clippy::approx_constant)]
#[test]
fn a_tolerance_snaps_every_multiple_and_the_header_states_the_deviation() {
    let import = urdf_import(ROUNDED, &options(Some(1e-9))).expect("imported");
    assert!(
        import.text.contains("rpy = [0, pi/2, 0];"),
        "{}",
        import.text
    );
    assert!(
        import.text.contains("com_rpy = [0, 0, pi];"),
        "{}",
        import.text
    );
    // The three nonzero angles, by their distances from pi/2, 0 and pi.
    let deviations = [
        1.570_796_326_79_f64 - std::f64::consts::FRAC_PI_2,
        1e-13,
        3.141_592_653_59 - std::f64::consts::PI,
    ]
    .map(f64::abs);
    let SnappedAngles {
        count,
        largest,
        total,
    } = import.snapped.expect("reported");
    assert_eq!(count, 3);
    assert_eq!(largest, deviations[0]);
    assert!(
        (total - deviations.iter().sum::<f64>()).abs() < 1e-24,
        "{total:e}"
    );
    let line = "/// Angles within 1e-9 rad of a multiple of pi/2 written as one: 3 angles, \
                moved by at most 4.90e-12 rad each, 5.20e-12 rad in all";
    assert!(import.text.contains(line), "{}", import.text);
    assert_eq!(import.notes.len(), 1, "{:?}", import.notes);
    // The header is a doc comment before the struct.
    let header_end = import.text.find("pub struct R;").expect("the struct");
    assert!(import.text[..header_end].contains(line));
}

#[test]
fn a_tolerance_that_snaps_nothing_says_so() {
    let import = urdf_import(ROUNDED, &options(Some(0.0))).expect("imported");
    assert!(import.text.contains("rpy = [0, 1.57079632679, 0];"));
    // 3.14159265359 is 2.1e-13 from pi: a tolerance of 0 keeps it numeric too.
    assert!(import.text.contains("com_rpy = [1e-13, 0, 3.14159265359];"));
    assert!(
        import
            .text
            .contains("of a multiple of pi/2 written as one: none is.")
    );
    assert_eq!(import.snapped.map(|s| s.count), Some(0));
}

#[test]
fn a_tolerance_out_of_range_is_refused_in_one_line() {
    for t in [-1e-9, 0.01, f64::NAN, f64::INFINITY] {
        let e = urdf_import(ROUNDED, &options(Some(t))).expect_err("refused");
        let text = e.to_string();
        assert!(text.starts_with("t.urdf:1:1: <robot"), "{text}");
        assert!(text.contains("is not between 0 and 0.001"), "{text}");
        assert!(!text.contains('\n'), "{text}");
    }
}
