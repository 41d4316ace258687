//! What a figure shows, apart from how it is drawn: a title over panels stacked vertically,
//! each with its lines (the data), and the legend geometry that axes and drawing share.

/// Distance of the legend box from the plot edges, and its inner padding (px).
pub(super) const LEGEND_MARGIN: i32 = 14;

/// One line of a panel.
pub(super) struct Line {
    pub(super) label: String,
    pub(super) y: Vec<f64>,
}

/// One set of axes.
pub(super) struct Panel<'a> {
    pub(super) t: &'a [f64],
    pub(super) lines: Vec<Line>,
    pub(super) y_label: String,
    /// Draw the x-axis description (only the bottom panel does).
    pub(super) x_label: bool,
    /// y holds log10 of the data; axis ticks at whole decades.
    pub(super) log: bool,
    /// Magnitude of the quantity across the mechanism: a spread below 1e-12 of it is
    /// round-off and drawn constant (`axes::linear_range`); unused on a log axis.
    pub(super) scale: f64,
}

/// A figure: a title over panels stacked vertically.
pub(super) struct Spec<'a> {
    pub(super) title: String,
    pub(super) height: u32,
    pub(super) panels: Vec<Panel<'a>>,
}
