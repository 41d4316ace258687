//! The strobe figure: the declared drawing at evenly spaced instants of a run, superimposed
//! and fading (earliest faintest), projected on a view plane, with the paths of the traced
//! points. What an engineer sketches to judge a linkage's motion on one page.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::coord::cartesian::Cartesian2d;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

use super::font::FONT;
use super::render::{Drawing, PALETTE, write_png_and_svg};
use super::title::{draw_title, glyph_offsets};
use crate::output::{OutputError, Scene};

/// The plane the strobe figure is drawn in.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum View {
    /// A planar drawing (thinner than 1 % of its size in one axis) face on; otherwise the
    /// oblique view [`View::Oblique`] that shows all three axes.
    #[default]
    Auto,
    /// x right, y up.
    Xy,
    /// x right, z up.
    Xz,
    /// y right, z up.
    Yz,
    /// Seen from azimuth -50 deg (about z, from +x towards -y) and elevation 25 deg, z up:
    /// what an engineer sketches of a spatial linkage.
    Oblique,
}

/// A projection onto the figure: screen right and screen up as world directions, and
/// their names for the axis labels.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// World direction drawn to the right.
    pub right: [f64; 3],
    /// World direction drawn upwards.
    pub up: [f64; 3],
    /// Axis descriptions (`x`, `z`; for the oblique view, which has no world axis along
    /// the screen, what the distances are measured along; the figure adds an x, y, z triad).
    pub names: (&'static str, &'static str),
    /// No world axis lies along the screen: the figure draws an x, y, z triad.
    pub oblique: bool,
}

impl View {
    /// The projection for `scene`.
    pub fn projection(self, scene: &Scene) -> Projection {
        let plane = |right, up, names| Projection {
            right,
            up,
            names,
            oblique: false,
        };
        match self {
            View::Xy => plane([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], ("x", "y")),
            View::Xz => plane([1.0, 0.0, 0.0], [0.0, 0.0, 1.0], ("x", "z")),
            View::Yz => plane([0.0, 1.0, 0.0], [0.0, 0.0, 1.0], ("y", "z")),
            View::Oblique => {
                let (az, el) = ((-50.0_f64).to_radians(), 25.0_f64.to_radians());
                Projection {
                    oblique: true,
                    ..plane(
                        [-az.sin(), az.cos(), 0.0],
                        [-az.cos() * el.sin(), -az.sin() * el.sin(), el.cos()],
                        (
                            "across the view from azimuth −50°, elevation 25°",
                            "up the view",
                        ),
                    )
                }
            }
            View::Auto => {
                let extent = extents(scene);
                let size = extent.iter().fold(0.0_f64, |a, &e| a.max(e));
                let thin = (0..3).fold(0, |a, k| if extent[k] < extent[a] { k } else { a });
                if extent[thin] > 0.01 * size {
                    return View::Oblique.projection(scene);
                }
                [View::Yz, View::Xz, View::Xy][thin].projection(scene)
            }
        }
    }
}

/// max - min of each world axis over every point and frame.
fn extents(scene: &Scene) -> [f64; 3] {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in scene.positions.chunks_exact(3) {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]]
}

/// The frames shown: `instants` evenly spaced (first and last included) over the first
/// revolution or period of the driving coordinate ([`Scene::cycle`]) when the scene has one,
/// else over the whole scene.
pub fn strobe_frames(scene: &Scene, instants: usize) -> Vec<usize> {
    let f = scene.cycle().map_or(scene.frames(), |c| c.end + 1);
    match (f, instants) {
        (0, _) | (_, 0) => vec![],
        (_, 1) => vec![f - 1],
        _ => {
            let mut picked: Vec<usize> = (0..instants)
                .map(|i| ((i * (f - 1)) as f64 / (instants - 1) as f64).round() as usize)
                .collect();
            picked.dedup();
            picked
        }
    }
}

/// Writes `<stem>.png` and `<stem>.svg`: the drawing at `instants` evenly spaced frames,
/// superimposed, projected on `view`. Fails on an empty scene or non-finite positions.
pub fn plot_strobe(
    stem: &Path,
    scene: &Scene,
    view: View,
    instants: usize,
) -> Result<Vec<PathBuf>, OutputError> {
    let png = stem.with_extension("png");
    if scene.frames() == 0 || scene.points.is_empty() {
        return Err(OutputError::invalid(
            png.display().to_string(),
            "the scene has no frames or no points",
        ));
    }
    if scene.positions.iter().any(|v| !v.is_finite()) {
        return Err(OutputError::invalid(
            png.display().to_string(),
            "a drawn point is NaN or infinite",
        ));
    }
    let frames = strobe_frames(scene, instants);
    let frame = Frame::new(scene, view, &frames);
    let size = (1000, frame.height);
    write_png_and_svg(
        stem,
        size,
        &Strobe {
            scene,
            frame: &frame,
            instants,
        },
    )
}

