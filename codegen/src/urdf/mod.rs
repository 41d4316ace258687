//! URDF import: a robot described in URDF (the ROS Unified Robot Description Format) as
//! declaration text, whose `link` sections the `syntax` stage reads like any `.mech` file.
//!
//! Enters: the text of a `.urdf` file and [`UrdfOptions`]. Leaves: the text of a
//! declaration (`pub struct`, the gravity parameter `g`, one `link` block per URDF link,
//! parents before children), or one [`UrdfError`] naming the file, line, column and
//! element. Imports nothing of the other stages: the output is text, and the derivation
//! that reads it checks it again like any declaration.
//!
//! The stages: [`read`] (XML to a [`robot::Robot`], numbers parsed), [`check`] (locks
//! applied, the tree, the physics of each inertia, the identifiers) and [`write`] (the
//! text). What is imported: links with their `<inertial>` (mass, centre of mass, inertia
//! and its axes) and revolute, continuous, prismatic and fixed joints with their origin,
//! axis and `<limit>`; a `<mimic>` (q = multiplier * q_master + offset) as a constraint
//! row, the joints no mimic sets being the independent coordinates; on request
//! ([`UrdfOptions::damping`]), `<dynamics damping>` b as the force -b q'. What is not,
//! because it carries no rigid-body dynamics: `<visual>`, `<collision>`, `<material>`,
//! `<transmission>`, `<gazebo>`, `<safety_controller>`, `<calibration>`; and Coulomb
//! friction (and the damping, without the option), which the header of the output counts.

mod bounds;
mod check;
mod error;
mod format;
mod inertia;
mod names;
mod read;
mod robot;
mod write;

pub use error::UrdfError;

/// Largest tolerance [`UrdfOptions::snap_angles`] accepts, rad: past it, snapping would
/// move frames by more than a rounded decimal does (a link of 1 m by a millimetre).
pub const MAX_SNAP_ANGLES: f64 = 1e-3;

/// How to import a URDF.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UrdfOptions {
    /// The file name the errors and the output's header quote (`robots/panda.urdf`).
    pub file_name: String,
    /// The struct name; `None` for the robot's name in CamelCase (`panda` gives `Panda`).
    pub struct_name: Option<String>,
    /// URDF names of movable joints to lock at q = 0: each becomes a fixed joint (0 must
    /// be within the joint's limits). A locked joint's `<mimic>` is dropped.
    pub lock: Vec<String>,
    /// Import each movable joint's `<dynamics damping>` b as the generalised force
    /// -b q' on its coordinate (a viscous damper in the joint). Off by default: the
    /// rigid-body references (Pinocchio's `rnea`, `crba`) leave damping out. Coulomb
    /// `friction` is not imported either way (a force that jumps where q' changes sign).
    pub damping: bool,
    /// Write every angle (a joint's `rpy`, an inertia's `com_rpy`) within this many rad of
    /// a multiple k pi/2 as `k*pi/2`, 0 included, so that the derivation folds its sine and
    /// cosine to 0 and +-1; the header states how many angles moved and by how much.
    /// `None` (the default): nonzero multiples within 1e-12 rad only, which leaves a file
    /// rounded to 11 decimals (`1.57079632679`, 4.9e-12 rad from pi/2) numeric. At most
    /// [`MAX_SNAP_ANGLES`].
    pub snap_angles: Option<f64>,
    /// Give the root link a floating joint, `joint = floating(root_joint);` (Pinocchio's
    /// `JointModelFreeFlyer` and its name): its configuration `root_joint_x`, ..,
    /// `root_joint_qw` and velocities `root_joint_vx`, .., `root_joint_wz` come before the
    /// joints'. Refused for a robot whose root is the `world` link (already fixed).
    pub floating: bool,
}

/// The angles an import wrote as multiples of pi/2 under [`UrdfOptions::snap_angles`]
/// (exact zeros not counted).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SnappedAngles {
    /// How many angles.
    pub count: usize,
    /// The largest |x - k pi/2| among them, rad.
    pub largest: f64,
    /// The sum of |x - k pi/2| over them, rad: a bound on how far any frame turns (the
    /// rotations moved along its path compose, each by at most its angle's deviation).
    pub total: f64,
}

/// The name a floating root's joint is given on import (Pinocchio's for the free flyer it
/// adds to a URDF's root).
pub const FLOATING_ROOT: &str = "root_joint";

