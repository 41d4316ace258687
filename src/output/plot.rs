//! Figures as PNG and SVG, sized and styled to read well when embedded in a README:
//! 1000 px wide, 18–26 px text, 3 px lines, a grid, a box, legends, axis labels with units.
//!
//! - [`plot_coordinate`]: q(t) above dq/dt(t), seed Figures 3.1–3.4;
//! - [`plot_constraint_error`]: each |f_i| on a logarithmic axis, seed Figure 3.5;
//! - [`plot_driving_torque`]: tau(t) of an inverse-dynamics run;
//! - [`plot_overview`]: every coordinate of a large mechanism in one heat map of q over time;
//! - [`plot_run`]: the figures of a forward run that [`Figures`] asks for, named by
//!   [`FigureNames`] ([`plot_trajectory`]: all of them).
//!
//! Each function writes `<stem>.png` and `<stem>.svg` and returns their paths. Figures stay
//! readable at any size: past [`MAX_LEGEND`] series a figure draws their envelope instead of
//! one labelled line each, and a spread below 1e-12 of the mechanism's scale (round-off
//! around a constant) is drawn constant.

mod axes;
mod font;
mod overview;
mod render;
mod spec;
mod strobe;
mod title;

use std::path::{Path, PathBuf};

pub use self::overview::plot_overview;
use self::render::render;
use self::spec::{Line, Panel, Spec};
pub use self::strobe::{View, plot_strobe, strobe_frames};
use super::{InverseTable, OutputError, Unit};
use crate::simulation::trajectory::Trajectory;

/// Values below this are drawn at this height on logarithmic axes (so exact zeros show).
pub const LOG_FLOOR: f64 = 1e-18;

/// Most series a figure labels one by one; with more, it draws what sums them up (the
/// largest and the median constraint residual) so the legend stays readable.
pub const MAX_LEGEND: usize = 8;

/// Most coordinates that get a figure each by default ([`Figures::auto`]); a larger
/// mechanism gets the one [`plot_overview`] figure instead.
pub const PER_COORDINATE_LIMIT: usize = 12;

/// Which time-series figures a forward run writes (`--figures`); the constraint error comes
/// with every set but `None`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Figures {
    /// No time-series figures.
    None,
    /// One overview of every coordinate ([`plot_overview`]) and the constraint error.
    Overview,
    /// One figure per coordinate ([`plot_coordinate`]) and the constraint error.
    All,
}

impl Figures {
    /// The default for `n` coordinates: [`Figures::All`] up to [`PER_COORDINATE_LIMIT`], else
    /// [`Figures::Overview`] (the A02 chain's 82 coordinates would be 164 files).
    pub fn auto(n: usize) -> Self {
        if n <= PER_COORDINATE_LIMIT {
            Self::All
        } else {
            Self::Overview
        }
    }
}

/// Which figure, for [`FigureNames`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Figure<'a> {
    /// q and dq/dt of the named coordinate.
    Coordinate(&'a str),
    /// The constraint residuals.
    ConstraintError,
    /// The driving torque of an inverse-dynamics run.
    DrivingTorque,
    /// Every coordinate over time in one heat map ([`plot_overview`]).
    Overview,
}

impl Figure<'_> {
    /// The figure's own file name without extension: `<coordinate>`, `constraint_error`,
    /// `driving_torque`, `coordinates` (the overview).
    pub fn stem(self) -> String {
        match self {
            Figure::Coordinate(name) => name.to_string(),
            Figure::ConstraintError => "constraint_error".to_string(),
            Figure::DrivingTorque => "driving_torque".to_string(),
            Figure::Overview => "coordinates".to_string(),
        }
    }
}

/// The file names (without extension) of a run's figures, chosen by the caller: each
/// figure's own [`Figure::stem`] unless `renamed` gives it another (the command-line tool
/// names the seed paper's figures after its numbers, `fig_3_1_phi` ..
/// `fig_3_5_constraint_error`).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct FigureNames {
    /// (own stem, file stem) pairs: the figure whose own stem is the first is written
    /// under the second.
    pub renamed: Vec<(String, String)>,
}

impl FigureNames {
    /// The file name without extension of `figure`.
    pub fn stem(&self, figure: Figure<'_>) -> String {
        let own = figure.stem();
        match self.renamed.iter().find(|(from, _)| *from == own) {
            Some((_, to)) => to.clone(),
            None => own,
        }
    }
}

