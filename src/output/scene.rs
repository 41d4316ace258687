//! A [`Scene`]: the declared drawing (`draw { .. }`) of a mechanism evaluated at the frames of
//! a trajectory, what the animation page and the strobe figure show.

use super::Unit;
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
    /// most `max_frames` of them (every k-th, and the last): for trajectories and for the
    /// samples of an inverse-dynamics run alike. `None` without a drawing or samples.
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
        })
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
