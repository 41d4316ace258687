//! The drawing of a mechanism: the points a `draw` section names, as world vectors in
//! (q, t) and the parameters, each marked ground when it depends on no coordinate and not
//! on time, with the lines and traces by index.

use crate::algebra::expr::Vec3;
use crate::algebra::expr::{Arena, SymbolId};
use crate::error::{DeclarationError, Error, Location, Result};
use crate::syntax::draw::DrawSection;

/// One drawn point.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawnPoint {
    /// Its name in the declaration.
    pub name: String,
    /// World position (x, y, z) in q, t and the parameters.
    pub position: Vec3,
    /// Depends on no coordinate and not on time: fixed to the ground.
    pub ground: bool,
    /// Where the drawing first names it.
    pub location: Location,
}

/// The declared drawing: points in order of first mention, polylines and traces by index.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Drawing {
    /// The drawn points.
    pub points: Vec<DrawnPoint>,
    /// Polylines through the points (`line O, A, B;`).
    pub lines: Vec<Vec<usize>>,
    /// Points whose paths are traced (`trace B;`).
    pub traces: Vec<usize>,
}

/// Builds the drawing of `section`: `vector(name)` is the world position of a declared point
/// or body (None for other names), `is_axis(name)` tells directions apart from points, and
/// `moving` are the symbols (coordinates and time) that make a point move.
pub(crate) fn build_drawing(
    arena: &Arena,
    section: &DrawSection,
    vector: impl Fn(&str) -> Option<Vec3>,
    is_axis: impl Fn(&str) -> bool,
    moving: &[SymbolId],
) -> Result<Drawing> {
    let mut drawing = Drawing::default();
    let index = |name: &str, at: Location, drawing: &mut Drawing| -> Result<usize> {
        if let Some(i) = drawing.points.iter().position(|p| p.name == name) {
            return Ok(i);
        }
        if is_axis(name) {
            let kind = DeclarationError::DrawnAxis { name: name.into() };
            return Err(Error::declaration(kind, at));
        }
        let position = vector(name).ok_or_else(|| {
            let kind = DeclarationError::UnknownDrawnPoint { name: name.into() };
            Error::declaration(kind, at)
        })?;
        let ground = !position
            .iter()
            .any(|&c| moving.iter().any(|&s| arena.depends_on(c, s)));
        drawing.points.push(DrawnPoint {
            name: name.to_string(),
            position,
            ground,
            location: at,
        });
        Ok(drawing.points.len() - 1)
    };
    for line in &section.lines {
        let mut l = Vec::with_capacity(line.len());
        for (name, at) in line {
            l.push(index(name, *at, &mut drawing)?);
        }
        drawing.lines.push(l);
    }
    for (name, at) in &section.traces {
        let i = index(name, *at, &mut drawing)?;
        if !drawing.traces.contains(&i) {
            drawing.traces.push(i);
        }
    }
    Ok(drawing)
}