/// Display form of a coordinate name: Greek letter names become letters (`phi` -> `φ`,
/// `theta_2` -> `θ₂`); anything else is kept.
pub fn pretty_name(name: &str) -> String {
    const GREEK: [(&str, &str); 24] = [
        ("alpha", "α"),
        ("beta", "β"),
        ("gamma", "γ"),
        ("delta", "δ"),
        ("epsilon", "ε"),
        ("zeta", "ζ"),
        ("eta", "η"),
        ("theta", "θ"),
        ("iota", "ι"),
        ("kappa", "κ"),
        ("lambda", "λ"),
        ("mu", "μ"),
        ("nu", "ν"),
        ("xi", "ξ"),
        ("omicron", "ο"),
        ("pi", "π"),
        ("rho", "ρ"),
        ("sigma", "σ"),
        ("tau", "τ"),
        ("upsilon", "υ"),
        ("phi", "φ"),
        ("chi", "χ"),
        ("psi", "ψ"),
        ("omega", "ω"),
    ];
    let (head, tail) = name
        .split_once('_')
        .map_or((name, None), |(h, t)| (h, Some(t)));
    let Some(&(_, letter)) = GREEK.iter().find(|(g, _)| *g == head) else {
        return name.to_string();
    };
    match tail {
        None => letter.to_string(),
        Some(t) if !t.is_empty() && t.chars().all(|c| c.is_ascii_digit()) => {
            format!("{letter}{}", subscript(t))
        }
        Some(t) => format!("{letter}_{t}"),
    }
}

fn subscript(digits: &str) -> String {
    digits
        .chars()
        .map(|c| char::from_u32(0x2080 + c.to_digit(10).unwrap_or(0)).unwrap_or(c))
        .collect()
}

/// `label (unit)`, or just `label` without a unit.
fn with_unit(label: &str, unit: &str) -> String {
    if unit.is_empty() {
        label.to_string()
    } else {
        format!("{label} ({unit})")
    }
}

/// Seed Figures 3.1–3.4: `name`(t) in the top panel and its rate in the bottom one, with
/// units from `unit` (rad and rad/s, or m and m/s). Writes `<stem>.png` and `<stem>.svg`.
/// Round-off is judged against the series' own magnitudes ([`plot_coordinate_scaled`] takes
/// the mechanism's).
pub fn plot_coordinate(
    stem: &Path,
    name: &str,
    unit: Unit,
    t: &[f64],
    q: &[f64],
    qd: &[f64],
) -> Result<Vec<PathBuf>, OutputError> {
    let scale = (magnitude(q.iter()), magnitude(qd.iter()));
    plot_coordinate_scaled(stem, name, unit, t, (q, qd), scale)
}

/// [`plot_coordinate`] of `(q, qd)` with the mechanism's scales `(position, rate)` (the
/// largest |q| and |q'| of coordinates of the same unit): a coordinate that stays constant to
/// 1e-12 of them is drawn constant, not as magnified round-off.
pub fn plot_coordinate_scaled(
    stem: &Path,
    name: &str,
    unit: Unit,
    t: &[f64],
    (q, qd): (&[f64], &[f64]),
    (position, rate_scale): (f64, f64),
) -> Result<Vec<PathBuf>, OutputError> {
    let p = pretty_name(name);
    let rate = format!("d{p}/dt");
    let panel = |label: &str, y: &[f64], unit: &str, bottom, scale| Panel {
        t,
        lines: vec![Line {
            label: format!("{label}(t)"),
            y: y.to_vec(),
        }],
        y_label: with_unit(label, unit),
        x_label: bottom,
        log: false,
        scale,
    };
    let spec = Spec {
        title: format!("{p} and {rate} over time"),
        height: 760,
        panels: vec![
            panel(&p, q, unit.position(), false, position),
            panel(&rate, qd, unit.rate(), true, rate_scale),
        ],
    };
    render(stem, &spec)
}

/// The largest finite |v|, 0 for none.
fn magnitude<'a>(values: impl Iterator<Item = &'a f64>) -> f64 {
    values
        .filter(|v| v.is_finite())
        .fold(0.0, |a, v| a.max(v.abs()))
}

