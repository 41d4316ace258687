//! Checks: the rules a [`Robot`] must meet to be written as a declaration, each in its own
//! `check_*` function, and the [`Tree`] they establish (the links from the root down, each
//! link's parent joint, the identifiers written).

use std::collections::HashMap;

use super::error::{Place, UrdfError};
use super::inertia::inertia_fault;
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
}

/// Locks the joints `lock` names at q = 0, then checks `robot` and builds its [`Tree`].
///
/// # Errors
/// The first broken rule, at its element (see the `check_*` functions).
pub(crate) fn check(robot: &mut Robot, lock: &[String], file: &str) -> Result<Tree, UrdfError> {
    check_unique_names(robot, file)?;
    apply_locks(robot, lock, file)?;
    check_mimics(robot, file)?;
    check_inertials(robot, file)?;
    let parent_joint = check_parents(robot, file)?;
    let root = check_single_root(robot, &parent_joint, file)?;
    let order = check_connected(robot, &parent_joint, root, file)?;
    let world_root = robot.links[root].name == "world" && robot.links[root].inertial.is_none();
    let (link_names, coordinates) = check_identifiers(robot, root, world_root, file)?;
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

/// A `<mimic>` couples a joint to another, which a tree of independent coordinates cannot
/// say; a locked joint's mimic no longer matters.
fn check_mimics(robot: &Robot, file: &str) -> Result<(), UrdfError> {
    for joint in &robot.joints {
        if let Some(mimic) = &joint.mimic
            && joint.kind != JointKind::Fixed
            && !joint.locked
        {
            return Err(mimic.error(
                file,
                format!(
                    "joint \"{0}\" mimics another joint, which is not imported; lock it at q = 0 \
                     (`--lock {0}`, or `lock = [\"{0}\"]` in mechanism!)",
                    joint.name
                ),
            ));
        }
    }
    Ok(())
}

/// Mass not negative; inertia symmetric positive semi-definite with the triangle
/// inequalities ([`inertia_fault`]).
fn check_inertials(robot: &Robot, file: &str) -> Result<(), UrdfError> {
    for link in &robot.links {
        let Some(inertial) = &link.inertial else {
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
        if let Some(fault) = inertia_fault(inertial.inertia) {
            return Err(inertial.inertia_place.error(
                file,
                format!(
                    "the inertia of link \"{}\" is not physical: {fault}",
                    link.name
                ),
            ));
        }
    }
    Ok(())
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

/// The identifiers written: links' ([`identifier`] with `l_`) and the movable joints'
/// coordinates (`j_`); none reserved ([`RESERVED`]), no two alike (a link and a coordinate
/// share one namespace). A `world` root is not written and claims nothing.
fn check_identifiers(
    robot: &Robot,
    root: usize,
    world_root: bool,
    file: &str,
) -> Result<(Vec<String>, Vec<Option<String>>), UrdfError> {
    let mut taken = Identifiers {
        file,
        taken: HashMap::new(),
    };
    let mut link_names = Vec::with_capacity(robot.links.len());
    for (i, link) in robot.links.iter().enumerate() {
        let id = identifier(&link.name, "l_");
        if !(world_root && i == root) {
            taken.claim(&id, "link", &link.name, &link.place)?;
        }
        link_names.push(id);
    }
    let mut coordinates = Vec::with_capacity(robot.joints.len());
    for joint in &robot.joints {
        if joint.kind == JointKind::Fixed || joint.locked {
            coordinates.push(None);
            continue;
        }
        let id = identifier(&joint.name, "j_");
        taken.claim(&id, "joint", &joint.name, &joint.place)?;
        coordinates.push(Some(id));
    }
    Ok((link_names, coordinates))
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
        if RESERVED.contains(&id) {
            return Err(place.error(
                self.file,
                format!(
                    "{kind} \"{name}\" would be written as `{id}`, a name the declaration \
                     reserves (reserved: {}); rename it",
                    RESERVED.join(", ")
                ),
            ));
        }
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