/// The strobe figure as a [`Drawing`].
struct Strobe<'a> {
    scene: &'a Scene,
    frame: &'a Frame,
    instants: usize,
}

impl Drawing for Strobe<'_> {
    fn draw<DB: DrawingBackend>(
        &self,
        area: DrawingArea<DB, Shift>,
        bitmap: bool,
    ) -> Result<(), String> {
        draw(area, self.scene, self.frame, (self.instants, bitmap))
    }
}

/// The projection and the ranges of the figure: equal scales on both axes.
struct Frame {
    projection: Projection,
    u: (f64, f64),
    v: (f64, f64),
    height: u32,
}

impl Frame {
    /// The ranges hold the points at every frame from the first to the last of `frames`
    /// (the instants and the traced paths between them), not the whole run: a rolling disc's
    /// first period is not drawn at the scale of its 10 m of travel.
    fn new(scene: &Scene, view: View, frames: &[usize]) -> Self {
        let mut frame = Self {
            projection: view.projection(scene),
            u: (0.0, 0.0),
            v: (0.0, 0.0),
            height: 0,
        };
        let (mut u, mut v) = (
            (f64::INFINITY, f64::NEG_INFINITY),
            (f64::INFINITY, f64::NEG_INFINITY),
        );
        let shown = frames.first().copied().unwrap_or(0)..=frames.last().copied().unwrap_or(0);
        let points = scene.points.len();
        for p in shown.flat_map(|f| (0..points).map(move |i| (f, i))) {
            let (pu, pv) = frame.project(scene.position(p.0, p.1));
            u = (u.0.min(pu), u.1.max(pu));
            v = (v.0.min(pv), v.1.max(pv));
        }
        let span = (u.1 - u.0).max(v.1 - v.0).max(1e-9);
        // 8 % of the larger span around the drawing, so symbols at the edge stay inside.
        let pad = 0.08 * span;
        let (wu, wv) = ((u.1 - u.0) + 2.0 * pad, (v.1 - v.0) + 2.0 * pad);
        // Plot area 840 px wide; the height follows for equal scales, within 300..900 px.
        let plot_w = 840.0;
        let plot_h = (plot_w * wv / wu).clamp(300.0, 900.0);
        // Widen the narrower range so that a metre is as long on both axes.
        let scale = (wu / plot_w).max(wv / plot_h);
        let (cu, cv) = (0.5 * (u.0 + u.1), 0.5 * (v.0 + v.1));
        let (hu, hv) = (0.5 * scale * plot_w, 0.5 * scale * plot_h);
        frame.u = (cu - hu, cu + hu);
        frame.v = (cv - hv, cv + hv);
        frame.height = plot_h as u32 + 130;
        frame
    }