/// Seed Figure 3.5: each |f_i(t)| of `residuals` (one series per constraint row, named
/// f_1..f_m) on a logarithmic axis. Values below [`LOG_FLOOR`], exact zeros included, are
/// drawn at the floor; the axis spans the whole decades that hold the data. With more than
/// [`MAX_LEGEND`] rows the figure draws, at each instant, the largest |f_i| and the median
/// one instead (81 overlapping lines and their legend could not be read).
pub fn plot_constraint_error(
    stem: &Path,
    t: &[f64],
    residuals: &[Vec<f64>],
) -> Result<Vec<PathBuf>, OutputError> {
    let lines = if residuals.len() <= MAX_LEGEND {
        residuals
            .iter()
            .enumerate()
            .map(|(i, f)| Line {
                label: format!("|f{}|", subscript(&(i + 1).to_string())),
                y: to_log(f),
            })
            .collect()
    } else {
        let (max, median) = envelope(t.len(), residuals);
        let m = residuals.len();
        vec![
            Line {
                label: format!("max over the {m} rows"),
                y: to_log(&max),
            },
            Line {
                label: "median row".to_string(),
                y: to_log(&median),
            },
        ]
    };
    constraint_figure(stem, t, lines)
}

/// At each of the `samples` instants, the largest |f_i| and the median of the |f_i| (NaN
/// where a row is NaN: a NaN is shown, not hidden). Rows shorter than `samples` make the
/// figure's length check fail later, so they are read as far as they go.
fn envelope(samples: usize, rows: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    let mut column = Vec::with_capacity(rows.len());
    (0..samples)
        .map(|k| {
            column.clear();
            column.extend(rows.iter().filter_map(|r| r.get(k)).map(|v| v.abs()));
            if column.iter().any(|v| v.is_nan()) {
                return (f64::NAN, f64::NAN);
            }
            column.sort_by(f64::total_cmp);
            let median = column.get(column.len() / 2).copied().unwrap_or(f64::NAN);
            (column.last().copied().unwrap_or(f64::NAN), median)
        })
        .unzip()
}

fn to_log(values: &[f64]) -> Vec<f64> {
    values
        .iter()
        .map(|v| {
            if v.is_nan() {
                f64::NAN
            } else {
                v.abs().max(LOG_FLOOR).log10()
            }
        })
        .collect()
}

fn constraint_figure(
    stem: &Path,
    t: &[f64],
    lines: Vec<Line>,
) -> Result<Vec<PathBuf>, OutputError> {
    let spec = Spec {
        title: "Constraint error".to_string(),
        height: 600,
        panels: vec![Panel {
            t,
            lines,
            // Exact zeros sit on the floor: say so, or a row that is exactly satisfied (the
            // bicycle's five of six) reads as an error of 1e-18.
            y_label: format!(
                "|fᵢ(q(t))| (log scale, 0 at {})",
                axes::decade_label(&LOG_FLOOR.log10())
            ),
            x_label: true,
            log: true,
            scale: 0.0,
        }],
    };
    render(stem, &spec)
}

/// Driving torque of an inverse-dynamics run: tau(t) for each driven coordinate of `table`,
/// in N m for angles and N for lengths (units from `unit_of`, called with each name).
pub fn plot_driving_torque(
    stem: &Path,
    table: &InverseTable,
    unit_of: impl Fn(&str) -> Unit,
) -> Result<Vec<PathBuf>, OutputError> {
    let t = table.times();
    let lines = table
        .driven
        .iter()
        .enumerate()
        .map(|(k, name)| Line {
            label: format!("τ on {}", pretty_name(name)),
            y: table.torque(k),
        })
        .collect();
    let mut units: Vec<&str> = table.driven.iter().map(|d| unit_of(d).force()).collect();
    units.dedup();
    let unit = if units.len() == 1 {
        units[0].to_string()
    } else {
        units.join(" or ")
    };
    let spec = Spec {
        title: "Driving torque".to_string(),
        height: 600,
        panels: vec![Panel {
            t: &t,
            lines,
            y_label: with_unit("τ", &unit),
            x_label: true,
            log: false,
            scale: 0.0,
        }],
    };
    render(stem, &spec)
}

/// All figures of a forward run into `dir`, under their own names: [`plot_run`] with
/// [`Figures::All`] and the default [`FigureNames`].
pub fn plot_trajectory(
    dir: &Path,
    trajectory: &Trajectory,
    units: Option<&[Unit]>,
    residuals: Option<&[Vec<f64>]>,
) -> Result<Vec<PathBuf>, OutputError> {
    let names = FigureNames::default();
    plot_run(dir, trajectory, units, residuals, Figures::All, &names)
}

