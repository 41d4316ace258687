//! The [`SystemInfo`] of a derived [`Model`]: what the interpreted systems report as their
//! names, guesses, independent coordinates, row labels, drawing and joint limits.

use mechanism_codegen::Model;

use crate::system::parameters::declared_range;
use crate::system::{
    BodyOrientation, ConstraintRow, Drawing, DrawnPoint, Independent, JointLimits, RotationFactor,
    SystemInfo,
};

/// Names, guesses, independent coordinates and row labels of a model with m constraint rows.
pub(crate) fn system_info(model: &Model, m: usize) -> SystemInfo {
    SystemInfo {
        name: model.name.clone(),
        coordinates: model.coordinates.iter().map(|c| c.name.clone()).collect(),
        parameters: model.parameters.iter().map(|p| p.name.clone()).collect(),
        parameter_ranges: model
            .parameters
            .iter()
            .map(|p| declared_range(p.range))
            .collect(),
        initial_guess: model.coordinates.iter().map(|c| c.guess).collect(),
        independent: model
            .independent
            .iter()
            .map(|i| Independent {
                coordinate: i.coordinate,
                position: i.position,
                velocity: i.velocity,
            })
            .collect(),
        constraints: m,
        frames: model.links.iter().map(|l| l.name.clone()).collect(),
        velocity_rows: model.velocity_constraints.len(),
        energy_depends_on_time: model.energies_depend_on_time(),
        constraint_rows: model
            .constraints
            .iter()
            .chain(&model.velocity_constraints)
            .enumerate()
            .map(|(k, c)| {
                if c.joint.is_empty() {
                    // A hand-built Model that did not name its rows.
                    ConstraintRow::unnamed(k)
                } else {
                    ConstraintRow {
                        joint: c.joint.clone(),
                        component: c.component.clone(),
                    }
                }
            })
            .collect(),
        drawing: Drawing {
            points: model
                .drawing
                .points
                .iter()
                .map(|p| DrawnPoint {
                    name: p.name.clone(),
                    ground: p.ground,
                })
                .collect(),
            lines: model.drawing.lines.clone(),
            traces: model.drawing.traces.clone(),
        },
        orientations: (model.rotations.iter())
            .map(|r| BodyOrientation {
                body: r.body.clone(),
                factors: (r.factors.iter())
                    .map(|&(axis, coordinate)| RotationFactor { axis, coordinate })
                    .collect(),
            })
            .collect(),
        joint_limits: mechanism_codegen::declared_limits(&model.links)
            .into_iter()
            .map(|l| JointLimits {
                coordinate: l.coordinate,
                linear: l.linear,
                position: l.position,
                velocity: l.velocity,
                effort: l.effort,
            })
            .collect(),
    }
}
