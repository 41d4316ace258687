//! A [`Scene`]: the declared drawing (`draw { .. }`) of a mechanism evaluated at the frames of
//! a trajectory, what the animation page and the strobe figure show.

use super::Unit;

/// Most numbers (point coordinates and coordinate values over all frames) a scene holds:
/// about 20 bytes each in the page's JSON, so the page stays under about 1.5 MB.
pub const MAX_VALUES: usize = 65_000;

/// Fewest frames a scene is cut to for size (a mechanism so large that fewer would fit gets
/// these, and a larger page).
const MIN_FRAMES: usize = 100;
use crate::simulation::trajectory::Trajectory;
use crate::system::System;

/// One drawn point of a scene.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "files", derive(serde::Serialize))]
pub struct ScenePoint {
    /// Its declared name.
    pub name: String,
    /// Fixed to the ground.
    pub ground: bool,
}

/// One coordinate's values at the frames, for the plots beside the animation.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "files", derive(serde::Serialize))]
pub struct SceneCoordinate {
    /// Coordinate name.
    pub name: String,
    /// `rad`, `m`, or empty.
    pub unit: String,
    /// q_k at each frame.
    pub values: Vec<f64>,
}

/// The drawing of a mechanism evaluated along a trajectory: what the animation page and the
/// strobe figure show.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "files", derive(serde::Serialize))]
pub struct Scene {
    /// Mechanism name.
    pub name: String,
    /// One line for the page: run length, frames, decimation.
    pub note: String,
    /// The drawn points.
    pub points: Vec<ScenePoint>,
    /// Polylines through the points (indices).
    pub lines: Vec<Vec<usize>>,
    /// Traced points (indices).
    pub traces: Vec<usize>,
    /// Time of each frame (s).
    pub times: Vec<f64>,
    /// x, y, z of every point at every frame: frame-major, 3 values per point.
    pub positions: Vec<f64>,
    /// The coordinates at the frames.
    pub coordinates: Vec<SceneCoordinate>,
    /// Every `decimation`-th sample of the trajectory is a frame (and the last one).
    pub decimation: usize,
    /// The index in `coordinates` of the driving coordinate (the first independent one),
    /// whose first revolution or period the strobe figure shows ([`Scene::cycle`]).
    pub driver: Option<usize>,
}

/// The first revolution or period of a scene's driving coordinate ([`Scene::cycle`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Cycle {
    /// The last frame of it (the first frame at or after its end).
    pub end: usize,
    /// `revolution` (an angle that turned by 2 pi) or `period` (one oscillation).
    pub kind: &'static str,
    /// The coordinate's name.
    pub coordinate: String,
}

impl Scene {
    /// The drawing of `system` at the samples of `trajectory`, at most `max_frames` of them
    /// (every k-th, and the last). `None` when the system declares no drawing or the
    /// trajectory is empty.
    pub fn new(system: &dyn System, trajectory: &Trajectory, max_frames: usize) -> Option<Self> {
        Self::from_samples(system, trajectory.len(), max_frames, |i| {
            let s = trajectory.sample(i);
            (s.t, s.q)
        })
    }

