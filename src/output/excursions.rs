//! Where a run passed the joints' declared limits ([`crate::JointLimits`]): the position
//! range, the largest rate and, where the run computes a driving force, the largest effort.
//!
//! Nothing in the equations enforces a limit (a stop is a unilateral contact), so a free
//! simulation of a robot swings through them; the run says where, so that a motion or a
//! torque beyond what the hardware allows is not taken for a feasible one.

use serde::Serialize;

use super::table::InverseTable;
use crate::system::{JointLimits, SystemInfo};

/// Beyond a bound b means beyond b by more than this times max(1, |b|): far above the
/// round-off of an assembled state resting on a limit (about 1e-15), far below any motion
/// that matters (1 nrad, 1 nm).
const SLACK: f64 = 1e-9;

/// One declared limit a run passed: the first time it did and the value furthest beyond it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct LimitExcursion {
    /// The coordinate (the joint's name).
    pub coordinate: String,
    /// `position` (q), `rate` (q') or `effort` (the driving force on q).
    pub quantity: &'static str,
    /// The allowed range [lower, upper] (for a rate or an effort, [-limit, limit]).
    pub lower: f64,
    /// See [`LimitExcursion::lower`].
    pub upper: f64,
    /// `rad`, `m`, `rad/s`, `m/s`, `N m` or `N`.
    pub unit: &'static str,
    /// The first sample time beyond the range (s).
    pub first_t: f64,
    /// The value furthest outside the range.
    pub extreme: f64,
    /// When [`LimitExcursion::extreme`] was reached (s).
    pub extreme_t: f64,
}

/// Watches samples of a run against the declared limits of `info`.
#[derive(Clone, Debug)]
pub struct LimitWatch {
    /// Each limit watched.
    watched: Vec<Watched>,
    /// What each has passed so far.
    found: Vec<Option<LimitExcursion>>,
}

/// One limit watched: the coordinate's index, the quantity, the allowed range and its unit.
#[derive(Clone, Debug)]
struct Watched {
    coordinate: usize,
    quantity: Quantity,
    range: [f64; 2],
    unit: &'static str,
}

/// What a limit bounds: q, q' or the driving force on q.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Quantity {
    Position,
    Rate,
    Effort,
}

impl LimitWatch {
    /// A watch on every limit `info` declares.
    pub fn new(info: &SystemInfo) -> Self {
        let mut watched = Vec::new();
        for l in &info.joint_limits {
            let JointLimits {
                coordinate, linear, ..
            } = *l;
            let (q, rate, force) = if linear {
                ("m", "m/s", "N")
            } else {
                ("rad", "rad/s", "N m")
            };
            let mut watch = |quantity, range, unit| {
                watched.push(Watched {
                    coordinate,
                    quantity,
                    range,
                    unit,
                })
            };
            if let Some(range) = l.position {
                watch(Quantity::Position, range, q);
            }
            if let Some(v) = l.velocity {
                watch(Quantity::Rate, [-v, v], rate);
            }
            if let Some(e) = l.effort {
                watch(Quantity::Effort, [-e, e], force);
            }
        }
        let found = vec![None; watched.len()];
        Self { watched, found }
    }

    /// Reads one sample at time `t`: positions `q`, rates `qd` and, when the run computes
    /// them, the driving forces by coordinate (`NaN` where a coordinate is not driven).
    pub fn sample(&mut self, t: f64, q: &[f64], qd: &[f64], force: Option<&[f64]>) {
        for (w, found) in self.watched.iter().zip(&mut self.found) {
            let value = match w.quantity {
                Quantity::Position => q.get(w.coordinate),
                Quantity::Rate => qd.get(w.coordinate),
                Quantity::Effort => force.and_then(|f| f.get(w.coordinate)),
            };
            let Some(&value) = value else { continue };
            let [lower, upper] = w.range;
            let beyond = (lower - value).max(value - upper);
            let slack = |b: f64| SLACK * b.abs().max(1.0);
            let outside = value < lower - slack(lower) || value > upper + slack(upper);
            if !outside {
                continue;
            }
            if let Some(e) = found.as_mut() {
                let worst = (lower - e.extreme).max(e.extreme - upper);
                if beyond > worst {
                    e.extreme = value;
                    e.extreme_t = t;
                }
                continue;
            }
            *found = Some(LimitExcursion {
                coordinate: String::new(),
                quantity: match w.quantity {
                    Quantity::Position => "position",
                    Quantity::Rate => "rate",
                    Quantity::Effort => "effort",
                },
                lower,
                upper,
                unit: w.unit,
                first_t: t,
                extreme: value,
                extreme_t: t,
            });
        }
    }

    /// The limits passed, in the order `info` declares them (coordinate order; position,
    /// rate, effort), with the coordinates named from `info`.
    pub fn finish(self, info: &SystemInfo) -> Vec<LimitExcursion> {
        self.watched
            .iter()
            .zip(self.found)
            .filter_map(|(w, found)| {
                found.map(|mut e| {
                    e.coordinate = info.coordinates[w.coordinate].clone();
                    e
                })
            })
            .collect()
    }
}

/// The declared limits an inverse-dynamics run passed: positions and rates of every
/// coordinate, and the effort of each driven one (its driving force `tau_<name>`).
pub fn inverse_excursions(info: &SystemInfo, table: &InverseTable) -> Vec<LimitExcursion> {
    let n = info.n();
    let driven: Vec<Option<usize>> = table
        .driven
        .iter()
        .map(|d| info.coordinates.iter().position(|c| c == d))
        .collect();
    let mut watch = LimitWatch::new(info);
    let mut force = vec![f64::NAN; n];
    for row in &table.rows {
        if row.len() < 1 + 3 * n + driven.len() {
            continue;
        }
        for (k, &d) in driven.iter().enumerate() {
            if let Some(i) = d {
                force[i] = row[1 + 3 * n + k];
            }
        }
        let (q, qd) = (&row[1..1 + n], &row[1 + n..1 + 2 * n]);
        watch.sample(row[0], q, qd, Some(&force));
    }
    watch.finish(info)
}

/// One line per excursion, at most `lines` of them, then how many more:
/// `panda_joint4 position outside [-3.0718, -0.0698] rad from t = 0 s; furthest 0.2345 rad
/// at t = 0.4 s` (times as the samples have them).
pub fn excursion_lines(excursions: &[LimitExcursion], lines: usize) -> Vec<String> {
    let mut out: Vec<String> = excursions
        .iter()
        .take(lines)
        .map(|e| {
            format!(
                "{} {} outside [{}, {}] {} from t = {} s; furthest {:.6} {} at t = {} s",
                e.coordinate,
                e.quantity,
                e.lower,
                e.upper,
                e.unit,
                e.first_t,
                e.extreme,
                e.unit,
                e.extreme_t
            )
        })
        .collect();
    if excursions.len() > lines {
        out.push(format!("and {} more", excursions.len() - lines));
    }
    out
}
