//! Writing: a checked [`Robot`] and its [`Tree`] as declaration text, one `link` block per
//! link from the root down, keys at their defaults left out.

use std::fmt::Write as _;

use super::check::{MimicRow, Tree};
use super::format::{Snap, angles, number, vector};
use super::robot::{Inertial, Joint, JointKind, Link, Robot};
use super::{SnappedAngles, UrdfOptions};

/// Standard gravity written as the parameter `g`, m/s^2.
const GRAVITY: &str = "9.81";

/// The declaration of `robot` as `struct_name`, imported with `options` (the file name,
/// the damping, the angles snapped).
pub(crate) fn write(
    robot: &Robot,
    tree: &Tree,
    struct_name: &str,
    options: &UrdfOptions,
) -> String {
    let (file, damping) = (options.file_name.as_str(), options.damping);
    let snap = options.snap_angles.map_or_else(Snap::default, Snap::within);
    let mut out = header(robot, tree, file, damping, options.floating);
    if let Some(tolerance) = options.snap_angles {
        out.push_str(&snap_line(tolerance, snapped_angles(robot, tree, snap)));
    }
    let _ = writeln!(out, "pub struct {struct_name};");
    let _ = writeln!(out, "parameters {{ g = {GRAVITY}; }} // m/s^2");
    out.push_str("gravity = [0, 0, -g];\n");
    for &l in &tree.order {
        let joint = tree.parent_joint[l].map(|j| (j, &robot.joints[j]));
        if tree.world_root && joint.is_none() {
            continue;
        }
        out.push('\n');
        let floating = options.floating && tree.order.first() == Some(&l);
        out.push_str(&link_block(robot, tree, l, joint, snap, floating));
    }
    out.push_str(&mimic_rows(tree));
    if damping {
        out.push_str(&damping_forces(robot, tree));
    }
    out.push_str(&drawing(tree));
    out
}

/// The moving joints' `<dynamics damping>` b > 0 as generalised forces -b q', one per
/// coordinate; empty when no moving joint is damped.
fn damping_forces(robot: &Robot, tree: &Tree) -> String {
    let forces: Vec<String> = robot
        .joints
        .iter()
        .zip(&tree.coordinates)
        .filter_map(|(joint, q)| {
            let b = joint.dynamics.as_ref()?.damping;
            let q = q.as_deref()?;
            (b > 0.0).then(|| format!("    {q}: -{}*der({q});", number(b)))
        })
        .collect();
    if forces.is_empty() {
        return String::new();
    }
    format!(
        "\n// The URDF's <dynamics damping> b of each moving joint: tau = -b q' (N m s/rad, N s/m).\n\
         // `mechanism inverse` replaces a driven joint's forces by its driving force, the\n\
         // total the motion needs: the motor gives that plus b q'.\n\
         forces {{\n{}\n}}\n",
        forces.join("\n")
    )
}

/// The `<mimic>` couplings as `constraints` rows, q - multiplier * q_master - offset, and
/// the coordinates they leave free as `independent` at q = 0 (the mimicking ones follow
/// from the rows when the mechanism is assembled). Empty without couplings.
fn mimic_rows(tree: &Tree) -> String {
    if tree.mimics.is_empty() {
        return String::new();
    }
    let mut out = String::from(
        "\n// The URDF's <mimic> couplings, each a constraint row: the joint's coordinate is\n\
         // multiplier * (its master's) + offset, with a master that is fixed or locked at 0.\n\
         constraints {\n",
    );
    let coordinate = |j: usize| tree.coordinates[j].as_deref().unwrap_or_default();
    for row in &tree.mimics {
        let _ = writeln!(
            out,
            "    {};",
            mimic_row(row, coordinate(row.joint), row.master.map(coordinate))
        );
    }
    out.push_str("}\n");
    let free: Vec<String> = tree
        .coordinates
        .iter()
        .enumerate()
        .filter(|&(j, q)| q.is_some() && !tree.mimics.iter().any(|r| r.joint == j))
        .map(|(_, q)| format!("{} = 0;", q.as_deref().unwrap_or_default()))
        .collect();
    out.push_str(
        "// The coordinates no <mimic> sets, at q = 0 (the others follow from the rows).\n",
    );
    // One line for a few, one per line for many (a humanoid's dozens).
    if free.len() <= 4 {
        let _ = writeln!(out, "independent {{ {} }}", free.join(" "));
    } else {
        let _ = writeln!(out, "independent {{\n    {}\n}}", free.join("\n    "));
    }
    out
}

