//! Drawing: the mesh and line styles of a figure described by a [`Spec`], and [`render`]
//! to PNG and SVG.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::ranged1d::Ranged;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::axes::{
    Decades, decade_label, decade_range, linear_range, place_legend, thin, tick_label,
    tick_label_spanning, time_range,
};
use super::font::{FONT, register_font};
use super::spec::{LEGEND_MARGIN, Panel, Spec};
use super::title::{draw_title, glyph_offsets};
use crate::output::{OutputError, ensure_dir, write_atomically};

const WIDTH: u32 = 1000;
/// MATLAB's default line colours.
pub(super) const PALETTE: [RGBColor; 7] = [
    RGBColor(0, 114, 189),
    RGBColor(217, 83, 25),
    RGBColor(237, 177, 32),
    RGBColor(126, 47, 142),
    RGBColor(119, 172, 48),
    RGBColor(77, 190, 238),
    RGBColor(162, 20, 47),
];

/// Tick labels asked of a linear y axis.
const Y_TICKS: usize = 8;
/// Least width (px) of the y label area: room for a tick label of 6 characters and the
/// rotated axis title.
const MIN_Y_AREA: u32 = 110;

/// Width (px) of the y label area for these tick labels: the widest label at 18 px plus
/// 36 px for the tick, the gap and the rotated axis title (the rolling disc's height,
/// `0.0999985`, ran into its title `z (m)` in the fixed 110 px), at least [`MIN_Y_AREA`].
fn y_label_area(labels: impl Iterator<Item = String>) -> u32 {
    let widest = labels
        .map(|label| glyph_offsets(&label, 18.0).1)
        .fold(0.0_f32, f32::max);
    (widest.ceil() as u32 + 36).max(MIN_Y_AREA)
}

/// Draws one panel into `area`.
fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel<'_>,
    brush: bool,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let x = time_range(panel.t);
    let all = || panel.lines.iter().flat_map(|l| l.y.iter());
    let y = if panel.log {
        decade_range(all())
    } else {
        linear_range(all(), panel.scale)
    };
    let x_area = if panel.x_label { 62 } else { 36 };
    let y_area = if panel.log {
        MIN_Y_AREA
    } else {
        let span = y.1 - y.0;
        y_label_area(
            RangedCoordf64::from(y.0..y.1)
                .key_points(Y_TICKS)
                .into_iter()
                .map(|v| tick_label_spanning(v, span)),
        )
    };
    let (w, h) = area.dim_in_pixel();
    let plot = (
        f64::from(w) - f64::from(y_area) - 40.0,
        f64::from(h) - f64::from(x_area) - 24.0,
    );
    let (legend, y) = place_legend(panel, x, y, (plot.0.max(100.0), plot.1.max(100.0)));
    let mut builder = ChartBuilder::on(area);
    builder
        .margin(12)
        .margin_right(28)
        .x_label_area_size(x_area)
        .y_label_area_size(y_area);
    if panel.log {
        let y_range = Decades { lo: y.0, hi: y.1 };
        let mut chart = builder.build_cartesian_2d(x.0..x.1, y_range).map_err(err)?;
        let mut mesh = chart.configure_mesh();
        style_mesh(&mut mesh, panel);
        mesh.y_label_formatter(&decade_label)
            .x_max_light_lines(0)
            .y_max_light_lines(9)
            .draw()
            .map_err(err)?;
        draw_lines(&mut chart, panel, (x, y), legend, brush)?;
    } else {
        let mut chart = builder
            .build_cartesian_2d(x.0..x.1, y.0..y.1)
            .map_err(err)?;
        let mut mesh = chart.configure_mesh();
        style_mesh(&mut mesh, panel);
        let span = y.1 - y.0;
        let label = |v: &f64| tick_label_spanning(*v, span);
        mesh.y_labels(Y_TICKS)
            .y_label_formatter(&label)
            .max_light_lines(0)
            .draw()
            .map_err(err)?;
        draw_lines(&mut chart, panel, (x, y), legend, brush)?;
    }
    Ok(())
}

fn style_mesh<DB: DrawingBackend, X: Ranged<ValueType = f64>, Y: Ranged<ValueType = f64>>(
    mesh: &mut plotters::chart::MeshStyle<'_, '_, X, Y, DB>,
    panel: &Panel<'_>,
) {
    mesh.x_labels(11)
        .x_label_formatter(&tick_label)
        .label_style((FONT, 18))
        .axis_desc_style((FONT, 22))
        .bold_line_style(RGBColor(205, 205, 205).stroke_width(1))
        .light_line_style(RGBColor(238, 238, 238).stroke_width(1))
        .axis_style(BLACK.stroke_width(2))
        .set_all_tick_mark_size(6)
        .y_desc(panel.y_label.as_str());
    if panel.x_label {
        mesh.x_desc("t (s)");
    }
}

/// Draws a 3 px polyline on a bitmap as nine 1 px paths over a 3x3 brush. (For wide lines
/// plotters fills one polygon around the whole path, which grows spikes at sharp turns and
/// ragged edges along dense data.)
fn draw_brushed<
    'a,
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
>(
    chart: &ChartContext<'a, DB, Cartesian2d<X, Y>>,
    points: &[(f64, f64)],
    color: RGBColor,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let area = chart.plotting_area().strip_coord_spec();
    let (x0, y0) = area.get_base_pixel();
    let mut pixels: Vec<(i32, i32)> = points
        .iter()
        .map(|p| chart.backend_coord(p))
        .map(|(x, y)| (x - x0, y - y0))
        .collect();
    pixels.dedup();
    for dx in -1..=1 {
        for dy in -1..=1 {
            let shifted = pixels
                .iter()
                .map(|&(x, y)| (x + dx, y + dy))
                .collect::<Vec<_>>();
            area.draw(&PathElement::new(shifted, color.stroke_width(1)))?;
        }
    }
    Ok(())
}

