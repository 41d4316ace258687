//! The overview figure of a large mechanism: every coordinate over time in one heat map,
//! one row per coordinate, each row coloured from its own minimum (dark) to its own maximum
//! (bright), so 82 or 401 coordinates fit one readable page where one figure each would be
//! hundreds of files.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::axes::{ROUND_OFF, tick_label, time_range};
use super::font::FONT;
use super::pretty_name;
use super::render::{Drawing, write_png_and_svg};
use super::title::draw_title;
use crate::output::{OutputError, Unit};

/// Least height of a labelled row (px): names are thinned to every k-th row below it.
const LABEL_PITCH: f64 = 18.0;
/// Colour of a row that stays constant (to round-off) over the run.
const CONSTANT: RGBColor = RGBColor(200, 200, 200);

/// Writes `<stem>.png` and `<stem>.svg`: `q[i]` over `t` for every coordinate `names[i]`
/// (units `units[i]`, which set the scale a constant row is judged against), as a heat map
/// with a colour bar. The map is one image of the plot's size (in the SVG an embedded PNG,
/// so its size does not grow with the samples). Fails on empty or inconsistent series.
pub fn plot_overview(
    stem: &Path,
    names: &[String],
    units: &[Unit],
    t: &[f64],
    q: &[Vec<f64>],
) -> Result<Vec<PathBuf>, OutputError> {
    let png = stem.with_extension("png");
    if t.is_empty() || q.is_empty() || q.len() != names.len() || units.len() != names.len() {
        return Err(OutputError::invalid(
            png.display().to_string(),
            format!(
                "{} times, {} series, {} names, {} units",
                t.len(),
                q.len(),
                names.len(),
                units.len()
            ),
        ));
    }
    if let Some(bad) = q.iter().position(|s| s.len() != t.len()) {
        return Err(OutputError::invalid(
            png.display().to_string(),
            format!(
                "{} has {} values for {} times",
                names[bad],
                q[bad].len(),
                t.len()
            ),
        ));
    }
    let map = HeatMap::new(names, units, t, q);
    write_png_and_svg(stem, (1000, map.height()), &map)
}

impl Drawing for HeatMap<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        area: DrawingArea<DB, Shift>,
        bitmap: bool,
    ) -> Result<(), String> {
        draw(area, self, bitmap)
    }
}

/// The series scaled for colour: each row from its own minimum (0) to its maximum (1), or
/// `None` where the row is constant to round-off or the value is not finite.
struct HeatMap<'a> {
    names: Vec<String>,
    t: &'a [f64],
    q: &'a [Vec<f64>],
    /// (minimum, maximum) of each row; `None` for a constant row.
    ranges: Vec<Option<(f64, f64)>>,
    time: (f64, f64),
}