/// One row, q - m * q_master - offset = 0, in its shortest form (`q - q_master` for the
/// plain copy m = 1, offset 0).
fn mimic_row(row: &MimicRow, q: &str, master: Option<&str>) -> String {
    let mut text = q.to_string();
    if let Some(master) = master.filter(|_| row.multiplier != 0.0) {
        let m = row.multiplier;
        let (sign, magnitude) = if m < 0.0 { ("+", -m) } else { ("-", m) };
        if magnitude == 1.0 {
            let _ = write!(text, " {sign} {master}");
        } else {
            let _ = write!(text, " {sign} {}*{master}", number(magnitude));
        }
    }
    if row.offset != 0.0 {
        let (sign, magnitude) = if row.offset < 0.0 {
            ("+", -row.offset)
        } else {
            ("-", row.offset)
        };
        let _ = write!(text, " {sign} {}", number(magnitude));
    }
    text
}

/// A `draw` section: lines through the link origins from the root to each leaf (a branch
/// from where it leaves one already drawn), and the path of the last link of the first
/// longest branch traced (the end effector of an arm). Empty for a robot with fewer than
/// two written links.
fn drawing(tree: &Tree) -> String {
    let written = |l: usize| !(tree.world_root && tree.parent_joint[l].is_none());
    let mut lines: Vec<Vec<usize>> = Vec::new();
    for &l in tree.order.iter().filter(|&&l| written(l)) {
        if tree.parent_link.contains(&Some(l)) {
            continue;
        }
        let mut chain = vec![l];
        let mut cur = tree.parent_link[l];
        while let Some(p) = cur.filter(|&p| written(p)) {
            chain.push(p);
            cur = tree.parent_link[p];
        }
        chain.reverse();
        lines.push(chain);
    }
    // The first of the longest branches is traced; the others are drawn from where they
    // leave a branch already drawn.
    let longest = lines.iter().map(Vec::len).max().unwrap_or(0);
    let Some(main) = lines
        .iter()
        .position(|c| c.len() == longest && longest >= 2)
    else {
        return String::new();
    };
    let tip = tree.link_names[*lines[main].last().unwrap_or(&0)].clone();
    lines.swap(0, main);
    let mut drawn: Vec<usize> = Vec::new();
    for chain in &mut lines {
        if let Some(k) = chain.iter().rposition(|l| drawn.contains(l)) {
            chain.drain(..k);
        }
        drawn.extend(chain.iter().copied());
    }
    lines.retain(|c| c.len() >= 2);
    let mut out = String::from(
        "\n// The drawing: the link origins joined from the root to each leaf.\ndraw {\n",
    );
    for chain in &lines {
        let names: Vec<&str> = chain.iter().map(|&l| tree.link_names[l].as_str()).collect();
        let _ = writeln!(out, "    line {};", names.join(", "));
    }
    let _ = writeln!(out, "    trace {tip};");
    out.push_str("}\n");
    out
}

/// The doc comment: where the declaration came from, what it holds, what was locked, the
/// gravity convention, and what was left out.
fn header(robot: &Robot, tree: &Tree, file: &str, damping: bool, floating: bool) -> String {
    let kinds = [
        JointKind::Revolute,
        JointKind::Continuous,
        JointKind::Prismatic,
        JointKind::Fixed,
    ];
    let counts: Vec<String> = kinds
        .iter()
        .map(|&k| (k, robot.joints.iter().filter(|j| j.kind == k).count()))
        .filter(|&(_, n)| n > 0)
        .map(|(k, n)| format!("{n} {}", k.urdf_name()))
        .collect();
    let counts = if counts.is_empty() {
        String::new()
    } else {
        format!(" ({})", counts.join(", "))
    };
    let mut out = format!(
        "/// Imported by `mechanism import` from {}: {} {}, {} {}{counts}.\n",
        comment_text(file),
        robot.links.len(),
        plural(robot.links.len(), "link"),
        robot.joints.len(),
        plural(robot.joints.len(), "joint"),
    );
    let locked: Vec<String> = robot
        .joints
        .iter()
        .filter(|j| j.locked)
        .map(|j| comment_text(&j.name))
        .collect();
    if locked.is_empty() {
        out.push_str("/// No joint locked.\n");
    } else {
        let _ = writeln!(
            out,
            "/// Locked at q = 0 (written as fixed joints): {}.",
            locked.join(", ")
        );
    }
    for note in &tree.adjusted {
        let _ = writeln!(out, "/// Inertia adjusted: {}.", comment_text(note));
    }
    if !tree.renamed.is_empty() {
        let renamed: Vec<String> = tree.renamed.iter().map(|r| comment_text(r)).collect();
        let _ = writeln!(out, "/// Renamed: {}.", renamed.join("; "));
    }
    if !tree.mimics.is_empty() {
        let _ = writeln!(
            out,
            "/// <mimic> couplings: {}, each held as a constraint row (`constraints` below).",
            tree.mimics.len()
        );
    }
    out.push_str("/// Gravity: z up, g = 9.81 m/s^2 along -z.\n");
    if tree.world_root {
        out.push_str("/// The URDF's root link `world` is the declaration's world frame.\n");
    } else if let Some(&root) = tree.order.first().filter(|_| floating) {
        let _ = writeln!(
            out,
            "/// The root link `{}` floats: q = [position, quaternion (x, y, z, w), joints], v = [velocity, angular velocity (root axes), joint rates].",
            tree.link_names[root]
        );
    } else if let Some(&root) = tree.order.first() {
        // A legged robot or humanoid is fixed unless asked to float: say so, and how.
        let _ = writeln!(
            out,
            "/// The root link `{}` is fixed to the world (`--floating`, or `floating = true` in mechanism!, imports it free).",
            tree.link_names[root]
        );
    }
    out.push_str(&dynamics_line(robot, tree, damping));
    let placeholders = robot
        .joints
        .iter()
        .zip(&tree.coordinates)
        .filter(|(j, q)| {
            q.is_some()
                && j.limit
                    .is_some_and(|l| l.velocity == Some(0.0) || l.effort == Some(0.0))
        })
        .count();
    if placeholders > 0 {
        let _ = writeln!(
            out,
            "/// Not written: the <limit> velocity or effort of 0 (a placeholder) of {placeholders} {}.",
            plural(placeholders, "joint")
        );
    }
    out
}

