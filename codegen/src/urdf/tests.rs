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
        damping: false,
        snap_angles: None,
        floating: false,
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

/// The error of parsing and deriving the imported `text`, which must be refused.
fn refused_declaration(text: &str) -> crate::Error {
    crate::parse_model_str(text)
        .and_then(|mut m| crate::derive(&mut m).map(|_| ()))
        .expect_err("the declaration is refused")
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
    o.struct_name = Some("fn".into());
    let e = urdf_to_mech(ARM, &o).expect_err("refused");
    assert!(
        e.message.contains("the struct name `fn` is a Rust keyword"),
        "{e}"
    );
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

/// URDF keeps joint and link names apart, the declaration does not: a link named like a
/// joint's coordinate is written with `_link`, a reserved name with `_joint` or `_link`,
/// each renaming listed in the header, and the result parses with the renamed coordinates.
#[test]
fn clashing_and_reserved_names_are_renamed() {
    let xml = robot(&(
        "<link name=\"base\"/>\n<link name=\"gripper\">{M}</link>\n<link name=\"pi\">{M}</link>\n\
         <joint name=\"gripper\" type=\"continuous\"><parent link=\"base\"/>\
         <child link=\"gripper\"/></joint>\n\
         <joint name=\"t\" type=\"prismatic\"><parent link=\"gripper\"/>\
         <child link=\"pi\"/></joint>"
            .replace(
                "{M}",
                "<inertial><mass value=\"1\"/>\
                 <inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial>",
            )
    ));
    let text = urdf_to_mech(&xml, &options(&[])).expect("imported");
    assert!(
        text.contains(
            "/// Renamed: joint \"t\" as t_joint (a reserved name); link \"gripper\" as \
             gripper_link (joint \"gripper\"'s coordinate); link \"pi\" as pi_link (a reserved \
             name).\n"
        ),
        "{text}"
    );
    assert!(
        text.contains(
            "link gripper_link {\n    parent = base;\n    joint = continuous(gripper, [1, 0, 0]);\n"
        ),
        "{text}"
    );
    assert!(
        text.contains("link pi_link {\n    parent = gripper_link;\n    joint = prismatic(t_joint, [1, 0, 0]);\n"),
        "{text}"
    );
    let model = crate::parse_model_str(&text).expect("the written text parses");
    let names: Vec<&str> = model.coordinates.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["gripper", "t_joint"]);
    // A link literally named `gripper_link`, declared after the one renamed, keeps its
    // name: the renamed one takes `gripper_link2`, whatever the order of the file.
    let xml = robot(
        "<link name=\"base\"/>\n<link name=\"gripper\"/>\n<link name=\"gripper_link\"/>\n\
         <joint name=\"gripper\" type=\"continuous\"><parent link=\"base\"/>\
         <child link=\"gripper\"/></joint>\n\
         <joint name=\"tip\" type=\"fixed\"><parent link=\"gripper\"/>\
         <child link=\"gripper_link\"/></joint>",
    );
    let text = urdf_to_mech(&xml, &options(&[])).expect("imported");
    assert!(text.contains("link \"gripper\" as gripper_link2"), "{text}");
    assert!(
        text.contains("link gripper_link {\n    parent = gripper_link2;"),
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

/// A `<mimic>` is written as a constraint row: a gripper on a wrist, whose right finger
/// follows the left one mirrored (multiplier -1, offset 0.01 m), gets the row
/// `right + left - 0.01`, the wrist and the left finger independent, and derives with one
/// constraint row whose Jacobian is d(q_right + q_left)/dq = [0, 1, 1].
#[test]
fn a_mimic_joint_is_written_as_a_constraint_row() {
    let link = |name: &str| {
        format!(
            "<link name=\"{name}\"><inertial><mass value=\"0.1\"/>\
             <inertia ixx=\"1e-4\" ixy=\"0\" ixz=\"0\" iyy=\"1e-4\" iyz=\"0\" izz=\"1e-4\"/>\
             </inertial></link>"
        )
    };
    let joint = |name: &str, kind: &str, child: &str, parent: &str, inside: &str| {
        format!(
            "<joint name=\"{name}\" type=\"{kind}\"><parent link=\"{parent}\"/>\
             <child link=\"{child}\"/><axis xyz=\"0 1 0\"/>{inside}</joint>"
        )
    };
    let xml = robot(
        &[
            "<link name=\"base\"/>".to_string(),
            link("palm"),
            link("fl"),
            link("fr"),
            joint("wrist", "continuous", "palm", "base", ""),
            joint(
                "left",
                "prismatic",
                "fl",
                "palm",
                "<limit lower=\"0\" upper=\"0.04\"/>",
            ),
            joint(
                "right",
                "prismatic",
                "fr",
                "palm",
                "<mimic joint=\"left\" multiplier=\"-1\" offset=\"0.01\"/>",
            ),
        ]
        .join("\n"),
    );
    let text = urdf_to_mech(&xml, &options(&[])).expect("imported");
    assert!(
        text.contains("constraints {\n    right + left - 0.01;\n}"),
        "{text}"
    );
    assert!(
        text.contains("independent { wrist = 0; left = 0; }"),
        "{text}"
    );
    assert!(text.contains("/// <mimic> couplings: 1,"), "{text}");
    let mut model = crate::parse_model_str(&text).expect("the written text parses");
    let eqs = crate::derive(&mut model).expect("derived");
    assert_eq!((eqs.n, eqs.m), (3, 1));
    let row: Vec<String> = (0..3)
        .map(|k| crate::to_text(&model.arena, eqs.phi_q.get(0, k)))
        .collect();
    assert_eq!(row, ["0", "1", "1"]);
    // Locked, the mimicking joint needs no row.
    let text = urdf_to_mech(&xml, &options(&["right"])).expect("imported");
    assert!(!text.contains("constraints"), "{text}");
    // A fixed joint's `<mimic>` couples nothing and is not read, even without a `joint`.
    let xml = pair(
        "<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/><mimic/></joint>",
    );
    assert!(urdf_to_mech(&xml, &options(&[])).is_ok());
}

/// With the damping option, each moving joint's `<dynamics damping>` b becomes the force
/// -b q' on its coordinate, and the header says so and counts the friction left out; a
/// locked or fixed joint's damping, and a zero one, write nothing; without the option no
/// force is written. The written forces derive as tau = -b q'.
#[test]
fn joint_damping_is_written_as_forces_on_request() {
    let xml = robot(
        "<link name=\"a\"/>\n<link name=\"b\"><inertial><mass value=\"1\"/>\
         <inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>\n\
         <link name=\"c\"/>\n<link name=\"d\"/>\n<link name=\"e\"/>\n\
         <joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/>\
         <dynamics damping=\"0.25\" friction=\"0.1\"/></joint>\n\
         <joint name=\"k\" type=\"prismatic\"><parent link=\"b\"/><child link=\"c\"/>\
         <limit lower=\"-1\" upper=\"1\"/><dynamics damping=\"3\"/></joint>\n\
         <joint name=\"l\" type=\"revolute\"><parent link=\"c\"/><child link=\"d\"/>\
         <dynamics damping=\"7\"/></joint>\n\
         <joint name=\"f\" type=\"fixed\"><parent link=\"d\"/><child link=\"e\"/>\
         <dynamics damping=\"9\"/></joint>",
    );
    let plain = urdf_to_mech(&xml, &options(&["l"])).expect("imported");
    assert!(!plain.contains("forces"), "{plain}");
    assert!(plain.contains("/// Not imported: the <dynamics> damping and friction of 4 joints."));
    let mut damped = options(&["l"]);
    damped.damping = true;
    let text = urdf_to_mech(&xml, &damped).expect("imported");
    assert!(
        text.contains(
            "/// <dynamics> damping of 2 joints imported as forces tau = -b q' (`forces` \
             below); not imported: the Coulomb friction of 1 joint.\n"
        ),
        "{text}"
    );
    assert!(
        text.contains("forces {\n    j: -0.25*der(j);\n    k: -3*der(k);\n}\n"),
        "{text}"
    );
    let mut model = crate::parse_model_str(&text).expect("parses");
    let eqs = crate::derive(&mut model).expect("derives");
    let arena = &model.arena;
    let printed: Vec<String> = eqs
        .forces
        .data
        .iter()
        .map(|&f| crate::print::text::to_text(arena, f))
        .collect();
    assert_eq!(printed, ["-0.25*der(j)", "-3*der(k)"]);
}

/// A negative damping, imported, would feed the joint energy: refused at its element;
/// without the option the damping is not read as a force and the file imports.
#[test]
fn a_negative_damping_is_refused_when_imported() {
    let xml = pair(&revolute("<dynamics damping=\"-0.5\"/>"));
    let mut damped = options(&[]);
    damped.damping = true;
    let e = urdf_to_mech(&xml, &damped).expect_err("refused");
    assert_one_line(
        "negative damping",
        &e,
        4,
        "<dynamics>",
        "the damping of joint \"j\" is -0.5: a damper takes energy out, so b >= 0",
    );
    assert!(urdf_to_mech(&xml, &options(&[])).is_ok());
}

/// The damping option on a robot without `<dynamics>` writes neither forces nor a line
/// about them; a `<limit>` velocity or effort of 0 on a moving joint (a placeholder: the
/// joint could not move, its motor would give nothing) is not written, and the header
/// counts it.
#[test]
fn no_damping_line_without_dynamics_and_zero_limits_left_out() {
    let xml = pair(&revolute(
        "<limit lower=\"-1\" upper=\"1\" velocity=\"0\" effort=\"0\"/>",
    ));
    let mut damped = options(&[]);
    damped.damping = true;
    let text = urdf_to_mech(&xml, &damped).expect("imported");
    assert!(!text.contains("dynamics"), "{text}");
    assert!(!text.contains("forces"), "{text}");
    assert!(text.contains("    limit = [-1, 1];\n"), "{text}");
    assert!(
        !text.contains("velocity_limit") && !text.contains("effort_limit"),
        "{text}"
    );
    assert!(
        text.contains(
            "/// Not written: the <limit> velocity or effort of 0 (a placeholder) of 1 joint.\n"
        ),
        "{text}"
    );
}

/// A robot whose joints are all fixed imports (its frames are a valid tree), and the
/// declaration is then refused in terms of its links: none moves, so it has no coordinates.
#[test]
fn a_robot_without_a_moving_joint_is_refused_as_such() {
    let xml =
        pair("<joint name=\"j\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>");
    let text = urdf_to_mech(&xml, &options(&[])).expect("imported");
    let e = refused_declaration(&text);
    assert!(
        e.to_string()
            .contains("no link of `R` moves: every link's joint is fixed"),
        "{e}"
    );
}

/// Inertias no rigid body has, as published URDFs carry them, are adjusted and said so in
/// the header: one breaking I1 + I2 >= I3 (diag(1, 1, 3)) is balanced to diag(1.5, 1.5, 3);
/// round-off on a 1 kg link (an ixz of 2.4e-35 alone, principal moments +-2.4e-35) is
/// written as zero. The result derives (the declaration's own check accepts it).
#[test]
fn unphysical_inertias_are_adjusted_and_noted() {
    let text = urdf_to_mech(
        &inertial("<mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"3\"/>"),
        &options(&[]),
    )
    .expect("imported");
    assert!(
        text.contains(
            "/// Inertia adjusted: link \"b\": principal moments 1, 1, 3 kg m^2 (no rigid body \
             has them) raised to 1.5, 1.5, 3 in the same axes.\n"
        ),
        "{text}"
    );
    assert!(
        text.contains("inertia = [[1.5, 0, 0], [0, 1.5, 0], [0, 0, 3]];"),
        "{text}"
    );
    let mut model = crate::parse_model_str(&text).expect("parses");
    crate::derive(&mut model).expect("derives");
    let text = urdf_to_mech(
        &inertial("<mass value=\"1\"/><inertia ixx=\"0\" ixy=\"0\" ixz=\"2.40741e-35\" iyy=\"0\" iyz=\"0\" izz=\"0\"/>"),
        &options(&[]),
    )
    .expect("imported");
    assert!(
        text.contains("/// Inertia adjusted: link \"b\": principal moments"),
        "{text}"
    );
    assert!(text.contains("written as zero.\n"), "{text}");
    assert!(!text.contains("inertia = "), "{text}");
}

/// A robot whose moving joint carries a link without mass imports, and is then refused in
/// terms of its links (not as a kinetic energy written without rates).
#[test]
fn a_robot_whose_moving_links_have_no_mass_is_refused_as_such() {
    let text = urdf_to_mech(&pair(&revolute("")), &options(&[])).expect("imported");
    let e = refused_declaration(&text);
    assert!(
        e.to_string().contains(
            "no mass moves: the links the joints j move carry no mass or inertia that moves \
             with them"
        ),
        "{e}"
    );
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
            "joint type \"floating\" (a free joint of six coordinates) is not supported (supported: revolute, continuous, prismatic, fixed)",
        ),
        (
            "planar joint",
            pair(
                "<joint name=\"j\" type=\"planar\"><parent link=\"a\"/><child link=\"b\"/></joint>",
            ),
            4,
            "<joint name=\"j\">",
            "joint type \"planar\" (a joint of three coordinates in a plane) is not supported",
        ),
        (
            "unknown joint type",
            pair(
                "<joint name=\"j\" type=\"hinge\"><parent link=\"a\"/><child link=\"b\"/></joint>",
            ),
            4,
            "<joint name=\"j\">",
            "unknown joint type \"hinge\" (supported: revolute, continuous, prismatic, fixed)",
        ),
        (
            "mimic of an undeclared joint",
            pair(&revolute("\n<mimic joint=\"other\" multiplier=\"1\"/>")),
            5,
            "<mimic joint=\"other\">",
            "joint \"j\" mimics joint \"other\", which the URDF does not declare",
        ),
        (
            "mimics in a cycle",
            robot(
                "<link name=\"a\"/>\n<link name=\"b\"/>\n<link name=\"c\"/>\n\
                 <joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/>\
                 <mimic joint=\"k\"/></joint>\n\
                 <joint name=\"k\" type=\"continuous\"><parent link=\"b\"/><child link=\"c\"/>\
                 <mimic joint=\"j\" multiplier=\"2\"/></joint>",
            ),
            5,
            "<mimic joint=\"k\">",
            "the <mimic> joints \"j\", \"k\" follow each other in a cycle",
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

/// A floating root with neither mass nor a link fixed to it that has some, and a single
/// joint moving from it, makes M singular: refused at the root's `<link>`. With a mass on
/// a link fixed to it, or two joints moving from it, the base's six motions are not
/// redundant and the import goes on.
#[test]
fn a_massless_floating_base_is_refused_where_m_would_be_singular() {
    let floating = UrdfOptions {
        floating: true,
        ..options(&[])
    };
    let mass = "<inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial>";
    let joint = |name: &str, parent: &str, child: &str, kind: &str| {
        format!(
            "<joint name=\"{name}\" type=\"{kind}\"><parent link=\"{parent}\"/><child link=\"{child}\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>"
        )
    };
    let one_leg = robot(&format!(
        "<link name=\"a\"/>\n<link name=\"b\">{mass}</link>\n{}",
        joint("j", "a", "b", "revolute")
    ));
    let e = urdf_to_mech(&one_leg, &floating).expect_err("refused");
    assert_eq!(
        e.to_string(),
        "t.urdf:2:1: <link name=\"a\">: the floating base `a` is massless (no <inertial> with \
         a mass, on it or on a link fixed to it) and one joint, \"j\", moves from it: the base \
         turning with that joint while the joint turns back moves nothing, so M is singular: \
         give `a` an <inertial>, or import the robot fixed (without --floating, `floating = \
         true`)"
    );
    assert!(
        urdf_to_mech(&one_leg, &options(&[])).is_ok(),
        "fixed, it imports"
    );
    // A mass fixed to the base.
    let weighted = robot(&format!(
        "<link name=\"a\"/>\n<link name=\"w\">{mass}</link>\n<link name=\"b\">{mass}</link>\n{}\n{}",
        joint("f", "a", "w", "fixed"),
        joint("j", "a", "b", "revolute")
    ));
    assert!(urdf_to_mech(&weighted, &floating).is_ok());
    // Two legs.
    let two_legs = robot(&format!(
        "<link name=\"a\"/>\n<link name=\"b\">{mass}</link>\n<link name=\"c\">{mass}</link>\n{}\n{}",
        joint("j", "a", "b", "revolute"),
        joint("k", "a", "c", "revolute")
    ));
    assert!(urdf_to_mech(&two_legs, &floating).is_ok());
}
