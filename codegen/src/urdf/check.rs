//! Checks: the rules a [`Robot`] must meet to be written as a declaration, each in its own
//! `check_*` function, and the [`Tree`] they establish (the links from the root down, each
//! link's parent joint, the identifiers written).

use std::collections::{HashMap, HashSet};

use super::error::{Place, UrdfError};
use super::format::number;
use super::inertia::{InertiaCheck, check_inertia, principal_axes};
use super::names::{RESERVED, identifier};
use super::robot::{JointKind, Robot};

/// The robot as a tree, ready to be written.
#[derive(Clone, Debug)]
pub(crate) struct Tree {
    /// Link indices from the root down: depth-first, siblings in the order their `<link>`s
    /// are declared (so parents come before their children).
    pub order: Vec<usize>,
    /// The joint whose child each link is (`None` for the root).
    pub parent_joint: Vec<Option<usize>>,
    /// The parent link of each link (`None` for the root).
    pub parent_link: Vec<Option<usize>>,
    /// Each link's identifier.
    pub link_names: Vec<String>,
    /// Each joint's coordinate (`None` for a fixed or locked joint).
    pub coordinates: Vec<Option<String>>,
    /// Whether the root link is the URDF's `world` frame (named `world`, massless), which
    /// the declaration has already: it is not written, and its children have no parent.
    pub world_root: bool,
    /// The `<mimic>` couplings of movable joints, each written as a constraint row.
    pub mimics: Vec<MimicRow>,
    /// The URDF names written otherwise than [`identifier`] gives, and why (a link named
    /// like a joint's coordinate, a reserved name), for the header.
    pub renamed: Vec<String>,
    /// The inertias written otherwise than the URDF gives, and how, for the header.
    pub adjusted: Vec<String>,
}

/// A movable joint whose coordinate follows another's: q_joint = multiplier * q_master +
/// offset, with q_master = 0 when the master is fixed or locked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct MimicRow {
    /// The mimicking joint (its index in the robot's joints).
    pub joint: usize,
    /// The joint followed, when it is movable and not locked.
    pub master: Option<usize>,
    /// The ratio q_joint / q_master.
    pub multiplier: f64,
    /// q_joint where q_master = 0.
    pub offset: f64,
}

/// Locks the joints `lock` names at q = 0, then checks `robot` and builds its [`Tree`].
///
/// # Errors
/// The first broken rule, at its element (see the `check_*` functions).
pub(crate) fn check(robot: &mut Robot, lock: &[String], file: &str) -> Result<Tree, UrdfError> {
    check_unique_names(robot, file)?;
    apply_locks(robot, lock, file)?;
    let mimics = check_mimics(robot, file)?;
    let adjusted = check_inertials(robot, file)?;
    let parent_joint = check_parents(robot, file)?;
    let root = check_single_root(robot, &parent_joint, file)?;
    let order = check_connected(robot, &parent_joint, root, file)?;
    let world_root = robot.links[root].name == "world" && robot.links[root].inertial.is_none();
    let Identified {
        link_names,
        coordinates,
        renamed,
    } = check_identifiers(robot, root, world_root, file)?;
    let index = link_index(robot);
    let parent_link = parent_joint
        .iter()
        .map(|j| j.map(|j| index[robot.joints[j].parent.as_str()]))
        .collect();
    Ok(Tree {
        order,
        parent_joint,
        parent_link,
        link_names,
        coordinates,
        world_root,
        mimics,
        renamed,
        adjusted,
    })
}

/// Each link's index by its URDF name.
fn link_index(robot: &Robot) -> HashMap<&str, usize> {
    robot
        .links
        .iter()
        .enumerate()
        .map(|(i, l)| (l.name.as_str(), i))
        .collect()
}

