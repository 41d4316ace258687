//! The importer on a small arm (a snapshot of the text it writes) and on every input it
//! refuses (one line naming the file, the line and the element).

use super::{UrdfError, UrdfOptions, urdf_to_mech};

/// The test arm: a revolute, a prismatic on a skew axis, a fixed tool frame.
const ARM: &str = include_str!("../../tests/urdf/arm.urdf");

/// Options for a file called `t.urdf`, locking `lock`.
fn options(lock: &[&str]) -> UrdfOptions {
    UrdfOptions {
        file_name: "t.urdf".into(),
        struct_name: None,
        lock: lock.iter().map(|s| s.to_string()).collect(),
    }
}

/// `body` inside `<robot name="r">`, whose first line is line 2.
fn robot(body: &str) -> String {
    format!("<robot name=\"r\">\n{body}\n</robot>\n")
}

/// Two links `a` and `b` joined by `joint` (line 4 of the file).
fn pair(joint: &str) -> String {
    robot(&format!("<link name=\"a\"/>\n<link name=\"b\"/>\n{joint}"))
}

/// A revolute joint `j` from `a` to `b` with `inside` in its element.
fn revolute(inside: &str) -> String {
    format!(
        "<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>{inside}</joint>"
    )
}

/// A link `b` whose `<inertial>` holds `inside`, on line 3, child of `a` by `j`.
fn inertial(inside: &str) -> String {
    robot(&format!(
        "<link name=\"a\"/>\n<link name=\"b\"><inertial>{inside}</inertial></link>\n{}",
        revolute("")
    ))
}

#[test]
fn the_test_arm_as_a_declaration() {
    let text = urdf_to_mech(ARM, &options(&[])).expect("imported");
    insta::assert_snapshot!(text);
}

/// What the importer writes reads back as a declaration of the same tree: its joints'
/// coordinates, independent by default (an open tree), every link a frame, and the
/// recursive route's M symmetric positive definite at q = 0.
#[test]
fn the_written_declaration_parses_and_derives() {
    let text = urdf_to_mech(ARM, &options(&[])).expect("imported");
    let mut model = crate::parse_model_str(&text).expect("the written text parses");
    let names: Vec<&str> = model.coordinates.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["shoulder", "slide"]);
    assert_eq!(model.independent.len(), 2);
    assert!(model.kinetic_from_links);
    let eqs = crate::derive(&mut model).expect("derived");
    assert_eq!(eqs.frames.len(), model.links.len());
    let env = |s: crate::SymbolId| {
        model
            .parameters
            .iter()
            .find(|p| model.arena.as_symbol(p.symbol) == Some(s))
            .map(|p| p.default)
            .or(Some(0.0))
    };
    let m = crate::eval_matrix(&model.arena, &eqs.mass, &env).expect("evaluated");
    let (a, b, c) = (m[0], m[1], m[3]);
    assert_eq!(m[1], m[2]);
    assert!(a > 0.0 && c > 0.0 && a * c - b * b > 0.0, "{m:?}");
}

#[test]
fn a_locked_joint_is_fixed_and_named_in_the_header() {
    let text = urdf_to_mech(ARM, &options(&["slide"])).expect("imported");
    assert!(
        text.contains("/// Locked at q = 0 (written as fixed joints): slide.\n"),
        "{text}"
    );
    assert!(
        text.contains("joint = fixed; // URDF prismatic joint \"slide\" locked at q = 0\n"),
        "{text}"
    );
    assert!(!text.contains("limit = [-0.1, 0.3]"), "{text}");
    assert!(
        text.contains("joint = revolute(shoulder, [0, 0, 1]);"),
        "{text}"
    );
}

#[test]
fn the_struct_name_option_replaces_the_robot_name() {
    let mut o = options(&[]);
    o.struct_name = Some("Arm".into());
    let text = urdf_to_mech(ARM, &o).expect("imported");
    assert!(text.contains("pub struct Arm;\n"), "{text}");
    o.struct_name = Some("2arm".into());
    let e = urdf_to_mech(ARM, &o).expect_err("refused");
    assert_eq!(e.line, 5);
    assert!(e.message.contains("`2arm` is not an identifier"), "{e}");
}

#[test]
fn a_world_root_is_the_world_frame() {
    let xml = robot(
        "<link name=\"world\"/>\n<link name=\"base\"/>\n\
         <joint name=\"fix\" type=\"fixed\"><parent link=\"world\"/><child link=\"base\"/>\
         <origin xyz=\"0 0 1\"/></joint>",
    );
    let text = urdf_to_mech(&xml, &options(&[])).expect("imported");
    assert!(!text.contains("link world"), "{text}");
    assert!(
        text.contains(
            "link base {\n    joint = fixed; // URDF joint \"fix\"\n    xyz = [0, 0, 1];\n}\n"
        ),
        "{text}"
    );
}

