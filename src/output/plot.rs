//! Figures as PNG and SVG, sized and styled to read well when embedded in a README:
//! 1000 px wide, 18–26 px text, 3 px lines, a grid, a box, legends, axis labels with units.
//!
//! - [`plot_coordinate`]: q(t) above dq/dt(t), seed Figures 3.1–3.4;
//! - [`plot_constraint_error`]: each |f_i| on a logarithmic axis, seed Figure 3.5;
//! - [`plot_driving_torque`]: tau(t) of an inverse-dynamics run;
//! - [`plot_trajectory`]: all figures of a forward run, named by [`figure_stem`].
//!
//! Each function writes `<stem>.png` and `<stem>.svg` and returns their paths.

mod axes;
mod render;
mod spec;
mod strobe;

use std::path::{Path, PathBuf};

use self::render::render;
use self::spec::{Line, Panel, Spec};
pub use self::strobe::{View, plot_strobe, strobe_frames};
use super::{InverseTable, OutputError, Unit};
use crate::simulation::trajectory::Trajectory;

/// Values below this are drawn at this height on logarithmic axes (so exact zeros show).
pub const LOG_FLOOR: f64 = 1e-18;

/// Which figure, for [`figure_stem`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Figure<'a> {
    /// q and dq/dt of the named coordinate.
    Coordinate(&'a str),
    /// The constraint residuals.
    ConstraintError,
    /// The driving torque of an inverse-dynamics run.
    DrivingTorque,
}

/// True for the seed paper's mechanism (`spatial_crank_slider`, `SpatialCrankSlider`, any case).
fn is_seed(mechanism: &str) -> bool {
    mechanism
        .chars()
        .filter(|&c| c != '_' && c != '-')
        .flat_map(char::to_lowercase)
        .eq("spatialcrankslider".chars())
}

/// File name without extension: for the seed mechanism the paper's figure numbers
/// (`fig_3_1_phi` .. `fig_3_4_x_c`, `fig_3_5_constraint_error`); otherwise `<coordinate>`,
/// `constraint_error`; and `driving_torque` for any mechanism.
pub fn figure_stem(mechanism: &str, figure: Figure<'_>) -> String {
    const SEED: [&str; 4] = ["phi", "beta", "gamma", "x_c"];
    match figure {
        Figure::Coordinate(name) => match SEED.iter().position(|&s| s == name) {
            Some(i) if is_seed(mechanism) => format!("fig_3_{}_{name}", i + 1),
            _ => name.to_string(),
        },
        Figure::ConstraintError if is_seed(mechanism) => "fig_3_5_constraint_error".to_string(),
        Figure::ConstraintError => "constraint_error".to_string(),
        Figure::DrivingTorque => "driving_torque".to_string(),
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
pub fn plot_coordinate(
    stem: &Path,
    name: &str,
    unit: Unit,
    t: &[f64],
    q: &[f64],
    qd: &[f64],
) -> Result<Vec<PathBuf>, OutputError> {
    let p = pretty_name(name);
    let rate = format!("d{p}/dt");
    let panel = |label: &str, y: &[f64], unit: &str, bottom| Panel {
        t,
        lines: vec![Line {
            label: format!("{label}(t)"),
            y: y.to_vec(),
        }],
        y_label: with_unit(label, unit),
        x_label: bottom,
        log: false,
    };
    let spec = Spec {
        title: format!("{p} and {rate} over time"),
        height: 760,
        panels: vec![
            panel(&p, q, unit.position(), false),
            panel(&rate, qd, unit.rate(), true),
        ],
    };
    render(stem, &spec)
}

/// Seed Figure 3.5: each |f_i(t)| of `residuals` (one series per constraint row, named
/// f_1..f_m) on a logarithmic axis. Values below [`LOG_FLOOR`], exact zeros included, are
/// drawn at the floor; the axis spans the whole decades that hold the data.
pub fn plot_constraint_error(
    stem: &Path,
    t: &[f64],
    residuals: &[Vec<f64>],
) -> Result<Vec<PathBuf>, OutputError> {
    let lines = residuals
        .iter()
        .enumerate()
        .map(|(i, f)| Line {
            label: format!("|f{}|", subscript(&(i + 1).to_string())),
            y: to_log(f),
        })
        .collect();
    constraint_figure(stem, t, lines)
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
            y_label: "|fᵢ(q(t))| (log scale)".to_string(),
            x_label: true,
            log: true,
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
        }],
    };
    render(stem, &spec)
}

/// All figures of a forward run into `dir`, named by [`figure_stem`]: one per coordinate
/// ([`plot_coordinate`], units from `units` or [`Unit::guess`]) and the constraint error
/// ([`plot_constraint_error`] of `residuals`, one series per constraint row; without them,
/// the recorded |Phi|_inf). Returns every file written.
pub fn plot_trajectory(
    dir: &Path,
    trajectory: &Trajectory,
    units: Option<&[Unit]>,
    residuals: Option<&[Vec<f64>]>,
) -> Result<Vec<PathBuf>, OutputError> {
    let info = &trajectory.info;
    let n = info.n();
    let t: Vec<f64> = trajectory.samples().map(|s| s.t).collect();
    let mut written = Vec::new();
    for (i, name) in info.coordinates.iter().enumerate() {
        let q: Vec<f64> = trajectory.samples().map(|s| s.q[i]).collect();
        let qd: Vec<f64> = trajectory.samples().map(|s| s.qd[i]).collect();
        let unit = units
            .and_then(|u| u.get(i).copied())
            .unwrap_or_else(|| Unit::guess(name));
        let stem = dir.join(figure_stem(&info.name, Figure::Coordinate(name)));
        written.extend(plot_coordinate(&stem, name, unit, &t, &q, &qd)?);
    }
    let stem = dir.join(figure_stem(&info.name, Figure::ConstraintError));
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
    debug_assert!(written.len() == 2 * (n + 1));
    Ok(written)
}