impl<'a> HeatMap<'a> {
    fn new(names: &[String], units: &[Unit], t: &'a [f64], q: &'a [Vec<f64>]) -> Self {
        let finite = |s: &[f64]| -> (f64, f64) {
            s.iter()
                .filter(|v| v.is_finite())
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                    (a.min(v), b.max(v))
                })
        };
        let extent: Vec<(f64, f64)> = q.iter().map(|s| finite(s)).collect();
        // The scale a row's spread is judged against: the largest |q| of its unit.
        let scale = |unit: Unit| {
            extent
                .iter()
                .zip(units)
                .filter(|&(&(lo, hi), &u)| u == unit && lo <= hi)
                .map(|(&(lo, hi), _)| lo.abs().max(hi.abs()))
                .fold(0.0, f64::max)
        };
        let ranges = extent
            .iter()
            .zip(units)
            .map(|(&(lo, hi), &unit)| {
                let magnitude = scale(unit).max(lo.abs()).max(hi.abs());
                (lo <= hi && hi - lo > ROUND_OFF * magnitude).then_some((lo, hi))
            })
            .collect();
        Self {
            names: names.iter().map(|n| pretty_name(n)).collect(),
            t,
            q,
            ranges,
            time: time_range(t),
        }
    }

    /// Row `row` at sample `k` scaled to [0, 1]; `None` for a constant row or a value that
    /// is not finite.
    fn value(&self, row: usize, k: usize) -> Option<f64> {
        let (lo, hi) = self.ranges[row]?;
        let v = self.q[row][k];
        v.is_finite()
            .then(|| ((v - lo) / (hi - lo)).clamp(0.0, 1.0))
    }

    /// The sample shown at time `time`: the last one at or before it.
    fn sample_at(&self, time: f64) -> usize {
        self.t.partition_point(|&s| s <= time).saturating_sub(1)
    }

    /// The map as RGB pixels, `width` x `height`, row 0 at the top.
    fn pixels(&self, width: u32, height: u32) -> Vec<u8> {
        let n = self.names.len();
        let (t0, t1) = self.time;
        let columns: Vec<usize> = (0..width)
            .map(|x| self.sample_at(t0 + (f64::from(x) + 0.5) / f64::from(width) * (t1 - t0)))
            .collect();
        let mut out = Vec::with_capacity(3 * (width * height) as usize);
        for y in 0..height {
            let row = ((f64::from(y) + 0.5) / f64::from(height) * n as f64) as usize;
            let row = row.min(n - 1);
            for &k in &columns {
                let RGBColor(r, g, b) = self.value(row, k).map_or(CONSTANT, viridis);
                out.extend([r, g, b]);
            }
        }
        out
    }

    fn constant_rows(&self) -> usize {
        self.ranges.iter().filter(|r| r.is_none()).count()
    }

    /// The plot's height: [`LABEL_PITCH`] px a row, between 300 and 800 px, so that every
    /// row is named up to 44 rows (Bricard's 30 and the bodies four-bar's 18 named every
    /// second row in 300 px).
    fn plot_height(&self) -> u32 {
        (LABEL_PITCH as usize * self.names.len()).clamp(300, 800) as u32
    }

    /// Rows are named every k-th, k such that names stand [`LABEL_PITCH`] px apart.
    fn label_step(&self) -> usize {
        (LABEL_PITCH * self.names.len() as f64 / f64::from(self.plot_height()))
            .ceil()
            .max(1.0) as usize
    }

    fn height(&self) -> u32 {
        self.plot_height() + 150
    }
}

