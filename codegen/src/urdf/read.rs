//! Reading: the URDF's XML into a [`Robot`], every number parsed and every element's place
//! kept. Only the rigid-body content is read: `<link>` with its `<inertial>`, `<joint>` with
//! `<origin>`, `<parent>`, `<child>`, `<axis>`, `<limit>`, `<mimic>` and `<dynamics>`
//! (damping and friction, which the writer imports on request). The elements that carry no
//! rigid-body dynamics are skipped: `<visual>`, `<collision>`, `<material>`,
//! `<transmission>`, `<gazebo>`, `<safety_controller>`, `<calibration>`.

use roxmltree::{Document, Node, ParsingOptions};

use super::bounds::{ANGLE, Bound, DAMPING, DIRECTION, INERTIA, LENGTH, LIMIT, MASS, RATIO};
use super::error::{Place, UrdfError};
use super::robot::{Inertial, Joint, JointDynamics, JointKind, Limit, Link, Mimic, Robot};

/// The joint types the importer knows, as the messages list them.
pub(crate) const SUPPORTED_JOINTS: &str = "revolute, continuous, prismatic, fixed";

/// The URDF's default axis of a joint without `<axis>`.
const DEFAULT_AXIS: [f64; 3] = [1.0, 0.0, 0.0];

/// Shortest axis accepted: shorter ones (0 0 0 written by mistake) have no direction.
const MIN_AXIS_LENGTH: f64 = 1e-12;

/// Parses `xml` (the text of `file`) into a [`Robot`].
///
/// # Errors
/// Malformed XML (with DTDs refused, so no entity expansion), a root element other than
/// `<robot>`, unexpanded xacro macros, a missing required element or attribute, a joint type
/// other than revolute, continuous, prismatic or fixed, a malformed or non-finite number,
/// a number beyond the bound of its quantity ([`super::bounds`]), a zero-length axis.
pub(crate) fn read(xml: &str, file: &str) -> Result<Robot, UrdfError> {
    let options = ParsingOptions {
        allow_dtd: false,
        ..ParsingOptions::default()
    };
    let doc = Document::parse_with_options(xml, options).map_err(|e| xml_error(file, &e))?;
    let reader = Reader { doc: &doc, file };
    reader.robot(doc.root_element())
}

/// A syntax error of the XML as a [`UrdfError`] (its position moved out of the message).
fn xml_error(file: &str, e: &roxmltree::Error) -> UrdfError {
    let pos = e.pos();
    let text = e.to_string().replace(&format!(" at {pos}"), "");
    UrdfError {
        file: file.to_string(),
        line: pos.row as usize,
        column: pos.col as usize,
        element: String::new(),
        message: format!("not well-formed XML: {text}"),
    }
}

/// The parsed document and the file name its errors quote.
struct Reader<'a, 'input> {
    doc: &'a Document<'input>,
    file: &'a str,
}

impl<'a, 'input> Reader<'a, 'input> {
    /// Where `node` is, described by its tag and identifying attribute.
    fn place(&self, node: Node) -> Place {
        let pos = self.doc.text_pos_at(node.range().start);
        Place {
            line: pos.row as usize,
            column: pos.col as usize,
            element: describe(node),
        }
    }

    /// The error `message` at `node`.
    fn error(&self, node: Node, message: impl Into<String>) -> UrdfError {
        self.place(node).error(self.file, message)
    }