/// The declaration text of the robot the URDF `xml` describes.
///
/// Links are written parents before children (depth-first from the root, siblings in the order
/// their `<link>`s are declared); each movable joint's coordinate is named after the joint,
/// each link after the link, with characters other than ASCII letters, digits and `_` replaced
/// by `_` (and `j_` or `l_` in front of a leading digit); a link named like a joint's
/// coordinate, or a reserved name, gets `_link` (`_joint`), noted in the header. Gravity is
/// g = 9.81 m/s^2 along -z.
///
/// # Example
///
/// ```
/// use mechanism_codegen::{UrdfOptions, urdf_to_mech};
///
/// let urdf = r#"<robot name="pendulum">
///   <link name="base"/>
///   <link name="arm">
///     <inertial><mass value="1"/><origin xyz="0 0 -0.5"/>
///       <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0"/></inertial>
///   </link>
///   <joint name="hinge" type="continuous">
///     <parent link="base"/><child link="arm"/><axis xyz="0 1 0"/>
///   </joint>
/// </robot>"#;
/// let options = UrdfOptions { file_name: "pendulum.urdf".into(), ..Default::default() };
/// let text = urdf_to_mech(urdf, &options)?;
/// assert!(text.contains("pub struct Pendulum;"));
/// assert!(text.contains("joint = continuous(hinge, [0, 1, 0]);"));
/// # Ok::<(), mechanism_codegen::UrdfError>(())
/// ```
///
/// # Errors
/// The first problem found, as one line `FILE:LINE:COL: <element>: message`: malformed
/// XML or numbers; a number beyond the bound of its quantity (a mass above 1e12 kg, a
/// length above 1e6 m, an inertia above 1e24 kg m^2, ...: the table of `urdf/bounds.rs`,
/// which keeps the derivation's products far from overflow); a root other than `<robot>`; a joint type other than revolute,
/// continuous, prismatic or fixed; a `<mimic>` of a movable joint naming an undeclared
/// joint, or mimics that follow each other in a cycle; a joint whose parent or child link
/// is not declared; a link with two parent joints; a cycle, or more than one root link; a
/// zero-length axis; a negative mass; an inertia with a negative principal moment beyond
/// round-off (others no rigid body has are adjusted: [`UrdfImport::notes`]); two joints,
/// or two links, written alike; a `lock` name that is not a movable joint, or whose limits
/// exclude 0; a `struct_name` that is not an identifier, or is a Rust keyword; `floating`
/// for a robot whose root link is `world`, or whose root (with the links fixed to it) is
/// massless with at most one joint moving from it (M would be singular).
pub fn urdf_to_mech(xml: &str, options: &UrdfOptions) -> Result<String, UrdfError> {
    urdf_import(xml, options).map(|import| import.text)
}

/// A URDF imported: the declaration text, and what the import changed on the way.
#[derive(Clone, Debug, PartialEq)]
pub struct UrdfImport {
    /// The declaration (as [`urdf_to_mech`] returns it).
    pub text: String,
    /// Each change from what the URDF says, in a sentence (also in the text's header): an
    /// inertia no rigid body has, balanced or written as zero; a name written otherwise
    /// (a link named like a joint's coordinate, a reserved name); the angles snapped to
    /// multiples of pi/2 under a tolerance of the caller's.
    pub notes: Vec<String>,
    /// The angles snapped under [`UrdfOptions::snap_angles`]; `None` without it.
    pub snapped: Option<SnappedAngles>,
}