    fn project(&self, p: [f64; 3]) -> (f64, f64) {
        let dot = |a: [f64; 3]| a[0] * p[0] + a[1] * p[1] + a[2] * p[2];
        (dot(self.projection.right), dot(self.projection.up))
    }
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    scene: &Scene,
    frame: &Frame,
    (instants, bitmap): (usize, bool),
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let frames = strobe_frames(scene, instants);
    draw_title(&root, &strobe_title(scene, &frames), 24, 20, bitmap).map_err(err)?;
    let body = root.margin(44, 0, 0, 0);
    let mut chart = ChartBuilder::on(&body)
        .margin(20)
        .margin_top(4)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(frame.u.0..frame.u.1, frame.v.0..frame.v.1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(format!("{} (m)", frame.projection.names.0))
        .y_desc(format!("{} (m)", frame.projection.names.1))
        .label_style((FONT, 18))
        .axis_desc_style((FONT, 20))
        .light_line_style(WHITE)
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .draw()
        .map_err(err)?;
    draw_instants(&mut chart, scene, frame, &frames).map_err(err)?;
    let f = *frames.last().unwrap_or(&0);
    // Point names at the last instant; points that coincide (the two halves of a joint)
    // share one label, "B1 = A2"; a label that would overlap one already placed is left out.
    let labels = thin_labels(scene, f, |p| {
        let at = frame.project(p);
        let px = chart.backend_coord(&at);
        (at, (f64::from(px.0), f64::from(px.1)))
    });
    // Right of its point, or left of it where it would run past the plot's right edge
    // (the rolling disc's `ground_end` at the end of its drawn road).
    let right_edge = chart.plotting_area().get_pixel_range().0.end;
    let offset = |at: &(f64, f64), text: &str| {
        let width = glyph_offsets(text, 18.0).1.ceil() as i32;
        if chart.backend_coord(at).0 + 8 + width > right_edge {
            (-8 - width, -22)
        } else {
            (8, -22)
        }
    };
    let labels: Vec<_> = labels
        .into_iter()
        .map(|(at, text)| (at, offset(&at, &text), text))
        .collect();
    chart
        .draw_series(
            labels
                .into_iter()
                .map(|(at, by, text)| EmptyElement::at(at) + Text::new(text, by, (FONT, 18))),
        )
        .map_err(err)?;
    if frame.projection.oblique {
        draw_triad(&root, &frame.projection).map_err(err)?;
    }
    root.present().map_err(err)
}

/// The strobe figure's title: the mechanism, the instants and the span they cover.
fn strobe_title(scene: &Scene, frames: &[usize]) -> String {
    let (t0, t1) = (
        scene.times[frames[0]],
        scene.times[*frames.last().unwrap_or(&0)],
    );
    let span = match scene.cycle() {
        Some(c) => format!("first {} of {}, ", c.kind, c.coordinate),
        None => String::new(),
    };
    format!(
        "{}: {} instants, {span}t = {} to {} s (darker = later)",
        scene.name,
        frames.len(),
        round(t0),
        round(t1)
    )
}

/// The traced paths (thin, grey), the drawing at each of `frames` (earliest faintest) and
/// the ground points once.
fn draw_instants<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    scene: &Scene,
    frame: &Frame,
    frames: &[usize],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    // Paths of the traced points over the span of the instants (the title's t0 to t1: one
    // revolution or period when there is one), thin and grey.
    let shown = frames[0]..=*frames.last().unwrap_or(&0);
    for &i in &scene.traces {
        let path: Vec<(f64, f64)> = shown
            .clone()
            .map(|f| frame.project(scene.position(f, i)))
            .collect();
        chart.draw_series(std::iter::once(PathElement::new(
            path,
            RGBColor(150, 150, 150).stroke_width(1),
        )))?;
    }
    let last = frames.len().saturating_sub(1).max(1) as f64;
    for (k, &f) in frames.iter().enumerate() {
        // Earliest at 15 % opacity, latest opaque.
        let alpha = 0.15 + 0.85 * k as f64 / last;
        for (l, line) in scene.lines.iter().enumerate() {
            let colour = PALETTE[l % PALETTE.len()].mix(alpha);
            let path: Vec<(f64, f64)> = line
                .iter()
                .map(|&i| frame.project(scene.position(f, i)))
                .collect();
            chart.draw_series(std::iter::once(PathElement::new(
                path,
                colour.stroke_width(4),
            )))?;
        }
        let joints = scene.points.iter().enumerate().filter(|(_, p)| !p.ground);
        chart.draw_series(joints.map(|(i, _)| {
            Circle::new(
                frame.project(scene.position(f, i)),
                4,
                BLACK.mix(alpha).stroke_width(2),
            )
        }))?;
    }
    // Ground points once (they do not move): a triangle under a circle.
    let f = *frames.last().unwrap_or(&0);
    for (i, _) in scene.points.iter().enumerate().filter(|(_, p)| p.ground) {
        let at = frame.project(scene.position(f, i));
        chart.draw_series(std::iter::once(
            EmptyElement::at(at)
                + Polygon::new(
                    vec![(0, 0), (-11, 18), (11, 18)],
                    RGBColor(170, 170, 170).filled(),
                )
                + Circle::new((0, 0), 5, BLACK.stroke_width(2)),
        ))?;
    }
    Ok(())
}

/// A label: where its point is in the chart, its pixel, its text.
type Label = ((f64, f64), (f64, f64), String);