/// The header's line on `<dynamics>`: the damping imported as forces and the friction left
/// out, or (without `damping`) that neither is imported; empty when no joint has any.
fn dynamics_line(robot: &Robot, tree: &Tree, damping: bool) -> String {
    let mut out = String::new();
    let damped = robot.joints.iter().filter(|j| j.dynamics.is_some()).count();
    if damping {
        let moving = || {
            robot
                .joints
                .iter()
                .zip(&tree.coordinates)
                .filter(|(_, q)| q.is_some())
                .filter_map(|(j, _)| j.dynamics.as_ref())
        };
        let (viscous, friction) = (
            moving().filter(|d| d.damping > 0.0).count(),
            moving().filter(|d| d.friction > 0.0).count(),
        );
        if viscous + friction == 0 {
            return out;
        }
        let _ = write!(
            out,
            "/// <dynamics> damping of {viscous} {} imported as forces tau = -b q' (`forces` below)",
            plural(viscous, "joint")
        );
        if friction > 0 {
            let _ = write!(
                out,
                "; not imported: the Coulomb friction of {friction} {}",
                plural(friction, "joint")
            );
        }
        out.push_str(".\n");
    } else if damped > 0 {
        let _ = writeln!(
            out,
            "/// Not imported: the <dynamics> damping and friction of {damped} {}.",
            plural(damped, "joint")
        );
    }
    out
}

/// The header's line on the angles written as multiples of pi/2 under a tolerance of the
/// user's (`--snap-angles`): how many, and how far they moved.
fn snap_line(tolerance: f64, s: SnappedAngles) -> String {
    if s.count == 0 {
        return format!(
            "/// Angles within {} rad of a multiple of pi/2 written as one: none is.\n",
            number(tolerance)
        );
    }
    format!(
        "/// Angles within {} rad of a multiple of pi/2 written as one: {} {}, moved by at most \
         {:.2e} rad each, {:.2e} rad in all (no frame turns by more than the sum along its \
         path from the root).\n",
        number(tolerance),
        s.count,
        plural(s.count, "angle"),
        s.largest,
        s.total
    )
}

/// The angles the text writes (each written joint's `rpy`, each written inertia's
/// `com_rpy`) that `snap` turns into multiples of pi/2, other than exact zeros.
pub(crate) fn snapped_angles(robot: &Robot, tree: &Tree, snap: Snap) -> SnappedAngles {
    let mut s = SnappedAngles::default();
    let mut add = |v: &[f64; 3]| {
        for &x in v.iter().filter(|&&x| x != 0.0) {
            if let Some((_, deviation)) = snap.quarter_turns(x) {
                s.count += 1;
                s.largest = s.largest.max(deviation);
                s.total += deviation;
            }
        }
    };
    for &l in &tree.order {
        let joint = tree.parent_joint[l];
        if tree.world_root && joint.is_none() {
            continue;
        }
        if let Some(j) = joint {
            add(&robot.joints[j].rpy);
        }
        if let Some(inertial) = robot.links[l].inertial.as_ref().filter(|i| written(i)) {
            add(&inertial.rpy);
        }
    }
    s
}