#[test]
fn names_become_identifiers() {
    let xml = robot(
        "<link name=\"0base\"/>\n<link name=\"arm/1\"/>\n\
         <joint name=\"1st joint\" type=\"continuous\"><parent link=\"0base\"/>\
         <child link=\"arm/1\"/></joint>",
    );
    let text = urdf_to_mech(&xml, &options(&[])).expect("imported");
    assert!(text.contains("link l_0base { }"), "{text}");
    assert!(
        text.contains("link arm_1 {\n    parent = l_0base;\n    joint = continuous(j_1st_joint, [1, 0, 0]);\n}"),
        "{text}"
    );
}

#[test]
fn links_are_written_depth_first_siblings_in_declaration_order() {
    // Joints declared leaf first; links declared root, then c, then b, then d (b's child).
    let xml = robot(
        "<link name=\"a\"/>\n<link name=\"c\"/>\n<link name=\"b\"/>\n<link name=\"d\"/>\n\
         <joint name=\"jd\" type=\"fixed\"><parent link=\"b\"/><child link=\"d\"/></joint>\n\
         <joint name=\"jb\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>\n\
         <joint name=\"jc\" type=\"fixed\"><parent link=\"a\"/><child link=\"c\"/></joint>",
    );
    let text = urdf_to_mech(&xml, &options(&[])).expect("imported");
    let order: Vec<&str> = text
        .lines()
        .filter_map(|l| l.strip_prefix("link "))
        .map(|l| l.split(' ').next().unwrap_or_default())
        .collect();
    assert_eq!(order, ["a", "c", "b", "d"], "{text}");
}

/// Each refused input: the URDF, the line and element the error names, and a phrase of its
/// message.
#[test]
fn refused_inputs_name_the_element_and_its_line() {
    let cases: Vec<(&str, String, usize, &str, &str)> = vec![
        (
            "floating joint",
            pair(
                "<joint name=\"j\" type=\"floating\"><parent link=\"a\"/><child link=\"b\"/></joint>",
            ),
            4,
            "<joint name=\"j\">",
            "unknown joint type \"floating\" (supported: revolute, continuous, prismatic, fixed)",
        ),
        (
            "planar joint",
            pair(
                "<joint name=\"j\" type=\"planar\"><parent link=\"a\"/><child link=\"b\"/></joint>",
            ),
            4,
            "<joint name=\"j\">",
            "unknown joint type \"planar\"",
        ),
        (
            "mimic not locked",
            pair(&revolute("\n<mimic joint=\"other\" multiplier=\"1\"/>")),
            5,
            "<mimic joint=\"other\">",
            "`--lock j`",
        ),
        (
            "missing parent link",
            pair(
                "<joint name=\"j\" type=\"fixed\"><parent link=\"nowhere\"/><child link=\"b\"/></joint>",
            ),
            4,
            "<parent link=\"nowhere\">",
            "the parent link \"nowhere\" of joint \"j\" is not declared",
        ),
        (
            "missing child link",
            pair(
                "<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"c\"/></joint>",
            ),
            4,
            "<child link=\"c\">",
            "the child link \"c\" of joint \"j\" is not declared",
        ),
        (
            "two parent joints",
            robot(
                "<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n\
                 <joint name=\"j1\" type=\"fixed\"><parent link=\"a\"/><child link=\"c\"/></joint>\n\
                 <joint name=\"j2\" type=\"fixed\"><parent link=\"b\"/><child link=\"c\"/></joint>",
            ),
            6,
            "<joint name=\"j2\">",
            "link \"c\" has two parent joints, \"j1\" (line 5) and \"j2\"",
        ),
        (
            "cycle",
            robot(
                "<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n\
                 <joint name=\"j1\" type=\"fixed\"><parent link=\"b\"/><child link=\"c\"/></joint>\n\
                 <joint name=\"j2\" type=\"fixed\"><parent link=\"c\"/><child link=\"b\"/></joint>",
            ),
            6,
            "<joint name=\"j2\">",
            "the joints form a cycle: link \"b\" is not reached from the root link \"a\"",
        ),
        (
            "no root",
            robot(
                "<link name=\"a\"/>\n\
                 <joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"a\"/></joint>",
            ),
            1,
            "<robot name=\"r\">",
            "no root link",
        ),
        (
            "two roots",
            robot("<link name=\"a\"/>\n<link name=\"b\"/>"),
            3,
            "<link name=\"b\">",
            "more than one root link: \"b\" is no joint's child, nor is \"a\" (line 2)",
        ),
        (
            "zero axis",
            pair(&revolute("\n<axis xyz=\"0 0 0\"/>")),
            5,
            "<axis>",
            "the axis of joint \"j\" has zero length",
        ),
        (
            "negative mass",
            inertial(
                "<mass value=\"-1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/>",
            ),
            3,
            "<inertial>",
            "link \"b\" has a negative mass, -1",
        ),
        (
            "infinite mass",
            inertial(
                "<mass value=\"inf\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/>",
            ),
            3,
            "<mass>",
            "value: `inf` is not a finite number",
        ),
        (
            "NaN inertia",
            inertial(
                "<mass value=\"1\"/><inertia ixx=\"NaN\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/>",
            ),
            3,
            "<inertia>",
            "ixx: `NaN` is not a finite number",
        ),
        (
            "negative principal moment",
            inertial(
                "<mass value=\"1\"/><inertia ixx=\"1\" ixy=\"2\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/>",
            ),
            3,
            "<inertia>",
            "the inertia of link \"b\" is not physical: a negative principal moment",
        ),
        (
            "triangle inequality",
            inertial(
                "<mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"3\"/>",
            ),
            3,
            "<inertia>",
            "break the triangle inequality",
        ),
        (
            "xyz with two numbers",
            pair(&revolute("\n<origin xyz=\"0 0\"/>")),
            5,
            "<origin>",
            "xyz=\"0 0\" has 2 values, expected 3 numbers",
        ),
        (
            "not a number",
            pair(&revolute("\n<origin rpy=\"0 x 0\"/>")),
            5,
            "<origin>",
            "rpy: `x` is not a number",
        ),
        (
            "not a robot",
            "<?xml version=\"1.0\"?>\n<sdf version=\"1.6\"/>\n".to_string(),
            2,
            "<sdf>",
            "the document is a <sdf>, not a URDF <robot>",
        ),
        (
            "not XML",
            "<robot name=\"r\">\n<link name=\"a\">\n</robot>\n".to_string(),
            3,
            "",
            "not well-formed XML",
        ),
        (
            "names written alike",
            robot(
                "<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n\
                 <joint name=\"x-1\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/></joint>\n\
                 <joint name=\"x.1\" type=\"continuous\"><parent link=\"b\"/><child link=\"c\"/></joint>",
            ),
            6,
            "<joint name=\"x.1\">",
            "joint \"x.1\" and joint \"x-1\" would both be written as `x_1`",
        ),
        (
            "reserved name",
            pair(
                "<joint name=\"t\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/></joint>",
            ),
            4,
            "<joint name=\"t\">",
            "would be written as `t`, a name the declaration reserves",
        ),
        (
            "duplicate link",
            robot("<link name=\"a\"/>\n<link name=\"a\"/>"),
            3,
            "<link name=\"a\">",
            "a second link named \"a\" (the first is on line 2)",
        ),
        (
            "xacro",
            "<robot name=\"r\" xmlns:xacro=\"http://www.ros.org/wiki/xacro\">\n\
             <xacro:include filename=\"arm.xacro\"/>\n</robot>"
                .to_string(),
            2,
            "<include>",
            "run xacro on the file first",
        ),
    ];
    for (name, xml, line, element, phrase) in cases {
        let e: UrdfError = urdf_to_mech(&xml, &options(&[])).expect_err(name);
        assert_one_line(name, &e, line, element, phrase);
    }
}