/// Viridis at 0, 1/4, 1/2, 3/4 and 1 (matplotlib's default map: perceptually uniform and
/// readable in grey), linearly interpolated.
fn viridis(x: f64) -> RGBColor {
    const STOPS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let x = x.clamp(0.0, 1.0) * 4.0;
    let k = (x.floor() as usize).min(3);
    let f = x - k as f64;
    let (a, b) = (STOPS[k], STOPS[k + 1]);
    let mix = |p: f64, q: f64| (p + f * (q - p)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    map: &HeatMap,
    bitmap: bool,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let n = map.names.len();
    let title = format!(
        "All {n} coordinates over time: each row from its minimum (dark) to its maximum (bright)"
    );
    draw_title(&root, &title, 22, 5, bitmap).map_err(err)?;
    let root = root.margin(30, 0, 0, 0);
    let (main, bar) = root.split_horizontally(880);
    let rows = n as f64;
    let mut chart = ChartBuilder::on(&main)
        .margin(12)
        .x_label_area_size(62)
        .y_label_area_size(130)
        .build_cartesian_2d(map.time.0..map.time.1, 0.0..rows)
        .map_err(err)?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .disable_x_mesh()
        .y_labels(0)
        .x_labels(11)
        .x_label_formatter(&tick_label)
        .label_style((FONT, 18))
        .axis_desc_style((FONT, 22))
        .axis_style(BLACK.stroke_width(2))
        .x_desc("t (s)")
        .y_desc("coordinate")
        .draw()
        .map_err(err)?;
    // The map: one pixel per pixel of the plot area.
    let plot = chart.plotting_area().strip_coord_spec();
    let (w, h) = plot.dim_in_pixel();
    let image = BitMapElement::with_owned_buffer((0, 0), (w, h), map.pixels(w, h))
        .ok_or_else(|| format!("a {w} x {h} image"))?;
    plot.draw(&image).map_err(err)?;
    // Row 0 at the top.
    let y = |row: usize| rows - row as f64;
    let every = map.label_step();
    let style = TextStyle::from((FONT, 15).into_font()).pos(Pos::new(HPos::Right, VPos::Center));
    chart
        .draw_series((0..n).step_by(every).map(|row| {
            EmptyElement::at((map.time.0, y(row) - 0.5))
                + Text::new(map.names[row].clone(), (-8, 0), style.clone())
        }))
        .map_err(err)?;
    draw_colour_bar(&bar, map).map_err(err)
}

/// The colour bar: min at the bottom, max at the top, and the grey of constant rows.
fn draw_colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    map: &HeatMap,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (top, height) = (30, map.plot_height() as i32 - 40);
    let (x0, x1) = (20, 44);
    for k in 0..height {
        let y = top + height - 1 - k;
        let colour = viridis((f64::from(k) + 0.5) / f64::from(height));
        area.draw(&PathElement::new(vec![(x0, y), (x1, y)], colour))?;
    }
    area.draw(&Rectangle::new(
        [(x0, top), (x1, top + height)],
        BLACK.stroke_width(1),
    ))?;
    let font = (FONT, 16).into_font();
    area.draw(&Text::new("max", (x1 + 6, top - 2), font.clone()))?;
    area.draw(&Text::new("min", (x1 + 6, top + height - 14), font.clone()))?;
    if map.constant_rows() > 0 {
        let y = top + height + 24;
        area.draw(&Rectangle::new([(x0, y), (x1, y + 16)], CONSTANT.filled()))?;
        area.draw(&Text::new("const.", (x0 - 8, y + 20), font))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_row_is_named_up_to_44_rows_and_every_second_at_82() {
        let map = |n: usize| {
            let t = vec![0.0, 1.0];
            let names: Vec<String> = (0..n).map(|i| format!("q{i}")).collect();
            let q: Vec<Vec<f64>> = (0..n).map(|i| vec![0.0, i as f64]).collect();
            let units = vec![Unit::Length; n];
            let map = HeatMap::new(&names, &units, &t, &q);
            (map.plot_height(), map.label_step())
        };
        // 18 px a row: the bodies four-bar's 18 rows, Bricard's 30, and 44 (792 px).
        assert_eq!(map(18), (324, 1));
        assert_eq!(map(30), (540, 1));
        assert_eq!(map(44), (792, 1));
        // Past 800 px: A02's 82 rows are 9.8 px apart, named every second.
        assert_eq!(map(82), (800, 2));
        // Few rows keep the least height.
        assert_eq!(map(3), (300, 1));
    }

    #[test]
    fn each_row_spans_its_own_range_and_round_off_is_constant() {
        let t: Vec<f64> = (0..1001).map(|k| k as f64 * 0.01).collect();
        // x1 rises from 2 m to 3 m; y1 stays at 0 +- 1e-15 m, round-off in a metre-size
        // mechanism; y2 moves by 1 mm, which is motion.
        let ramp: Vec<f64> = t.iter().map(|&t| 2.0 + t / 10.0).collect();
        let noise: Vec<f64> = (0..1001)
            .map(|k| if k % 2 == 0 { 1e-15 } else { -1e-15 })
            .collect();
        let small: Vec<f64> = t.iter().map(|&t| 1e-3 * (t / 10.0)).collect();
        let names = ["x1", "y1", "y2"].map(String::from);
        let q = [ramp, noise, small];
        let map = HeatMap::new(&names, &[Unit::Length; 3], &t, &q);
        assert_eq!(map.constant_rows(), 1);
        assert_eq!(
            (map.value(0, 0), map.value(0, 1000)),
            (Some(0.0), Some(1.0))
        );
        assert!((map.value(0, 500).unwrap() - 0.5).abs() < 1e-12);
        assert_eq!(map.value(1, 7), None);
        assert_eq!(map.value(2, 1000), Some(1.0));
        // Pixels: row 0 on top; pixel column x shows the sample at its middle, t = (x + 0.5)
        // / 100 * 10 s (column 0: sample 5 of x1, 0.005 of its range: dark; column 99:
        // sample 995, 0.995: bright); the constant row grey.
        let px = map.pixels(100, 30);
        let at = |x: usize, y: usize| px[3 * (100 * y + x)..3 * (100 * y + x) + 3].to_vec();
        let rgb = |c: RGBColor| vec![c.0, c.1, c.2];
        assert_eq!(at(0, 0), rgb(viridis(0.005)));
        // (9.95 s falls at sample 994 or 995 by the rounding of the times.)
        let right = at(99, 0);
        assert!(
            right == rgb(viridis(0.995)) || right == rgb(viridis(0.994)),
            "{right:?}"
        );
        assert_eq!(at(50, 15), rgb(CONSTANT));
        assert_eq!(viridis(0.0), RGBColor(68, 1, 84));
        assert_eq!(viridis(1.0), RGBColor(253, 231, 37));
    }
}