/// Whether an inertia is written (a massless link has none).
fn written(inertial: &Inertial) -> bool {
    inertial.mass != 0.0 || inertial.inertia.iter().any(|&v| v != 0.0)
}

/// One `link` block: its parent and joint (none for a root), then its mass properties.
fn link_block(
    robot: &Robot,
    tree: &Tree,
    l: usize,
    joint: Option<(usize, &Joint)>,
    snap: Snap,
    floating: bool,
) -> String {
    let link: &Link = &robot.links[l];
    let mut keys: Vec<String> = Vec::new();
    if floating {
        keys.push(format!("joint = floating({});", super::FLOATING_ROOT));
    }
    if let Some((j, joint)) = joint {
        // A child of the `world` root is written without a parent: its joint is to the world.
        if let Some(parent) = tree.parent_link[l]
            && !(tree.world_root && tree.parent_joint[parent].is_none())
        {
            keys.push(format!("parent = {};", tree.link_names[parent]));
        }
        keys.push(joint_key(joint, tree.coordinates[j].as_deref()));
        push_nonzero(&mut keys, "xyz", &joint.xyz, vector);
        push_nonzero(&mut keys, "rpy", &joint.rpy, |v| angles(v, snap));
        if let (Some(limit), Some(_)) = (joint.limit, &tree.coordinates[j]) {
            if joint.kind != JointKind::Continuous
                && let Some(range) = limit.range()
            {
                keys.push(format!("limit = {};", vector(&range)));
            }
            // A zero rate or effort limit on a moving joint is a placeholder (the joint
            // could not move, or its motor give nothing): not written.
            if let Some(v) = limit.velocity.filter(|&v| v > 0.0) {
                keys.push(format!("velocity_limit = {};", number(v)));
            }
            if let Some(e) = limit.effort.filter(|&e| e > 0.0) {
                keys.push(format!("effort_limit = {};", number(e)));
            }
        }
    }
    if let Some(inertial) = &link.inertial {
        inertial_keys(&mut keys, inertial, snap);
    }
    let name = &tree.link_names[l];
    if keys.is_empty() {
        return format!("link {name} {{ }}\n");
    }
    let mut out = format!("link {name} {{\n");
    for key in keys {
        let _ = writeln!(out, "    {key}");
    }
    out.push_str("}\n");
    out
}

/// `joint = revolute(q, [x, y, z]);`, or `joint = fixed;` with the URDF joint named in a
/// comment (and why, for a locked one).
fn joint_key(joint: &Joint, coordinate: Option<&str>) -> String {
    let name = comment_text(&joint.name);
    match coordinate {
        Some(q) => format!(
            "joint = {}({q}, {});",
            joint.kind.urdf_name(),
            vector(&joint.axis)
        ),
        None if joint.locked => format!(
            "joint = fixed; // URDF {} joint \"{name}\" locked at q = 0",
            joint.kind.urdf_name()
        ),
        None => format!("joint = fixed; // URDF joint \"{name}\""),
    }
}

/// `mass`, `com`, `com_rpy` and `inertia`, each left out at its default (a massless link
/// has none of them).
fn inertial_keys(keys: &mut Vec<String>, inertial: &Inertial, snap: Snap) {
    if !written(inertial) {
        return;
    }
    let zero_inertia = inertial.inertia.iter().all(|&v| v == 0.0);
    keys.push(format!("mass = {};", number(inertial.mass)));
    push_nonzero(keys, "com", &inertial.xyz, vector);
    push_nonzero(keys, "com_rpy", &inertial.rpy, |v| angles(v, snap));
    if !zero_inertia {
        let [xx, xy, xz, yy, yz, zz] = inertial.inertia;
        keys.push(format!(
            "inertia = [{}, {}, {}];",
            vector(&[xx, xy, xz]),
            vector(&[xy, yy, yz]),
            vector(&[xz, yz, zz])
        ));
    }
}

/// `key = [..];` unless all of `v` is zero.
fn push_nonzero(keys: &mut Vec<String>, key: &str, v: &[f64; 3], text: impl Fn(&[f64]) -> String) {
    if v.iter().any(|&x| x != 0.0) {
        keys.push(format!("{key} = {};", text(v)));
    }
}

/// `word`, with an `s` unless `n` is 1.
fn plural(n: usize, word: &str) -> String {
    if n == 1 {
        word.to_string()
    } else {
        format!("{word}s")
    }
}

/// `text` safe inside a line comment: control characters (a newline in a URDF attribute)
/// become spaces.
fn comment_text(text: &str) -> String {
    text.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}
