//! What a declaration's `draw` section declares: named points, each fixed to the ground or
//! moving with the mechanism, the polylines drawn through them, and the points whose paths
//! are traced. Positions are in the declaration's units (usually m), in the world frame.

/// One drawn point.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawnPoint {
    /// Its name in the declaration (`O`, `A`, `C2`).
    pub name: String,
    /// A ground point (drawn with a ground symbol); otherwise a joint or body point.
    pub ground: bool,
}

/// The picture of a mechanism: points, and polylines through them by index.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Drawing {
    /// The points, in the order their positions are evaluated.
    pub points: Vec<DrawnPoint>,
    /// Polylines: each a list of point indices, drawn as connected segments (`line O, A;`).
    pub lines: Vec<Vec<usize>>,
    /// Points whose paths are traced in the animation.
    pub traces: Vec<usize>,
}

impl Drawing {
    /// The drawing of a mechanism with static sizes, from the constants `mechanism!` emits.
    pub fn from_static(points: &[(&str, bool)], lines: &[&[usize]], traces: &[usize]) -> Self {
        Self {
            points: points
                .iter()
                .map(|&(name, ground)| DrawnPoint {
                    name: name.to_string(),
                    ground,
                })
                .collect(),
            lines: lines.iter().map(|l| l.to_vec()).collect(),
            traces: traces.to_vec(),
        }
    }

    /// True when nothing is declared.
    pub fn is_empty(&self) -> bool {
        self.points.is_empty()
    }

    /// Every segment of every polyline, as index pairs: `line O, A, B;` gives (O, A), (A, B).
    pub fn segments(&self) -> Vec<(usize, usize)> {
        self.lines
            .iter()
            .flat_map(|l| l.windows(2).map(|w| (w[0], w[1])))
            .collect()
    }
}