/// [`urdf_to_mech`], with the notes of what was changed.
///
/// # Errors
/// As [`urdf_to_mech`].
pub fn urdf_import(xml: &str, options: &UrdfOptions) -> Result<UrdfImport, UrdfError> {
    let file = options.file_name.as_str();
    let mut robot = read::read(xml, file)?;
    let struct_name = match &options.struct_name {
        Some(name) if names::is_keyword(name) => {
            return Err(robot
                .place
                .error(file, format!("the struct name `{name}` is a Rust keyword")));
        }
        Some(name) if names::is_identifier(name) => name.clone(),
        Some(name) => {
            return Err(robot.place.error(
                file,
                format!("the struct name `{name}` is not an identifier"),
            ));
        }
        None => names::struct_name(&robot.name),
    };
    if let Some(t) = options.snap_angles
        && !(0.0..=MAX_SNAP_ANGLES).contains(&t)
    {
        return Err(robot.place.error(
            file,
            format!("the angle snapping tolerance {t} rad is not between 0 and {MAX_SNAP_ANGLES}"),
        ));
    }
    let tree = check::check(&mut robot, &options.lock, file)?;
    if options.floating && tree.world_root {
        let root = tree
            .order
            .first()
            .map_or(&robot.place, |&r| &robot.links[r].place);
        let message = "the robot is fixed to the world by its root link `world`, so its base \
                       cannot float (--floating, `floating = true`): remove the `world` link and \
                       its joint, or import it fixed";
        return Err(root.error(file, message));
    }
    if options.floating {
        check_floating_mass(&robot, &tree, file)?;
    }
    if options.damping {
        check_damping(&robot, &tree, file)?;
    }
    let snapped = options
        .snap_angles
        .map(|t| write::snapped_angles(&robot, &tree, format::Snap::within(t)));
    let notes = tree
        .adjusted
        .iter()
        .map(|a| format!("inertia adjusted: {a}"))
        .chain(tree.renamed.iter().map(|r| format!("renamed: {r}")))
        .chain(snapped.filter(|s| s.count > 0).map(|s| {
            format!(
                "angles snapped: {} written as multiples of pi/2, moved by at most {:.2e} rad",
                s.count, s.largest
            )
        }))
        .collect();
    Ok(UrdfImport {
        text: write::write(&robot, &tree, &struct_name, options),
        notes,
        snapped,
    })
}

/// Refuses a floating root that carries no mass (nor does any link fixed to it) with at
/// most one joint moving from it: the base turning with that joint's motion while the joint
/// moves back moves nothing, so M is singular at every q (an arm's empty `base_link`
/// imported with `--floating`).
fn check_floating_mass(
    robot: &robot::Robot,
    tree: &check::Tree,
    file: &str,
) -> Result<(), UrdfError> {
    let Some(&root) = tree.order.first() else {
        return Ok(());
    };
    // The root's rigid group: the links joined to it by fixed or locked joints (parents
    // come before their children in `order`).
    let mut rigid = vec![false; robot.links.len()];
    rigid[root] = true;
    let mut moving = Vec::new();
    for &link in &tree.order[1..] {
        if let (Some(parent), Some(joint)) = (tree.parent_link[link], tree.parent_joint[link])
            && rigid[parent]
        {
            match tree.coordinates[joint] {
                None => rigid[link] = true,
                Some(_) => moving.push(joint),
            }
        }
    }
    let mass: f64 = (robot.links.iter().zip(&rigid))
        .filter(|(_, r)| **r)
        .filter_map(|(l, _)| l.inertial.as_ref().map(|i| i.mass))
        .sum();
    if mass > 0.0 || moving.len() > 1 {
        return Ok(());
    }
    let name = &robot.links[root].name;
    let how = match moving.first() {
        Some(&j) => format!(
            "one joint, \"{}\", moves from it: the base turning with that joint while the \
             joint turns back moves nothing",
            robot.joints[j].name
        ),
        None => "no joint moves from it".to_string(),
    };
    let message = format!(
        "the floating base `{name}` is massless (no <inertial> with a mass, on it or on a link \
         fixed to it) and {how}, so M is singular: give `{name}` an <inertial>, or import \
         the robot fixed (without --floating, `floating = true`)"
    );
    Err(robot.links[root].place.error(file, message))
}

/// Refuses a damping to be imported that is negative (or not finite): such a damper would
/// feed the joint energy.
fn check_damping(robot: &robot::Robot, tree: &check::Tree, file: &str) -> Result<(), UrdfError> {
    for (joint, q) in robot.joints.iter().zip(&tree.coordinates) {
        if let (Some(d), Some(_)) = (&joint.dynamics, q)
            && !(d.damping >= 0.0 && d.damping.is_finite())
        {
            let message = format!(
                "the damping of joint \"{}\" is {}: a damper takes energy out, \
                 so b >= 0",
                joint.name, d.damping
            );
            return Err(d.place.error(file, message));
        }
    }
    Ok(())
}

#[cfg(test)]
mod snap_tests;
#[cfg(test)]
mod tests;
