//! `mechanism import`: a URDF to stdout or to `--out`, joints locked, and a refused URDF as
//! one line with exit status 1.

use super::{assert_one_line_error, mechanism, out_dir, stderr};

/// The importer's test arm (codegen's fixture).
const ARM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/codegen/tests/urdf/arm.urdf");

#[test]
fn import_prints_the_declaration() {
    let o = mechanism(&["import", ARM]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(o.stderr.is_empty(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).expect("UTF-8");
    assert!(
        text.starts_with("/// Imported by `mechanism import` from "),
        "{text}"
    );
    assert!(text.contains("arm.urdf: 4 links, 3 joints"), "{text}");
    assert!(text.contains("pub struct TestArm;\n"), "{text}");
    assert!(
        text.contains("joint = prismatic(slide, [0.7071067811865475, 0.7071067811865475, 0]);"),
        "{text}"
    );
}

#[test]
fn import_writes_out_with_a_name_and_locks() {
    let dir = out_dir("import-out");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("arm.mech");
    let o = mechanism(&[
        "import",
        ARM,
        "--out",
        out.to_str().unwrap(),
        "--lock",
        "slide",
        "--name",
        "Arm",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(o.stdout.is_empty(), "nothing printed with --out");
    let text = std::fs::read_to_string(&out).expect("written");
    assert!(text.contains("pub struct Arm;\n"), "{text}");
    assert!(
        text.contains("/// Locked at q = 0 (written as fixed joints): slide.\n"),
        "{text}"
    );
    assert!(
        text.contains("joint = fixed; // URDF prismatic joint \"slide\""),
        "{text}"
    );
    // Only the declaration is left in the folder: the temporary was renamed.
    let files: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(files.len(), 1, "{files:?}");
}

#[test]
fn a_refused_urdf_is_one_line_and_exit_status_1() {
    let dir = out_dir("import-bad");
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("bad.urdf");
    std::fs::write(
        &bad,
        "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n\
         <joint name=\"free\" type=\"floating\"><parent link=\"a\"/><child link=\"b\"/></joint>\n\
         </robot>\n",
    )
    .unwrap();
    let out = dir.join("bad.mech");
    let o = mechanism(&[
        "import",
        bad.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_one_line_error(
        &o,
        "bad.urdf:4:1: <joint name=\"free\">: joint type \"floating\" (a free joint of six \
         coordinates) is not supported (supported: revolute, continuous, prismatic, fixed): \
         only the root link floats (--floating, or `floating = true` in mechanism!)",
    );
    assert!(!out.exists(), "nothing written");
    // A lock that names no joint, a folder, a missing file.
    assert_one_line_error(
        &mechanism(&["import", ARM, "--lock", "elbow"]),
        "cannot lock \"elbow\"",
    );
    assert_one_line_error(
        &mechanism(&["import", dir.to_str().unwrap()]),
        "not a regular file",
    );
    assert_one_line_error(
        &mechanism(&["import", dir.join("none.urdf").to_str().unwrap()]),
        "cannot read",
    );
}

/// An inertia no rigid body has is balanced, not refused: the declaration is written, and
/// stderr notes the change in one line (the header says it too).
#[test]
fn an_adjusted_inertia_is_noted_on_stderr() {
    let dir = out_dir("import-note");
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("flat.urdf");
    std::fs::write(
        &urdf,
        "<robot name=\"flat\">\n<link name=\"a\"/>\n<link name=\"b\"><inertial><mass value=\"1\"/>\
         <inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"3\"/></inertial></link>\n\
         <joint name=\"j\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/></joint>\n\
         </robot>\n",
    )
    .unwrap();
    let out = dir.join("flat.mech");
    let o = mechanism(&[
        "import",
        urdf.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(
        e.starts_with("note: ") && e.contains("inertia adjusted: link \"b\""),
        "{e}"
    );
    let text = std::fs::read_to_string(&out).expect("written");
    assert!(
        text.contains("inertia = [[1.5, 0, 0], [0, 1.5, 0], [0, 0, 3]];"),
        "{text}"
    );
}

/// `--damping` writes the arm's one damped joint (b = 0.1, friction 0) as a force, and the
/// written declaration runs through `simulate`, T + Pi - W kept (the decay itself is
/// checked against the closed form in tests/mechanisms/urdf_damping.rs).
#[test]
fn damping_is_imported_on_request_and_simulates() {
    let dir = out_dir("import-damping");
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("arm.mech");
    let o = mechanism(&["import", ARM, "--damping", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("forces {\n    shoulder: -0.1*der(shoulder);\n}"),
        "{text}"
    );
    let run = dir.join("run");
    let o = mechanism(&[
        "simulate",
        out.to_str().unwrap(),
        "--t-end",
        "0.5",
        "--figures",
        "none",
        "--no-animation",
        "--out",
        run.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("summary.json")).unwrap()).unwrap();
    let balance = summary["max_energy_balance_error"].as_f64().unwrap();
    assert!(balance < 1e-8, "T + Pi - W drifted by {balance:e} J");
}

/// `--out` naming something that is not a regular file (a symbolic link, a named pipe, a
/// directory) is refused in one line, and the entry is left as it was: renaming the
/// declaration over it would have replaced the link or the pipe itself.
#[test]
fn out_that_is_not_a_regular_file_is_refused_and_left_alone() {
    let dir = out_dir("import-not-a-file");
    std::fs::create_dir_all(&dir).unwrap();
    let target = dir.join("kept.txt");
    std::fs::write(&target, "kept").unwrap();
    let link = dir.join("link.mech");
    std::os::unix::fs::symlink(&target, &link).unwrap();
    let pipe = dir.join("pipe.mech");
    let made = std::process::Command::new("mkfifo").arg(&pipe).status();
    let folder = dir.join("folder.mech");
    std::fs::create_dir_all(&folder).unwrap();
    let mut cases = vec![(link.clone(), "a symbolic link"), (folder, "a directory")];
    if made.is_ok_and(|s| s.success()) {
        cases.push((pipe.clone(), "a device or a named pipe"));
    }
    for (path, kind) in cases {
        let o = mechanism(&["import", ARM, "--out", path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(1), "{}", stderr(&o));
        assert_one_line_error(&o, &format!("it exists and is {kind}, not a regular file"));
    }
    assert!(
        std::fs::symlink_metadata(&link)
            .unwrap()
            .file_type()
            .is_symlink()
    );
    assert_eq!(std::fs::read_to_string(&target).unwrap(), "kept");
    if pipe.exists() {
        use std::os::unix::fs::FileTypeExt;
        assert!(
            std::fs::symlink_metadata(&pipe)
                .unwrap()
                .file_type()
                .is_fifo()
        );
    }
}

/// `--out` that is the URDF being imported, by any path (the same name, `./name`, a
/// symbolic link either way, a hard link): refused in one line before anything is read or
/// written, the URDF byte for byte as it was.
#[cfg(unix)]
#[test]
fn out_that_is_the_urdf_itself_is_refused_and_the_urdf_kept() {
    let dir = out_dir("import-self");
    std::fs::create_dir_all(&dir).unwrap();
    let urdf = dir.join("R.urdf");
    let original = std::fs::read(ARM).unwrap();
    std::fs::write(&urdf, &original).unwrap();
    std::os::unix::fs::symlink(&urdf, dir.join("L.urdf")).unwrap();
    std::fs::hard_link(&urdf, dir.join("H.urdf")).unwrap();
    let cases = [
        ("R.urdf", "R.urdf"),
        ("R.urdf", "./R.urdf"),
        ("L.urdf", "R.urdf"),
        ("R.urdf", "L.urdf"),
        ("H.urdf", "R.urdf"),
    ];
    for (input, out) in cases {
        let o = super::mechanism_in(&dir, &["import", input, "--out", out]);
        assert_one_line_error(
            &o,
            &format!(
                "--out {out} is the URDF being imported ({input}): the declaration would replace it"
            ),
        );
        assert_eq!(
            std::fs::read(&urdf).unwrap(),
            original,
            "{input} --out {out}"
        );
    }
    assert!(
        std::fs::symlink_metadata(dir.join("L.urdf"))
            .unwrap()
            .is_symlink()
    );
    // Another name in the same folder is written as usual.
    let o = super::mechanism_in(&dir, &["import", "R.urdf", "--out", "R.mech"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(dir.join("R.mech").is_file());
}

/// Numbers beyond the bound of their quantity (issue 53, item 13): refused at import,
/// naming the file, the line, the element and the bound; nothing written.
#[test]
fn out_of_range_numbers_are_refused_at_the_element() {
    let dir = out_dir("import-range");
    std::fs::create_dir_all(&dir).unwrap();
    let arm = std::fs::read_to_string(ARM).unwrap();
    let cases = [
        (
            ("<mass value=\"2.5\"/>", "<mass value=\"1e300\"/>"),
            "x.urdf:13:7: <mass>: value: 1e300 kg is beyond 1e12 kg, the largest mass",
        ),
        (
            ("ixx=\"0.053\"", "ixx=\"1e300\""),
            "x.urdf:14:7: <inertia>: ixx: 1e300 kg m^2 is beyond 1e24 kg m^2",
        ),
        (
            ("<axis xyz=\"0 0 1\"/>", "<axis xyz=\"1e308 0 0\"/>"),
            "x.urdf:30:5: <axis>: xyz: 1e308 is beyond 1e6, the largest axis component",
        ),
        (
            ("<origin xyz=\"0 0 0.25\"", "<origin xyz=\"0 0 1e200\""),
            "x.urdf:12:7: <origin>: xyz: 1e200 m is beyond 1e6 m, the largest length",
        ),
        (
            ("<mass value=\"2.5\"/>", "<mass value=\"nan\"/>"),
            "x.urdf:13:7: <mass>: value: `nan` is not a finite number",
        ),
    ];
    for ((from, to), needle) in cases {
        assert!(arm.contains(from), "{from}");
        std::fs::write(dir.join("x.urdf"), arm.replacen(from, to, 1)).unwrap();
        let o = super::mechanism_in(&dir, &["import", "x.urdf", "--out", "x.mech"]);
        assert_one_line_error(&o, needle);
        assert!(!dir.join("x.mech").exists(), "{to}: nothing written");
    }
}

/// A URDF that is not UTF-8 text (issue 53, item 14): the file and what it is, with the
/// byte offset, line and column of a byte that is not UTF-8, or the encoding and the
/// conversion for UTF-16; a file over the input budget with its size.
#[test]
fn text_that_is_not_utf8_is_named_with_its_place() {
    let dir = out_dir("import-encoding");
    std::fs::create_dir_all(&dir).unwrap();
    let ascii = "<robot name=\"r\">\n  <link name=\"a\"/>\n</robot>\n";
    let le: Vec<u8> = ascii.encode_utf16().flat_map(u16::to_le_bytes).collect();
    let be: Vec<u8> = ascii.encode_utf16().flat_map(u16::to_be_bytes).collect();
    let bom = [&[0xff, 0xfe][..], &le].concat();
    let latin1 = b"<robot name=\"r\">\n  <link name=\"caf\xe9\"/>\n</robot>\n".to_vec();
    let cases: [(&str, Vec<u8>, &str); 4] = [
        (
            "bom.urdf",
            bom,
            "cannot read bom.urdf: it is UTF-16 text (little-endian, its \
            byte-order mark FF FE at byte 0), and input files are read as UTF-8: convert it, \
            e.g. `iconv -f UTF-16 -t UTF-8 bom.urdf > utf8-copy`",
        ),
        (
            "le.urdf",
            le,
            "it is UTF-16 text (little-endian, without a byte-order mark)",
        ),
        (
            "be.urdf",
            be,
            "`iconv -f UTF-16BE -t UTF-8 be.urdf > utf8-copy`",
        ),
        (
            "latin1.urdf",
            latin1,
            "latin1.urdf:2:18: byte 34 (0xe9) is not valid UTF-8: save \
            the file as UTF-8",
        ),
    ];
    for (name, bytes, needle) in cases {
        std::fs::write(dir.join(name), bytes).unwrap();
        let o = super::mechanism_in(&dir, &["import", name]);
        assert_one_line_error(&o, needle);
    }
    // Over the budget (lowered here to keep the file small): the file and its size.
    std::fs::write(dir.join("big.urdf"), ascii).unwrap();
    let o = assert_cmd::Command::cargo_bin("mechanism")
        .unwrap()
        .current_dir(&dir)
        .args(["import", "big.urdf"])
        .env("MECHANISM_MAX_INPUT_BYTES", "10")
        .output()
        .unwrap();
    assert_one_line_error(
        &o,
        &format!(
            "cannot read big.urdf: {} bytes, more than the 10 allowed for an input file",
            ascii.len()
        ),
    );
}

/// `--snap-angles` on UR5 (angles rounded to 11 decimals): the rounded quarter turns become
/// `pi/2`, the header states how far they moved, stderr notes it in one line; without the
/// flag they stay numbers; a tolerance out of range is one line and exit status 1.
#[test]
fn snap_angles_writes_rounded_quarter_turns_as_multiples_of_pi() {
    let ur5 = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/mechanisms/urdf/ur5_robot.urdf"
    );
    let o = mechanism(&["import", ur5, "--snap-angles", "1e-9"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout.clone()).expect("UTF-8");
    assert!(text.contains("rpy = [0, pi/2, 0];"), "{text}");
    assert!(!text.contains("1.57079632679"), "{text}");
    assert!(
        text.contains("/// Angles within 1e-9 rad of a multiple of pi/2 written as one: "),
        "{text}"
    );
    let e = stderr(&o);
    assert_eq!(e.lines().count(), 1, "{e}");
    assert!(e.contains("angles snapped: "), "{e}");
    let o = mechanism(&["import", ur5]);
    let text = String::from_utf8(o.stdout).expect("UTF-8");
    assert!(text.contains("rpy = [0, 1.57079632679, 0];"), "{text}");
    assert!(!text.contains("Angles within"), "{text}");
    assert_one_line_error(
        &mechanism(&["import", ur5, "--snap-angles", "0.1"]),
        "the angle snapping tolerance 0.1 rad is not between 0 and 0.001",
    );
}

/// `--floating` gives the root link the free-flyer joint; the bad inputs are one line each:
/// an arm whose massless base would make M singular, a robot fixed by a `world` link, and a
/// URDF whose root has a parent (the joints form a cycle) (the floating runs themselves:
/// tests/cli/floating.rs).
#[test]
fn floating_import_and_its_bad_inputs() {
    let solo = concat!(env!("CARGO_MANIFEST_DIR"), "/mechanisms/urdf/solo12.urdf");
    let o = mechanism(&["import", solo, "--floating"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8(o.stdout).expect("UTF-8");
    assert!(text.contains("joint = floating(root_joint);"), "{text}");
    assert!(text.contains("floats: q = [position, quaternion (x, y, z, w), joints]"));
    let dir = out_dir("import-floating");
    std::fs::create_dir_all(&dir).unwrap();
    // The arm's massless base turns about z with nothing but the shoulder's axis: M would
    // be singular at every q, so the import refuses it, naming the base.
    assert_one_line_error(
        &mechanism(&["import", ARM, "--floating"]),
        "arm.urdf:7:3: <link name=\"base_link\">: the floating base `base_link` is massless \
         (no <inertial> with a mass, on it or on a link fixed to it) and one joint, \
         \"shoulder\", moves from it",
    );
    // Fixed, it imports as before.
    assert!(mechanism(&["import", ARM]).status.success());
    let world = dir.join("world.urdf");
    std::fs::write(
        &world,
        "<robot name=\"r\">\n<link name=\"world\"/>\n<link name=\"b\"/>\n\
         <joint name=\"anchor\" type=\"fixed\"><parent link=\"world\"/><child link=\"b\"/></joint>\n\
         </robot>\n",
    )
    .unwrap();
    assert_one_line_error(
        &mechanism(&["import", world.to_str().unwrap(), "--floating"]),
        "world.urdf:2:1: <link name=\"world\">: the robot is fixed to the world by its root \
         link `world`, so its base cannot float",
    );
    let cycle = dir.join("cycle.urdf");
    std::fs::write(
        &cycle,
        "<robot name=\"r\">\n<link name=\"a\"/>\n<link name=\"b\"/>\n\
         <joint name=\"ab\" type=\"fixed\"><parent link=\"a\"/><child link=\"b\"/></joint>\n\
         <joint name=\"ba\" type=\"fixed\"><parent link=\"b\"/><child link=\"a\"/></joint>\n\
         </robot>\n",
    )
    .unwrap();
    assert_one_line_error(
        &mechanism(&["import", cycle.to_str().unwrap(), "--floating"]),
        "no root link: every link is the child of a joint",
    );
}
