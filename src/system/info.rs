//! Names and declared data of a system: coordinates, parameters, the independent
//! coordinates and initial guesses, and where each constraint row comes from.

use super::drawing::Drawing;
use super::joint_limits::JointLimits;
use super::mechanism::Independent;
use super::parameter_range::ParameterRange;
use super::rotation_factor::RotationFactor;

/// Where one scalar constraint row comes from: the statement that declared it and which of
/// its rows it is. Lets the runtime name a row (`revolute(B1, B2, z, z) y`) and the joints
/// that share a redundant part of the multipliers.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstraintRow {
    /// The statement, as the user reads it: the joint as written (`revolute(B1, B2, z, z)`,
    /// `spherical(C2, C)`, `P = Q`, `P.z = 0`) or `constraint k` for the k-th statement
    /// (1-based) of `constraints { .. }`; `row k` when the mechanism does not say.
    pub joint: String,
    /// Which row of the statement: `x`, `y`, `z` (point rows, vector equations), `axis 1`,
    /// `axis 2` (parallel axes of `revolute` and `prismatic`), `slide 1`, `slide 2`, `twist`
    /// (the other rows of `prismatic`), `1`, `2`, .. (longer vector equations); empty for a
    /// statement of one row.
    pub component: String,
}

impl ConstraintRow {
    /// The row at 0-based index `row` when nobody named it: joint `row k` with k = `row` + 1,
    /// no component.
    pub fn unnamed(row: usize) -> Self {
        Self {
            joint: format!("row {}", row + 1),
            component: String::new(),
        }
    }

    /// The joint, then a space and the component when there is one.
    pub fn label(&self) -> String {
        if self.component.is_empty() {
            self.joint.clone()
        } else {
            format!("{} {}", self.joint, self.component)
        }
    }
}

/// A body's declared orientation R = F_1 F_2 ... (body to world), factor by factor
/// (`rot_z(psi) * rot_x(phi) * rot_y(th)`).
#[derive(Clone, Debug, PartialEq)]
pub struct BodyOrientation {
    /// The body.
    pub body: String,
    /// The factors, left to right.
    pub factors: Vec<RotationFactor>,
}

/// Names and declared data of a system. The names, sizes and rows are fixed for its
/// lifetime; the initial guesses and the independent values are the declared expressions
/// at the current parameter values: [`crate::System::set_parameter`] evaluates them again.
#[derive(Clone, Debug, PartialEq)]
pub struct SystemInfo {
    /// Mechanism name.
    pub name: String,
    /// Coordinate names, in the order of q.
    pub coordinates: Vec<String>,
    /// Parameter names, in declaration order.
    pub parameters: Vec<String>,
    /// The range each parameter's declaration gives it, in declaration order (one entry per
    /// parameter; [`ParameterRange::Any`] where none is declared).
    pub parameter_ranges: Vec<ParameterRange>,
    /// Declared initial guesses for q, at the current parameter values.
    pub initial_guess: Vec<f64>,
    /// Independent coordinates and their initial values, at the current parameter values.
    pub independent: Vec<Independent>,
    /// Number of constraint rows m.
    pub constraints: usize,
    /// Where each constraint row comes from, in row order (m entries).
    pub constraint_rows: Vec<ConstraintRow>,
    /// How many of the m rows (the last ones) are velocity constraints A q' + a = 0: rows
    /// of Phi_q (A) and Phi_t (a) with Phi = 0, not integrable to positions.
    pub velocity_rows: usize,
    /// Whether T or Pi depends on t explicitly (a moving base written into `kinetic`): then
    /// T + Pi - W is not constant even for an exact solution, and its drift is no error
    /// measure ([`crate::Sample::work`] holds the work of tau and of the moving rows only).
    pub energy_depends_on_time: bool,
    /// The declared picture (`draw { .. }`); empty when the declaration has none.
    pub drawing: Drawing,
    /// The bodies' declared orientation products, in declaration order (empty without
    /// bodies): what names a singularity of their angles.
    pub orientations: Vec<BodyOrientation>,
    /// The joints' declared limits, one entry per coordinate that has any, in coordinate
    /// order (see [`JointLimits`]); empty without a link tree.
    pub joint_limits: Vec<JointLimits>,
    /// The link frames (`link` sections) in declaration order, whose placements and
    /// Jacobians [`crate::System::frame_placement`] and [`crate::System::frame_jacobian`]
    /// give; empty without links.
    pub frames: Vec<String>,
}

impl SystemInfo {
    /// Number of coordinates n.
    pub fn n(&self) -> usize {
        self.coordinates.len()
    }
    /// Number of constraint rows m.
    pub fn m(&self) -> usize {
        self.constraints
    }
    /// Number of position rows Phi(q, t) = 0: m minus the velocity rows.
    pub fn position_rows(&self) -> usize {
        self.constraints.saturating_sub(self.velocity_rows)
    }
    /// Index of the coordinate called `name`.
    pub fn coordinate_index(&self, name: &str) -> Option<usize> {
        self.coordinates.iter().position(|c| c == name)
    }
    /// Index of the parameter called `name`.
    pub fn parameter_index(&self, name: &str) -> Option<usize> {
        self.parameters.iter().position(|c| c == name)
    }
    /// The declared range of parameter `index` ([`ParameterRange::Any`] out of range).
    pub fn parameter_range(&self, index: usize) -> ParameterRange {
        self.parameter_ranges
            .get(index)
            .copied()
            .unwrap_or_default()
    }
    /// Index of the link frame called `name` in [`SystemInfo::frames`].
    pub fn frame_index(&self, name: &str) -> Option<usize> {
        self.frames.iter().position(|f| f == name)
    }
    /// The label of constraint row `row` (0-based): the joint, then a space and the
    /// component if there is one (`revolute(B1, B2, z, z) y`, `constraint 2`); `row k`
    /// (1-based) when `row` has no entry in [`SystemInfo::constraint_rows`].
    pub fn constraint_label(&self, row: usize) -> String {
        self.constraint_rows
            .get(row)
            .map_or_else(|| ConstraintRow::unnamed(row).label(), ConstraintRow::label)
    }
    /// The distinct joints of constraint rows `rows` (0-based), in order of first appearance
    /// (rows without an entry count as `row k`).
    pub fn joints_of(&self, rows: &[usize]) -> Vec<String> {
        let mut joints: Vec<String> = Vec::new();
        for &row in rows {
            let joint = self
                .constraint_rows
                .get(row)
                .map_or_else(|| ConstraintRow::unnamed(row).joint, |r| r.joint.clone());
            if !joints.contains(&joint) {
                joints.push(joint);
            }
        }
        joints
    }
}