    /// The value of a required attribute.
    fn required(&self, node: Node<'a, 'input>, name: &str) -> Result<&'a str, UrdfError> {
        node.attribute(name).ok_or_else(|| {
            self.error(
                node,
                format!("<{}> has no `{name}` attribute", node.tag_name().name()),
            )
        })
    }

    /// The `N` numbers of attribute `name` of `node`, each within `bound`, or `default`
    /// when it is absent.
    fn numbers<const N: usize>(
        &self,
        node: Node,
        name: &str,
        default: [f64; N],
        bound: Bound,
    ) -> Result<[f64; N], UrdfError> {
        let Some(text) = node.attribute(name) else {
            return Ok(default);
        };
        let words: Vec<&str> = text.split_whitespace().collect();
        if words.len() != N {
            let expected = if N == 1 { "a number" } else { "numbers" };
            return Err(self.error(
                node,
                format!(
                    "{name}=\"{text}\" has {} {}, expected {N} {expected}",
                    words.len(),
                    if words.len() == 1 { "value" } else { "values" },
                ),
            ));
        }
        let mut out = [0.0; N];
        for (slot, word) in out.iter_mut().zip(&words) {
            *slot = self.number(node, name, word, bound)?;
        }
        Ok(out)
    }

    /// One finite number, `word`, of attribute `name` of `node`, within `bound`
    /// ([`super::bounds`]).
    fn number(&self, node: Node, name: &str, word: &str, bound: Bound) -> Result<f64, UrdfError> {
        match word.parse::<f64>() {
            Ok(v) if v.is_finite() => bound
                .check(v)
                .map(|()| v)
                .map_err(|why| self.error(node, format!("{name}: {why}"))),
            Ok(_) => Err(self.error(
                node,
                format!("{name}: `{word}` is not a finite number (at most about 1.8e308)"),
            )),
            Err(_) => Err(self.error(node, format!("{name}: `{word}` is not a number"))),
        }
    }

    /// The optional single number of attribute `name`, within `bound`.
    fn optional(&self, node: Node, name: &str, bound: Bound) -> Result<Option<f64>, UrdfError> {
        match node.attribute(name) {
            None => Ok(None),
            Some(_) => self
                .numbers::<1>(node, name, [0.0], bound)
                .map(|[v]| Some(v)),
        }
    }

    /// `xyz` and `rpy` of the `<origin>` child of `node` (each 0 when absent).
    fn origin(&self, node: Node) -> Result<([f64; 3], [f64; 3]), UrdfError> {
        match child(node, "origin") {
            None => Ok(([0.0; 3], [0.0; 3])),
            Some(o) => Ok((
                self.numbers(o, "xyz", [0.0; 3], LENGTH)?,
                self.numbers(o, "rpy", [0.0; 3], ANGLE)?,
            )),
        }
    }

    /// The `<robot>` element and its links and joints.
    fn robot(&self, root: Node<'a, 'input>) -> Result<Robot, UrdfError> {
        if root.tag_name().name() != "robot" {
            return Err(self.error(
                root,
                format!(
                    "the document is a <{}>, not a URDF <robot>",
                    root.tag_name().name()
                ),
            ));
        }
        let mut robot = Robot {
            name: root.attribute("name").unwrap_or_default().to_string(),
            place: self.place(root),
            links: Vec::new(),
            joints: Vec::new(),
        };
        for node in root.children().filter(Node::is_element) {
            if node
                .tag_name()
                .namespace()
                .is_some_and(|ns| ns.contains("xacro"))
            {
                return Err(self.error(
                    node,
                    "an unexpanded xacro element: run xacro on the file first and import its output",
                ));
            }
            match node.tag_name().name() {
                "link" => robot.links.push(self.link(node)?),
                "joint" => robot.joints.push(self.joint(node)?),
                // Appearance, simulator and actuator descriptions: no rigid-body dynamics.
                _ => {}
            }
        }
        if robot.links.is_empty() {
            return Err(self.error(root, "the robot has no <link>"));
        }
        Ok(robot)
    }

    /// A `<link>` and its `<inertial>`.
    fn link(&self, node: Node<'a, 'input>) -> Result<Link, UrdfError> {
        let name = self.name(node)?;
        let inertial = match child(node, "inertial") {
            None => None,
            Some(i) => Some(self.inertial(i, &name)?),
        };
        Ok(Link {
            name,
            place: self.place(node),
            inertial,
        })
    }

    /// The non-empty `name` of a link or joint.
    fn name(&self, node: Node<'a, 'input>) -> Result<String, UrdfError> {
        let name = self.required(node, "name")?;
        if name.trim().is_empty() {
            return Err(self.error(node, "the name is empty"));
        }
        Ok(name.to_string())
    }

    /// An `<inertial>` of the link `link`: `<origin>`, `<mass value>` and `<inertia>`.
    fn inertial(&self, node: Node<'a, 'input>, link: &str) -> Result<Inertial, UrdfError> {
        let (xyz, rpy) = self.origin(node)?;
        let mass_node = child(node, "mass").ok_or_else(|| {
            self.error(
                node,
                format!("the <inertial> of link \"{link}\" has no <mass>"),
            )
        })?;
        self.required(mass_node, "value")?;
        let [mass] = self.numbers(mass_node, "value", [0.0], MASS)?;
        let inertia_node = child(node, "inertia").ok_or_else(|| {
            self.error(
                node,
                format!("the <inertial> of link \"{link}\" has no <inertia>"),
            )
        })?;
        let mut inertia = [0.0; 6];
        for (slot, name) in inertia
            .iter_mut()
            .zip(["ixx", "ixy", "ixz", "iyy", "iyz", "izz"])
        {
            let text = self.required(inertia_node, name)?;
            *slot = self.number(inertia_node, name, text.trim(), INERTIA)?;
        }
        Ok(Inertial {
            place: self.place(node),
            mass,
            xyz,
            rpy,
            inertia,
            inertia_place: self.place(inertia_node),
        })
    }

    /// A `<joint>`.
    fn joint(&self, node: Node<'a, 'input>) -> Result<Joint, UrdfError> {
        let name = self.name(node)?;
        let kind = match self.required(node, "type")? {
            "revolute" => JointKind::Revolute,
            "continuous" => JointKind::Continuous,
            "prismatic" => JointKind::Prismatic,
            "fixed" => JointKind::Fixed,
            // Standard URDF types that an importer of trees of one-coordinate joints cannot
            // write: said as such, not as unknown.
            kind @ ("floating" | "planar") => {
                let what = if kind == "floating" {
                    "a free joint of six coordinates"
                } else {
                    "a joint of three coordinates in a plane"
                };
                return Err(self.error(
                    node,
                    format!(
                        "joint type \"{kind}\" ({what}) is not supported (supported: \
                         {SUPPORTED_JOINTS}): only the root link floats (--floating, or \
                         `floating = true` in mechanism!)"
                    ),
                ));
            }
            other => {
                return Err(self.error(
                    node,
                    format!("unknown joint type \"{other}\" (supported: {SUPPORTED_JOINTS})"),
                ));
            }
        };
        let link_of = |tag: &str| -> Result<(String, Place), UrdfError> {
            let n = child(node, tag)
                .ok_or_else(|| self.error(node, format!("joint \"{name}\" has no <{tag}>")))?;
            Ok((self.required(n, "link")?.to_string(), self.place(n)))
        };
        let (parent, parent_place) = link_of("parent")?;
        let (child_link, child_place) = link_of("child")?;
        let (xyz, rpy) = self.origin(node)?;
        let axis = match child(node, "axis") {
            Some(a) if kind != JointKind::Fixed => self.unit_axis(a, &name)?,
            _ => DEFAULT_AXIS,
        };
        // A mimic's offset is a coordinate's value: a length or an angle.
        let offset = if kind == JointKind::Prismatic {
            LENGTH
        } else {
            ANGLE
        };
        let limit = match child(node, "limit") {
            None => None,
            Some(l) => Some(self.limit(l, &name)?),
        };
        Ok(Joint {
            name,
            place: self.place(node),
            kind,
            parent,
            parent_place,
            child: child_link,
            child_place,
            xyz,
            rpy,
            axis,
            limit,
            // A fixed joint's `<mimic>` couples nothing: not read, so a placeholder one
            // (no `joint`, a bad number) does not stop the import.
            mimic: match child(node, "mimic").filter(|_| kind != JointKind::Fixed) {
                None => None,
                Some(m) => Some(Mimic {
                    joint: self.required(m, "joint")?.to_string(),
                    multiplier: self.optional(m, "multiplier", RATIO)?.unwrap_or(1.0),
                    offset: self.optional(m, "offset", offset)?.unwrap_or(0.0),
                    place: self.place(m),
                }),
            },
            dynamics: match child(node, "dynamics") {
                None => None,
                Some(d) => Some(JointDynamics {
                    damping: self.optional(d, "damping", DAMPING)?.unwrap_or(0.0),
                    friction: self.optional(d, "friction", DAMPING)?.unwrap_or(0.0),
                    place: self.place(d),
                }),
            },
            locked: false,
        })
    }

    /// `<axis xyz>` of joint `joint` as a unit vector (default 1 0 0).
    fn unit_axis(&self, node: Node, joint: &str) -> Result<[f64; 3], UrdfError> {
        let axis = self.numbers(node, "xyz", DEFAULT_AXIS, DIRECTION)?;
        let length = axis.iter().map(|a| a * a).sum::<f64>().sqrt();
        if length <= MIN_AXIS_LENGTH {
            return Err(self.error(
                node,
                format!("the axis of joint \"{joint}\" has zero length: it has no direction"),
            ));
        }
        if length == 1.0 {
            Ok(axis)
        } else {
            Ok(axis.map(|a| a / length))
        }
    }

    /// A `<limit>` of joint `joint`: `lower <= upper`, velocity and effort not negative.
    fn limit(&self, node: Node, joint: &str) -> Result<Limit, UrdfError> {
        let limit = Limit {
            lower: self.optional(node, "lower", LIMIT)?,
            upper: self.optional(node, "upper", LIMIT)?,
            velocity: self.optional(node, "velocity", LIMIT)?,
            effort: self.optional(node, "effort", LIMIT)?,
        };
        if let Some([lower, upper]) = limit.range()
            && lower > upper
        {
            return Err(self.error(
                node,
                format!("joint \"{joint}\": lower limit {lower} is above upper limit {upper}"),
            ));
        }
        for (name, value) in [("velocity", limit.velocity), ("effort", limit.effort)] {
            if let Some(v) = value
                && v < 0.0
            {
                return Err(self.error(
                    node,
                    format!("joint \"{joint}\": the {name} limit {v} is negative"),
                ));
            }
        }
        Ok(limit)
    }
}

/// The first child element of `node` called `tag`.
fn child<'a, 'input>(node: Node<'a, 'input>, tag: &str) -> Option<Node<'a, 'input>> {
    node.children()
        .find(|c| c.is_element() && c.tag_name().name() == tag)
}

/// The element as it opens, with the attribute that identifies it: `<joint name="elbow">`,
/// `<parent link="base">`, `<mimic joint="finger_1">`, or just `<inertia>`.
fn describe(node: Node) -> String {
    let tag = node.tag_name().name();
    ["name", "link", "joint"]
        .iter()
        .find_map(|key| {
            node.attribute(*key)
                .map(|v| format!("<{tag} {key}=\"{v}\">"))
        })
        .unwrap_or_else(|| format!("<{tag}>"))
}