/// The labels of the points at frame `f`: coinciding points joined ("B1 = A2"), then only
/// those whose text box (18 px text, about 10 px a character) overlaps no label kept
/// before it. `place` gives a point's chart position and its pixel.
fn thin_labels(
    scene: &Scene,
    f: usize,
    place: impl Fn([f64; 3]) -> ((f64, f64), (f64, f64)),
) -> Vec<((f64, f64), String)> {
    let mut joined: Vec<Label> = Vec::new();
    for (i, p) in scene.points.iter().enumerate() {
        let (at, px) = place(scene.position(f, i));
        let close = |q: &(f64, f64)| {
            (q.0 - at.0).hypot(q.1 - at.1) <= 1e-9 * (1.0 + at.0.abs() + at.1.abs())
        };
        match joined.iter_mut().find(|(q, _, _)| close(q)) {
            Some((_, _, text)) => *text = format!("{text} = {}", p.name),
            None => joined.push((at, px, p.name.clone())),
        }
    }
    // The text box right of and above its point: x from 8 px right over its width, 18 px
    // high; two boxes clash when they come within 4 px of each other both ways.
    let span = |px: (f64, f64), text: &str| (px.0, px.0 + 10.0 * text.chars().count() as f64);
    let mut kept: Vec<Label> = Vec::new();
    for (at, px, text) in joined {
        let (a0, a1) = span(px, &text);
        let overlaps = kept.iter().any(|(_, q, other)| {
            let (b0, b1) = span(*q, other);
            a0 < b1 + 4.0 && b0 < a1 + 4.0 && (px.1 - q.1).abs() < 22.0
        });
        if !overlaps {
            kept.push((at, px, text));
        }
    }
    kept.into_iter().map(|(at, _, text)| (at, text)).collect()
}

/// The world axes x, y, z as seen in an oblique view: three 40 px arrows from the lower
/// left corner, each with its name.
fn draw_triad<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    projection: &Projection,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (_, h) = root.dim_in_pixel();
    let origin = (150, h as i32 - 120);
    for (k, name) in ["x", "y", "z"].into_iter().enumerate() {
        let (u, v) = (projection.right[k], projection.up[k]);
        let tip = (
            origin.0 + (40.0 * u).round() as i32,
            origin.1 - (40.0 * v).round() as i32,
        );
        root.draw(&PathElement::new(vec![origin, tip], BLACK.stroke_width(2)))?;
        let label = (
            origin.0 + (52.0 * u).round() as i32 - 5,
            origin.1 - (52.0 * v).round() as i32 - 9,
        );
        root.draw(&Text::new(name, label, (FONT, 18)))?;
    }
    Ok(())
}

/// An axis label: 3 significant decimals at most, and never `-0`.
fn tick(v: f64) -> String {
    let s = round(v);
    if s == "-0" { "0".into() } else { s }
}

/// `x` with at most 4 decimals, trailing zeros removed.
fn round(x: f64) -> String {
    let s = format!("{x:.4}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::ScenePoint;

    #[test]
    fn the_ranges_hold_the_frames_shown_not_the_whole_run() {
        // A point rolling from x = 0 to x = 10 m over 11 frames, beside a ground point at
        // the origin and one at (0, 1): shown, the frames 0 to 2 (x = 0 to 2 m).
        let point = |name: &str, ground| ScenePoint {
            name: name.into(),
            ground,
        };
        let positions = (0..11)
            .flat_map(|k| [0.0, 0.0, 0.0, 0.0, 1.0, 0.0, f64::from(k), 0.5, 0.0])
            .collect();
        let scene = Scene {
            name: "roller".into(),
            note: String::new(),
            points: vec![point("O", true), point("Q", true), point("P", false)],
            lines: vec![],
            traces: vec![2],
            times: (0..11).map(f64::from).collect(),
            positions,
            coordinates: vec![],
            decimation: 1,
            driver: None,
        };
        let frame = Frame::new(&scene, View::Xy, &[0, 1, 2]);
        // The drawing spans x in [0, 2], y in [0, 1]: 8 % of 2 m pads each side, then the
        // narrower range widens for equal scales; x = 10 m is far outside.
        // (1e-9: the ranges are sums of these lengths, exact only to round-off.)
        let near = |a: f64, b: f64| (a - b).abs() < 1e-9;
        assert!(
            near(frame.u.0, -0.16) && near(frame.u.1, 2.16),
            "{:?}",
            frame.u
        );
        assert!(
            near(frame.v.0, -0.16) && near(frame.v.1, 1.16),
            "{:?}",
            frame.v
        );
        // The whole run: up to x = 10 m.
        let all: Vec<usize> = (0..11).collect();
        let whole = Frame::new(&scene, View::Xy, &all);
        assert!(
            near(whole.u.0, -0.8) && near(whole.u.1, 10.8),
            "{:?}",
            whole.u
        );
    }
}