/// Two links, or two joints, with one name: the tree would be ambiguous.
fn check_unique_names(robot: &Robot, file: &str) -> Result<(), UrdfError> {
    let items = [
        (
            "link",
            robot
                .links
                .iter()
                .map(|l| (&l.name, &l.place))
                .collect::<Vec<_>>(),
        ),
        (
            "joint",
            robot.joints.iter().map(|j| (&j.name, &j.place)).collect(),
        ),
    ];
    for (kind, named) in items {
        let mut seen: HashMap<&str, &Place> = HashMap::new();
        for (name, place) in named {
            if let Some(first) = seen.insert(name, place) {
                return Err(place.error(
                    file,
                    format!(
                        "a second {kind} named \"{name}\" (the first is on line {})",
                        first.line
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Marks the joints in `lock` as locked at q = 0. Each must be a movable joint whose range
/// (if it has one) holds 0.
fn apply_locks(robot: &mut Robot, lock: &[String], file: &str) -> Result<(), UrdfError> {
    for name in lock {
        let Some(joint) = robot.joints.iter_mut().find(|j| &j.name == name) else {
            let movable: Vec<&str> = robot
                .joints
                .iter()
                .filter(|j| j.kind != JointKind::Fixed)
                .map(|j| j.name.as_str())
                .collect();
            return Err(robot.place.error(
                file,
                format!(
                    "cannot lock \"{name}\": the robot has no joint of that name (movable joints: {})",
                    if movable.is_empty() { "none".to_string() } else { movable.join(", ") }
                ),
            ));
        };
        if joint.kind == JointKind::Fixed {
            return Err(joint.place.error(
                file,
                format!("cannot lock \"{name}\": it is a fixed joint already"),
            ));
        }
        let range = match joint.kind {
            JointKind::Continuous => None,
            _ => joint.limit.and_then(|l| l.range()),
        };
        if let Some([lower, upper]) = range
            && !(lower <= 0.0 && 0.0 <= upper)
        {
            return Err(joint.place.error(
                file,
                format!(
                    "cannot lock \"{name}\" at q = 0: 0 is outside its limits [{lower}, {upper}]"
                ),
            ));
        }
        joint.locked = true;
    }
    Ok(())
}

/// The `<mimic>` couplings: each movable, unlocked joint with a `<mimic>` keeps its
/// coordinate, held to its master's by a constraint row (a locked joint's mimic no longer
/// matters). The master must be a declared joint, and no chain of masters may lead back
/// to the joint (then no coordinate of the chain would be free).
fn check_mimics(robot: &Robot, file: &str) -> Result<Vec<MimicRow>, UrdfError> {
    let by_name: HashMap<&str, usize> = robot
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| (joint.name.as_str(), j))
        .collect();
    let movable = |j: usize| robot.joints[j].kind != JointKind::Fixed && !robot.joints[j].locked;
    // The master each active mimic follows, when that master is movable.
    let mut master_of: Vec<Option<usize>> = vec![None; robot.joints.len()];
    let mut rows = Vec::new();
    for (j, joint) in robot.joints.iter().enumerate() {
        let Some(mimic) = joint.mimic.as_ref().filter(|_| movable(j)) else {
            continue;
        };
        let Some(&master) = by_name.get(mimic.joint.as_str()) else {
            return Err(mimic.place.error(
                file,
                format!(
                    "joint \"{}\" mimics joint \"{}\", which the URDF does not declare",
                    joint.name, mimic.joint
                ),
            ));
        };
        let master = Some(master).filter(|&m| movable(m));
        master_of[j] = master;
        rows.push(MimicRow {
            joint: j,
            master,
            multiplier: mimic.multiplier,
            offset: mimic.offset,
        });
    }
    for row in &rows {
        let mut chain = vec![row.joint];
        let mut next = master_of[row.joint];
        while let Some(m) = next {
            if m == row.joint {
                let names: Vec<String> = chain
                    .iter()
                    .map(|&j| format!("\"{}\"", robot.joints[j].name))
                    .collect();
                let mimic = robot.joints[row.joint].mimic.as_ref().map(|m| &m.place);
                return Err(mimic.unwrap_or(&robot.joints[row.joint].place).error(
                    file,
                    format!(
                        "the <mimic> joints {} follow each other in a cycle, so none of them \
                         moves freely; lock one (`--lock {}`)",
                        names.join(", "),
                        robot.joints[row.joint].name
                    ),
                ));
            }
            if chain.contains(&m) {
                break;
            }
            chain.push(m);
            next = master_of[m];
        }
    }
    Ok(rows)
}

/// Mass not negative, and an inertia a rigid body can have ([`check_inertia`]): one
/// with a negative principal moment beyond round-off (of the link, or of the robot's
/// largest link) is refused; one whose moments are all within
/// the mass at a micrometre is set to zero (a point mass); one that breaks the triangle
/// inequality I1 + I2 >= I3 is balanced (the two smaller moments raised, the principal
/// axes kept). Published URDFs carry such inertias (placeholder links of 1e-6 kg with every
/// entry 1e-6, printed round-off), which other tools load as given; each change made is
/// returned as a note for the header.
fn check_inertials(robot: &mut Robot, file: &str) -> Result<Vec<String>, UrdfError> {
    let mut notes = Vec::new();
    // The robot's scale of inertia: the largest sum of a link's principal moments.
    let robot_scale = robot
        .links
        .iter()
        .filter_map(|l| l.inertial.as_ref())
        .map(|i| {
            principal_axes(i.inertia)
                .0
                .iter()
                .map(|m| m.abs())
                .sum::<f64>()
        })
        .fold(0.0_f64, f64::max);
    for link in &mut robot.links {
        let Some(inertial) = &mut link.inertial else {
            continue;
        };
        if inertial.mass < 0.0 {
            return Err(inertial.place.error(
                file,
                format!(
                    "link \"{}\" has a negative mass, {}",
                    link.name, inertial.mass
                ),
            ));
        }
        // Four significant digits: enough to recognise the file's numbers in a note.
        let short = |x: f64| {
            let exact = number(x);
            if exact.len() <= 8 {
                exact
            } else {
                format!("{x:.3e}")
            }
        };
        let moments = |m: &[f64; 3]| format!("{}, {}, {}", short(m[0]), short(m[1]), short(m[2]));
        match check_inertia(inertial.inertia, inertial.mass, robot_scale) {
            Err(fault) => {
                return Err(inertial.inertia_place.error(
                    file,
                    format!(
                        "the inertia of link \"{}\" is not physical: {fault}",
                        link.name
                    ),
                ));
            }
            Ok(InertiaCheck::Physical) => {}
            Ok(InertiaCheck::Negligible { moments: m }) => {
                inertial.inertia = [0.0; 6];
                notes.push(format!(
                    "link \"{}\": principal moments {} kg m^2, negligible for its {} kg \
                     (within the mass at a micrometre), written as zero",
                    link.name,
                    moments(&m),
                    inertial.mass
                ));
            }
            Ok(InertiaCheck::Balanced {
                moments: m,
                balanced,
                inertia,
            }) => {
                inertial.inertia = inertia;
                notes.push(format!(
                    "link \"{}\": principal moments {} kg m^2 (no rigid body has them) \
                     raised to {} in the same axes",
                    link.name,
                    moments(&m),
                    moments(&balanced)
                ));
            }
        }
    }
    Ok(notes)
}

/// Each joint's parent and child links exist, and no link is the child of two joints.
/// Returns the joint whose child each link is.
fn check_parents(robot: &Robot, file: &str) -> Result<Vec<Option<usize>>, UrdfError> {
    let index = link_index(robot);
    let mut parent_joint: Vec<Option<usize>> = vec![None; robot.links.len()];
    for (j, joint) in robot.joints.iter().enumerate() {
        for (link, place, role) in [
            (&joint.parent, &joint.parent_place, "parent"),
            (&joint.child, &joint.child_place, "child"),
        ] {
            if !index.contains_key(link.as_str()) {
                return Err(place.error(
                    file,
                    format!(
                        "the {role} link \"{link}\" of joint \"{}\" is not declared",
                        joint.name
                    ),
                ));
            }
        }
        let child = index[joint.child.as_str()];
        if let Some(first) = parent_joint[child] {
            let first = &robot.joints[first];
            return Err(joint.place.error(
                file,
                format!(
                    "link \"{}\" has two parent joints, \"{}\" (line {}) and \"{}\": a URDF is a tree",
                    joint.child, first.name, first.place.line, joint.name
                ),
            ));
        }
        parent_joint[child] = Some(j);
    }
    Ok(parent_joint)
}

/// Exactly one link is no joint's child: the root.
fn check_single_root(
    robot: &Robot,
    parent_joint: &[Option<usize>],
    file: &str,
) -> Result<usize, UrdfError> {
    let mut roots = (0..robot.links.len()).filter(|&l| parent_joint[l].is_none());
    let Some(root) = roots.next() else {
        return Err(robot.place.error(
            file,
            "no root link: every link is the child of a joint, so the joints form a cycle",
        ));
    };
    if let Some(second) = roots.next() {
        let (first, second) = (&robot.links[root], &robot.links[second]);
        return Err(second.place.error(
            file,
            format!(
                "more than one root link: \"{}\" is no joint's child, nor is \"{}\" (line {}); \
                 connect them with a joint",
                second.name, first.name, first.place.line
            ),
        ));
    }
    Ok(root)
}

/// Every link is reached from the root (otherwise its joints form a cycle). Returns the
/// links depth-first from the root, siblings in the order their `<link>`s are declared.
fn check_connected(
    robot: &Robot,
    parent_joint: &[Option<usize>],
    root: usize,
    file: &str,
) -> Result<Vec<usize>, UrdfError> {
    let index = link_index(robot);
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); robot.links.len()];
    for joint in &robot.joints {
        children[index[joint.parent.as_str()]].push(index[joint.child.as_str()]);
    }
    // Siblings in the order their links are declared.
    for siblings in &mut children {
        siblings.sort_unstable();
    }
    let mut order = Vec::with_capacity(robot.links.len());
    let mut stack = vec![root];
    let mut seen = vec![false; robot.links.len()];
    while let Some(link) = stack.pop() {
        if std::mem::replace(&mut seen[link], true) {
            continue;
        }
        order.push(link);
        stack.extend(children[link].iter().rev().filter(|&&c| !seen[c]));
    }
    if let Some(lost) = (0..robot.links.len()).find(|&l| !seen[l]) {
        let place = parent_joint[lost].map_or(&robot.links[lost].place, |j| &robot.joints[j].place);
        return Err(place.error(
            file,
            format!(
                "the joints form a cycle: link \"{}\" is not reached from the root link \"{}\"",
                robot.links[lost].name, robot.links[root].name
            ),
        ));
    }
    Ok(order)
}

/// The identifiers written: the movable joints' coordinates ([`identifier`] with `j_`),
/// then the links' (`l_`); no two alike (a link and a coordinate share one namespace). URDF
/// keeps joints and links apart, so a link whose name is a coordinate's (`gripper` the
/// joint and `gripper` the link) is written as `gripper_link`; a reserved name
/// ([`RESERVED`]) gets `_joint` or `_link` the same way. Each such renaming is returned as
/// a note for the header. Two joints, or two links, written alike are refused (one of
/// them would have to be guessed). A `world` root is not written and claims nothing.
fn check_identifiers(
    robot: &Robot,
    root: usize,
    world_root: bool,
    file: &str,
) -> Result<Identified, UrdfError> {
    let mut taken = Identifiers {
        file,
        taken: HashMap::new(),
    };
    let mut renamed = Vec::new();
    // Every identifier the file's own names give: a renaming picks none of them, so a
    // name written later (a link literally called `gripper_link`) keeps its own, whatever
    // the order of the file.
    let own: HashSet<String> = robot
        .joints
        .iter()
        .map(|j| identifier(&j.name, "j_"))
        .chain(robot.links.iter().map(|l| identifier(&l.name, "l_")))
        .collect();
    let fresh = |taken: &Identifiers<'_>, base: String| {
        let mut id = base.clone();
        let mut k = 2;
        while taken.taken.contains_key(&id) || own.contains(&id) {
            id = format!("{base}{k}");
            k += 1;
        }
        id
    };
    let mut coordinates = Vec::with_capacity(robot.joints.len());
    for joint in &robot.joints {
        if joint.kind == JointKind::Fixed || joint.locked {
            coordinates.push(None);
            continue;
        }
        let mut id = identifier(&joint.name, "j_");
        if RESERVED.contains(&id.as_str()) {
            id = fresh(&taken, format!("{id}_joint"));
            renamed.push(format!(
                "joint \"{}\" as {id} (a reserved name)",
                joint.name
            ));
        }
        taken.claim(&id, "joint", &joint.name, &joint.place)?;
        coordinates.push(Some(id));
    }
    let mut link_names = Vec::with_capacity(robot.links.len());
    for (i, link) in robot.links.iter().enumerate() {
        let mut id = identifier(&link.name, "l_");
        if !(world_root && i == root) {
            let why = if RESERVED.contains(&id.as_str()) {
                Some("a reserved name".to_string())
            } else {
                match taken.taken.get(&id) {
                    Some(("joint", joint)) => Some(format!("joint \"{joint}\"'s coordinate")),
                    _ => None,
                }
            };
            if let Some(why) = why {
                id = fresh(&taken, format!("{id}_link"));
                renamed.push(format!("link \"{}\" as {id} ({why})", link.name));
            }
            taken.claim(&id, "link", &link.name, &link.place)?;
        }
        link_names.push(id);
    }
    Ok(Identified {
        link_names,
        coordinates,
        renamed,
    })
}

/// What [`check_identifiers`] settles.
struct Identified {
    /// Each link's identifier.
    link_names: Vec<String>,
    /// Each joint's coordinate (`None` for a fixed or locked joint).
    coordinates: Vec<Option<String>>,
    /// The renamings, for the header.
    renamed: Vec<String>,
}

/// The identifiers claimed so far, with the kind and URDF name of what claimed each.
struct Identifiers<'a> {
    file: &'a str,
    taken: HashMap<String, (&'static str, String)>,
}

impl Identifiers<'_> {
    /// Claims `id` for the `kind` (link or joint) called `name` at `place`.
    fn claim(
        &mut self,
        id: &str,
        kind: &'static str,
        name: &str,
        place: &Place,
    ) -> Result<(), UrdfError> {
        if let Some((other_kind, other)) = self.taken.get(id) {
            return Err(place.error(
                self.file,
                format!(
                    "{kind} \"{name}\" and {other_kind} \"{other}\" would both be written as \
                     `{id}`; rename one"
                ),
            ));
        }
        self.taken.insert(id.to_string(), (kind, name.to_string()));
        Ok(())
    }
}