fn draw_lines<
    'a,
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    panel: &Panel<'_>,
    (x, y): ((f64, f64), (f64, f64)),
    legend: SeriesLabelPosition,
    brush: bool,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    // The box around the plot area, as MATLAB draws it.
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(x.0, y.0), (x.1, y.1)],
            BLACK.stroke_width(1),
        )))
        .map_err(err)?;
    for (i, line) in panel.lines.iter().enumerate() {
        let color = PALETTE[i % PALETTE.len()];
        let style = color.stroke_width(3);
        let points = thin(panel.t, &line.y);
        let series = if brush {
            draw_brushed(chart, &points, color).map_err(err)?;
            chart.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
        } else {
            chart.draw_series(LineSeries::new(points, style))
        };
        series
            .map_err(err)?
            .label(line.label.as_str())
            .legend(move |(px, py)| PathElement::new(vec![(px, py), (px + 36, py)], style));
    }
    chart
        .configure_series_labels()
        .position(legend)
        .label_font((FONT, 20))
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK.stroke_width(1))
        .legend_area_size(44)
        .margin(LEGEND_MARGIN)
        .draw()
        .map_err(err)
}

fn draw_figure<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    spec: &Spec<'_>,
    brush: bool,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    // Where plotters' `titled` puts a 26 px title: 5 px down, the panels 30 px below that.
    draw_title(&root, &spec.title, 26, 5, brush).map_err(err)?;
    let root = root.margin(30, 0, 0, 0);
    let areas = root.split_evenly((spec.panels.len().max(1), 1));
    for (area, panel) in areas.iter().zip(&spec.panels) {
        draw_panel(area, panel, brush)?;
    }
    root.present().map_err(err)
}

/// What a figure draws on either backend: `bitmap` says which (the title's glyphs and the
/// 3 px lines are placed by hand on a bitmap).
pub(super) trait Drawing {
    /// Draws the figure on `area`.
    fn draw<DB: DrawingBackend>(
        &self,
        area: DrawingArea<DB, Shift>,
        bitmap: bool,
    ) -> Result<(), String>;
}

impl Drawing for Spec<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        area: DrawingArea<DB, Shift>,
        bitmap: bool,
    ) -> Result<(), String> {
        draw_figure(area, self, bitmap)
    }
}

/// Writes `drawing` as `<stem>.png` and `<stem>.svg` of `size` px, each whole or not at all,
/// creating the folder; returns their paths.
pub(super) fn write_png_and_svg(
    stem: &Path,
    size: (u32, u32),
    drawing: &impl Drawing,
) -> Result<Vec<PathBuf>, OutputError> {
    let png = stem.with_extension("png");
    let svg = stem.with_extension("svg");
    let plot_err = |path: &Path| {
        let path = path.to_path_buf();
        move |message: String| OutputError::Plot { path, message }
    };
    if let Some(dir) = stem.parent().filter(|d| !d.as_os_str().is_empty()) {
        ensure_dir(dir)?;
    }
    register_font().map_err(plot_err(&png))?;
    // Each backend writes its file when the drawing is presented and is dropped before
    // the rename: plotters picks the format from the temporary's extension.
    write_atomically(&png, |partial| {
        let area = BitMapBackend::new(partial, size).into_drawing_area();
        drawing.draw(area, true).map_err(plot_err(&png))
    })?;
    write_atomically(&svg, |partial| {
        let area = SVGBackend::new(partial, size).into_drawing_area();
        drawing.draw(area, false).map_err(plot_err(&svg))
    })?;
    Ok(vec![png, svg])
}

/// Checks the figure's data and writes it as `<stem>.png` and `<stem>.svg`.
pub(super) fn render(stem: &Path, spec: &Spec<'_>) -> Result<Vec<PathBuf>, OutputError> {
    for panel in &spec.panels {
        if panel.t.is_empty() || panel.lines.iter().any(|l| l.y.len() != panel.t.len()) {
            let msg = format!(
                "{} times and series of lengths {:?}",
                panel.t.len(),
                panel.lines.iter().map(|l| l.y.len()).collect::<Vec<_>>()
            );
            let png = stem.with_extension("png");
            return Err(OutputError::invalid(png.display().to_string(), msg));
        }
    }
    write_png_and_svg(stem, (WIDTH, spec.height), spec)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_y_label_area_widens_for_long_tick_labels() {
        // DejaVu Sans at 18 px (ascent - descent = 2384 font units = 18 px): a digit
        // advances 1303 units (9.84 px), `.` 651 (4.92 px), `−` 1716 (12.96 px).
        // "0.0999985": 8 digits and a point, 83.6 px; + 36 px = 119.6, so 120.
        let area = |labels: &[&str]| y_label_area(labels.iter().map(|l| l.to_string()));
        assert_eq!(area(&["0.1000005", "0.0999985", "0.099997"]), 120);
        // "−0.015": 57.2 px + 36 = 93 px: the least width, 110.
        assert_eq!(area(&["−0.015", "−0.01", "0"]), MIN_Y_AREA);
        assert_eq!(area(&[]), MIN_Y_AREA);
    }
}