/// The lock option's refusals: a name of no joint, a fixed joint, 0 outside the limits.
#[test]
fn refused_locks() {
    let cases = [
        (
            "elbow",
            5,
            "<robot name=\"test_arm\">",
            "cannot lock \"elbow\": the robot has no joint of that name (movable joints: shoulder, slide)",
        ),
        (
            "tool_mount",
            41,
            "<joint name=\"tool_mount\">",
            "cannot lock \"tool_mount\": it is a fixed joint already",
        ),
    ];
    for (lock, line, element, phrase) in cases {
        let e = urdf_to_mech(ARM, &options(&[lock])).expect_err(lock);
        assert_one_line(lock, &e, line, element, phrase);
    }
    let xml = pair(&revolute("<limit lower=\"0.1\" upper=\"1\"/>"));
    let e = urdf_to_mech(&xml, &options(&["j"])).expect_err("outside");
    assert_one_line(
        "outside",
        &e,
        4,
        "<joint name=\"j\">",
        "cannot lock \"j\" at q = 0: 0 is outside its limits [0.1, 1]",
    );
    // A locked joint's mimic is accepted.
    let xml = pair(&revolute("<mimic joint=\"other\"/>"));
    assert!(urdf_to_mech(&xml, &options(&["j"])).is_ok());
}

/// `e` is one line, `t.urdf:LINE:COL: ELEMENT: ...PHRASE...`.
fn assert_one_line(case: &str, e: &UrdfError, line: usize, element: &str, phrase: &str) {
    let text = e.to_string();
    assert_eq!(text.lines().count(), 1, "{case}: {text}");
    assert!(
        text.starts_with(&format!("t.urdf:{line}:")),
        "{case}: {text}"
    );
    assert_eq!(e.element, element, "{case}: {text}");
    assert!(text.contains(phrase), "{case}: `{phrase}` in {text}");
    if !element.is_empty() {
        assert!(text.contains(&format!(": {element}: ")), "{case}: {text}");
    }
}