    /// The drawing of `system` at `samples` states, `state(i)` giving (t, q) of the i-th, at
    /// most `max_frames` of them and at most [`MAX_VALUES`] numbers (but at least 100
    /// frames): every k-th, and the last. For trajectories and for the samples of an
    /// inverse-dynamics run alike. `None` without a drawing or samples.
    pub fn from_samples<'a>(
        system: &dyn System,
        samples: usize,
        max_frames: usize,
        state: impl Fn(usize) -> (f64, &'a [f64]),
    ) -> Option<Self> {
        let info = system.info();
        let drawing = &info.drawing;
        if drawing.is_empty() || samples == 0 {
            return None;
        }
        // At most `max_frames`, and at most MAX_VALUES numbers in all (points and coordinates
        // at every frame), so a large mechanism's page stays small too.
        let per_frame = 3 * drawing.points.len() + info.n();
        let max_frames = max_frames
            .min(MAX_VALUES / per_frame.max(1))
            .max(MIN_FRAMES);
        let every = samples.div_ceil(max_frames.max(2) - 1).max(1);
        let mut picked: Vec<usize> = (0..samples).step_by(every).collect();
        if picked.last() != Some(&(samples - 1)) {
            picked.push(samples - 1);
        }
        let np = drawing.points.len();
        let mut positions = vec![0.0; 3 * np * picked.len()];
        let mut times = Vec::with_capacity(picked.len());
        for (frame, &i) in picked.iter().enumerate() {
            let (t, q) = state(i);
            times.push(t);
            system.draw_points(t, q, &mut positions[3 * np * frame..3 * np * (frame + 1)]);
        }
        let coordinates = info
            .coordinates
            .iter()
            .enumerate()
            .map(|(k, name)| SceneCoordinate {
                name: name.clone(),
                unit: Unit::guess(name).position().to_string(),
                values: picked.iter().map(|&i| state(i).1[k]).collect(),
            })
            .collect();
        let t_end = times.last().copied().unwrap_or(0.0);
        let note = if every == 1 {
            format!("{t_end} s, {} frames (every sample)", picked.len())
        } else {
            format!(
                "{t_end} s, {} frames: one sample in {every} of {samples}, so the page stays small",
                picked.len()
            )
        };
        Some(Self {
            name: info.name.clone(),
            note,
            points: drawing
                .points
                .iter()
                .map(|p| ScenePoint {
                    name: p.name.clone(),
                    ground: p.ground,
                })
                .collect(),
            lines: drawing.lines.clone(),
            traces: drawing.traces.clone(),
            times,
            positions,
            coordinates,
            decimation: every,
            driver: info.independent.first().map(|i| i.coordinate),
        })
    }

    /// The first revolution of the driving coordinate (an angle, by its unit, that turns by
    /// 2 pi within the scene), else its first period: the time between its first two upward
    /// crossings of the middle of its range, counted from the first frame. `None` without a
    /// driving coordinate, or when it does neither within the scene (it stays still or the
    /// scene ends first).
    pub fn cycle(&self) -> Option<Cycle> {
        let c = self.coordinates.get(self.driver?)?;
        let q = &c.values;
        let q0 = *q.first()?;
        let cycle = |end, kind| Cycle {
            end,
            kind,
            coordinate: c.name.clone(),
        };
        if c.unit == "rad" {
            let tau = 2.0 * std::f64::consts::PI;
            // 1e-9 rad below a full turn counts: a drive of exactly 2 pi t reaches it at t = 1.
            if let Some(end) = q.iter().position(|v| (v - q0).abs() >= tau - 1e-9) {
                return Some(cycle(end, "revolution"));
            }
        }
        let (lo, hi) = q
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
                (a.min(v), b.max(v))
            });
        // A coordinate that stays still to 1e-9 of its size has no period worth showing.
        let moves = hi - lo > 1e-9 * (1.0 + lo.abs().max(hi.abs()));
        if !moves {
            return None;
        }
        let mid = 0.5 * (lo + hi);
        let mut up = (1..q.len()).filter(|&f| q[f - 1] < mid && q[f] >= mid);
        let (a, b) = (up.next()?, up.next()?);
        let period = self.times[b] - self.times[a];
        let end = self
            .times
            .iter()
            .position(|&t| t >= self.times[0] + period)?;
        Some(cycle(end, "period"))
    }

    /// Number of frames.
    pub fn frames(&self) -> usize {
        self.times.len()
    }

    /// x, y, z of point `point` at frame `frame`.
    pub fn position(&self, frame: usize, point: usize) -> [f64; 3] {
        let o = 3 * (frame * self.points.len() + point);
        [
            self.positions[o],
            self.positions[o + 1],
            self.positions[o + 2],
        ]
    }
}