/// The coordinates of a run as the figures read them: names, units, times, and q and q'
/// of each coordinate over the times.
pub struct CoordinateSeries<'a> {
    /// Coordinate names.
    pub names: &'a [String],
    /// The unit of each coordinate.
    pub units: Vec<Unit>,
    /// The times (s).
    pub t: &'a [f64],
    /// q of each coordinate at the times.
    pub q: Vec<Vec<f64>>,
    /// q' of each coordinate at the times.
    pub qd: Vec<Vec<f64>>,
}

/// The coordinate figures `figures` asks for, into `dir`, named by `names`: one per coordinate
/// ([`Figures::All`], [`plot_coordinate_scaled`] with the scales the largest |q| and |q'| among
/// coordinates of the same unit), the one [`plot_overview`] ([`Figures::Overview`]) or none.
/// Returns the files written.
pub fn plot_coordinates(
    dir: &Path,
    names: &FigureNames,
    series: &CoordinateSeries<'_>,
    figures: Figures,
) -> Result<Vec<PathBuf>, OutputError> {
    let CoordinateSeries {
        names: coordinates,
        units,
        t,
        q,
        qd,
    } = series;
    match figures {
        Figures::None => Ok(vec![]),
        Figures::Overview => {
            let stem = dir.join(names.stem(Figure::Overview));
            plot_overview(&stem, coordinates, units, t, q)
        }
        Figures::All => {
            // The mechanism's scale of each unit: the largest |q| and |q'| of its coordinates.
            let scale = |unit: Unit, of: &[Vec<f64>]| {
                let same = units.iter().zip(of).filter(|(u, _)| **u == unit);
                magnitude(same.flat_map(|(_, s)| s.iter()))
            };
            let mut written = Vec::new();
            for (i, name) in coordinates.iter().enumerate() {
                let stem = dir.join(names.stem(Figure::Coordinate(name)));
                let scales = (scale(units[i], q), scale(units[i], qd));
                let (qi, qdi) = (q[i].as_slice(), qd[i].as_slice());
                written.extend(plot_coordinate_scaled(
                    &stem,
                    name,
                    units[i],
                    t,
                    (qi, qdi),
                    scales,
                )?);
            }
            Ok(written)
        }
    }
}

/// The figures of a forward run that `figures` asks for, into `dir`, named by `names`:
/// [`plot_coordinates`] (units from `units` or [`Unit::guess`]) and, unless [`Figures::None`]
/// or the mechanism has no constraint rows, the constraint error ([`plot_constraint_error`] of
/// `residuals`, one series per constraint row; without them, the recorded |Phi|_inf). Returns
/// every file written.
pub fn plot_run(
    dir: &Path,
    trajectory: &Trajectory,
    units: Option<&[Unit]>,
    residuals: Option<&[Vec<f64>]>,
    figures: Figures,
    names: &FigureNames,
) -> Result<Vec<PathBuf>, OutputError> {
    if figures == Figures::None {
        return Ok(vec![]);
    }
    let info = &trajectory.info;
    let t: Vec<f64> = trajectory.samples().map(|s| s.t).collect();
    let series = CoordinateSeries {
        names: &info.coordinates,
        units: (0..info.n())
            .map(|i| {
                units
                    .and_then(|u| u.get(i).copied())
                    .unwrap_or_else(|| Unit::guess(&info.coordinates[i]))
            })
            .collect(),
        t: &t,
        q: (0..info.n())
            .map(|i| trajectory.samples().map(|s| s.q[i]).collect())
            .collect(),
        qd: (0..info.n())
            .map(|i| trajectory.samples().map(|s| s.qd[i]).collect())
            .collect(),
    };
    let mut written = plot_coordinates(dir, names, &series, figures)?;
    // A mechanism without constraint rows (an open tree of links) has no error to draw.
    if info.m() == 0 {
        return Ok(written);
    }
    let stem = dir.join(names.stem(Figure::ConstraintError));
    written.extend(match residuals {
        Some(r) => plot_constraint_error(&stem, &t, r)?,
        None => {
            let y: Vec<f64> = trajectory.samples().map(|s| s.constraint_error).collect();
            constraint_figure(
                &stem,
                &t,
                vec![Line {
                    label: "‖Φ(q)‖∞".to_string(),
                    y: to_log(&y),
                }],
            )?
        }
    });
    Ok(written)
}
