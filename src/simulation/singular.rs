//! Singular configurations that a motion passes through.
//!
//! A singular configuration is one where Phi_q loses rank for an instant: a chain of
//! four-bar loops lying flat, a press at toggle. The solvers integrate through them (see
//! [`crate::Dynamics`]); this module only records where they happened.
//!
//! The test is the one [`crate::mobility()`] uses for the rank: the independence of each row
//! (its distance to the span of the rows before it, relative to its norm;
//! [`crate::linalg::RowBasis`]), here times the row's norm over the largest norm it has had
//! in the run, so that a row whose gradient vanishes counts as losing rank as much as one
//! that turns into the others' span (a five-bar lying flat: every point on one line, and
//! the closure row across that line has gradient zero; its independence alone stays 1).
//! Rows redundant at the start are left out; the **weakest** value w of the others
//! measures the distance to a singular configuration (w = 0 at one, w ~ |t - t*| near a
//! simple passage). After every accepted step with an end point
//! within [`COARSE`] of singular, the minimum of w inside the step is located on the
//! integrator's dense output by golden-section search (24 evaluations, to 1e-5 of the step;
//! w is unimodal on a step that short); so is one whose ends are both above [`COARSE`]
//! when w is below it at a quarter, half or three quarters of the step (sampled where the
//! dense output is built anyway: a long step can pass a whole dip of w). A
//! passage is recorded where that minimum (or a step end) falls below
//! [`SingularWatch::threshold`] (default 1e-3); another is recorded only after w has risen
//! above [`COARSE`] again. Its rank drop is the number of rows whose independence is below
//! max(sqrt(w), threshold) at the minimum (the rows that fall together; the others stay
//! near 1).
//!
//! The prediction of the singular position ahead ([`SingularWatch::crossing`]) steers the
//! explicit steps (`stepper/passage.rs`). [`SingularWatch::ahead_of_step`] gives it for a
//! step before the driver accepts it, so that a step found to end just before t* can be
//! taken again, steered.

use nalgebra::DMatrix;

use crate::linalg::RowBasis;
use crate::simulation::apex::PassageGeometry;
use crate::system::System;

/// One passage through or near a singular configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct SingularPassage {
    /// Estimated time of the passage (s), within one step.
    pub t: f64,
    /// How many rows lose their independence there.
    pub rank_drop: usize,
    /// Those rows (indices into Phi).
    pub rows: Vec<usize>,
    /// The weakest row independence at the nearest accepted step (0 exactly singular).
    pub independence: f64,
    /// Whether a nearby motion passes through this singular position or can miss it (see
    /// [`PassageGeometry`]); an [`PassageGeometry::Apex`] passed straight through holds only
    /// for a motion that hits it exactly.
    pub geometry: PassageGeometry,
    /// Whether one step went over the closest approach: w at both its ends at least 8
    /// times w there (a straddle placed around t*: ends at 1e-2 to 1e-1,
    /// the minimum at 1e-9 to 1e-6), rather than steps that follow w through its minimum
    /// (ends within a few times it: a turn around an apex resolved by the steps).
    pub stepped_over: bool,
}

/// The ratio of w at a step's ends to w at the closest approach inside it above which the
/// step went over a passage ([`SingularPassage::stepped_over`]).
pub(crate) const STEPPED_OVER: f64 = 8.0;

/// Above this weakest independence a step is not searched for a passage, and a new passage
/// can be recorded only after w has been above it.
pub const COARSE: f64 = 0.3;

/// Where in a step (fractions of it) w is sampled when it is above [`COARSE`] at both ends
/// (see [`SingularWatch::observe_step`]).
const PROBES: [f64; 3] = [0.25, 0.5, 0.75];

/// Watches the rank of Phi_q along a simulation; allocates only when it records a passage.
#[derive(Clone, Debug)]
pub(crate) struct SingularWatch {
    basis: RowBasis,
    phi_q: DMatrix<f64>,
    phi_t: Vec<f64>,
    /// The structural columns of Phi_q's rows in ascending order, row r's at
    /// `columns[starts[r]..starts[r + 1]]` (from [`System::sparsity`]; empty without one):
    /// the norms of [`SingularWatch::measure`] read these entries only.
    starts: Vec<usize>,
    columns: Vec<usize>,
    /// Rows redundant at the start, left out of the weakest independence.
    redundant: Vec<bool>,
    /// The largest norm |a_r| each row of Phi_q has had so far (see [`SingularWatch::measure`]).
    scale: Vec<f64>,
    /// Row independences at the last measurement, and at the lowest w of the current search.
    current: Vec<f64>,
    best: Vec<f64>,
    /// The rows of a step's end, kept while [`SingularWatch::ahead_of_step`] measures inside
    /// it.
    end: Vec<f64>,
    /// w at the end of the last accepted step.
    last: f64,
    /// False after a passage until w rises above [`COARSE`].
    armed: bool,
    /// The singular position predicted ahead of the last accepted step (see
    /// [`SingularWatch::crossing`]).
    crossing: Option<f64>,
    /// Whether the next step may come near a singular position (see
    /// [`SingularWatch::near`]).
    near: bool,
    /// Minima of w below this are recorded as passages (default 1e-3).
    pub threshold: f64,
}

impl SingularWatch {
    /// A watch for `system`, taking the rows redundant at (t0, q0) as redundant throughout.
    pub(crate) fn new(system: &dyn System, t0: f64, q0: &[f64]) -> Self {
        let info = system.info();
        let (n, m) = (info.n(), info.m());
        let mut w = Self {
            basis: RowBasis::new(m, n),
            phi_q: DMatrix::zeros(m, n),
            phi_t: vec![0.0; m],
            starts: Vec::new(),
            columns: Vec::new(),
            redundant: vec![false; m],
            scale: vec![0.0; m],
            current: vec![1.0; m],
            best: vec![1.0; m],
            end: vec![1.0; m],
            last: 1.0,
            armed: true,
            crossing: None,
            near: false,
            threshold: 1e-3,
        };
        if let Some(s) = system.sparsity() {
            w.basis.fix_ordered(&s.jacobian, &s.order);
            (w.starts, w.columns) = row_columns(m, &s.jacobian);
        }
        w.measure(system, t0, q0);
        for r in 0..m {
            w.redundant[r] = w.basis.is_redundant(r);
        }
        w.last = w.measure(system, t0, q0);
        w.armed = w.last > COARSE;
        w
    }

    /// The weakest independence at (t, q); the row values stay in `current`.
    ///
    /// Row r's value is its independence (distance to the span of the rows before it over
    /// its norm) times |a_r| / s_r, s_r the largest |a_r| seen so far in the run: the
    /// distance of a_r to the span of the others relative to the row's own scale. A row
    /// can lose rank by turning into the others' span or by vanishing (a five-bar lying
    /// flat: every point on one line, so the row of the loop's closure across that line
    /// has gradient zero); the independence alone sees only the first.
    pub(crate) fn measure(&mut self, system: &dyn System, t: f64, q: &[f64]) -> f64 {
        system.constraint_jacobian(t, q, &mut self.phi_q, &mut self.phi_t);
        self.basis.factor(&self.phi_q);
        let mut weakest = 1.0f64;
        for r in 0..self.current.len() {
            let norm = self.row_norm(r);
            self.scale[r] = self.scale[r].max(norm);
            let shrink = if self.scale[r] > 0.0 {
                norm / self.scale[r]
            } else {
                1.0
            };
            self.current[r] = self.basis.independence(r) * shrink;
            if !self.redundant[r] {
                weakest = weakest.min(self.current[r]);
            }
        }
        weakest
    }

    /// |a_r| of the last Phi_q: over the row's structural columns when the system has a
    /// pattern ([`row_norm`]), else over the whole dense row.
    fn row_norm(&self, r: usize) -> f64 {
        if self.starts.is_empty() {
            return self.phi_q.row(r).norm();
        }
        row_norm(
            &self.phi_q,
            r,
            &self.columns[self.starts[r]..self.starts[r + 1]],
        )
    }

    /// Observes an accepted step from t0 to t0 + h. `w1` is [`SingularWatch::measure`] at
    /// its end (so `current` holds the end's rows); `at(theta)` gives w at t0 + theta h from
    /// the dense output (and leaves its rows in `current`). With `probe` (the dense output
    /// costs nothing more: it is built), a step whose ends are both above [`COARSE`] is
    /// sampled at [`PROBES`] for a passage inside it. Returns a passage when one is found
    /// (see the module docs).
    pub(crate) fn observe_step<E>(
        &mut self,
        t0: f64,
        h: f64,
        w1: f64,
        probe: bool,
        mut at: impl FnMut(&mut Self, f64) -> Result<f64, E>,
    ) -> Result<Option<SingularPassage>, E> {
        let w0 = self.last;
        self.last = w1;
        self.best.copy_from_slice(&self.current);
        let (mut best_theta, mut best_w) = (1.0, w1);
        let mut dips = w0.min(w1) < COARSE;
        if !dips && self.armed && probe {
            // A step can pass a singular position with w above COARSE at both its ends
            // (A02 N = 200 at rtol 1e-6: 0.2 s steps over a dip of about 0.1 s; 3 to 5 of
            // its 20 passages went unrecorded). Sampled at its quarters, a dip wider than
            // a quarter of the step shows.
            for theta in PROBES {
                let w = at(self, theta)?;
                self.keep(theta, w, &mut best_theta, &mut best_w);
                if w < COARSE {
                    dips = true;
                    break;
                }
            }
        }
        if dips {
            {
                // Golden-section search for the minimum of w on [0, 1].
                let r = 0.5 * (5f64.sqrt() - 1.0);
                let (mut a, mut b) = (0.0f64, 1.0f64);
                let mut c = b - r * (b - a);
                let mut d = a + r * (b - a);
                let mut fc = at(self, c)?;
                self.keep(c, fc, &mut best_theta, &mut best_w);
                let mut fd = at(self, d)?;
                self.keep(d, fd, &mut best_theta, &mut best_w);
                for _ in 0..22 {
                    if fc < fd {
                        b = d;
                        d = c;
                        fd = fc;
                        c = b - r * (b - a);
                        fc = at(self, c)?;
                        self.keep(c, fc, &mut best_theta, &mut best_w);
                    } else {
                        a = c;
                        c = d;
                        fc = fd;
                        d = a + r * (b - a);
                        fd = at(self, d)?;
                        self.keep(d, fd, &mut best_theta, &mut best_w);
                    }
                }
            }
        }
        let (ahead, wm) = self.predict_ahead(t0, h, w0, w1, &mut at)?;
        if let Some(wm) = wm {
            self.keep(0.5, wm, &mut best_theta, &mut best_w);
        }
        self.near = ahead.is_some() || self.crossing.is_some();
        self.crossing = ahead;
        if !self.armed {
            self.armed = w1 > COARSE;
            return Ok(None);
        }
        // A NaN measure records nothing.
        if best_w.is_nan() || best_w >= self.threshold {
            return Ok(None);
        }
        self.armed = w1 > COARSE;
        let cut = best_w.sqrt().max(self.threshold);
        let rows: Vec<usize> = (0..self.best.len())
            .filter(|&r| !self.redundant[r] && self.best[r] <= cut)
            .collect();
        Ok(Some(SingularPassage {
            t: t0 + best_theta * h,
            rank_drop: rows.len().max(1),
            rows,
            independence: best_w,
            geometry: PassageGeometry::Unclassified,
            stepped_over: best_w * STEPPED_OVER < w0.min(w1),
        }))
    }

    /// The singular position predicted after a step from t0 to t0 + h with w = `w0` at its
    /// start and `w1` at its end (`at` as for [`SingularWatch::observe_step`]), and w at
    /// the step's middle when it was evaluated. The secant over the whole step misses the
    /// curvature of w (A02 in angles: by a third of the next step, which put t* on one of
    /// its nodes); the parabola through w at the step's start, middle and end does not.
    fn predict_ahead<E>(
        &mut self,
        t0: f64,
        h: f64,
        w0: f64,
        w1: f64,
        at: &mut impl FnMut(&mut Self, f64) -> Result<f64, E>,
    ) -> Result<(Option<f64>, Option<f64>), E> {
        let ahead = predict(t0 + h, h, w0, w1);
        if ahead.is_none() {
            return Ok((None, None));
        }
        let wm = at(self, 0.5)?;
        Ok((predict_curved(t0, h, w0, wm, w1).or(ahead), Some(wm)))
    }

    /// The singular position [`SingularWatch::observe_step`] would predict after a step
    /// from t0 to t0 + h that is not yet accepted, `w1` its end's
    /// [`SingularWatch::measure`]: for the driver to decide whether the step ends too near
    /// it and is to be retaken. Leaves the watch as it was (with the end's rows in
    /// `current`, as `observe_step` expects them).
    pub(crate) fn ahead_of_step<E>(
        &mut self,
        t0: f64,
        h: f64,
        w1: f64,
        mut at: impl FnMut(&mut Self, f64) -> Result<f64, E>,
    ) -> Result<Option<f64>, E> {
        self.end.copy_from_slice(&self.current);
        let ahead = self.predict_ahead(t0, h, self.last, w1, &mut at);
        self.current.copy_from_slice(&self.end);
        Ok(ahead?.0)
    }

    /// The time t* at which w is predicted to reach zero after the last accepted step,
    /// when w fell below [`COARSE`] over it: the line through w at the step's two ends
    /// (w ~ |t - t*| near a simple passage). `None` while w rises or stays coarse.
    pub(crate) fn crossing(&self) -> Option<f64> {
        self.crossing
    }

    /// Whether the next step may come near a singular position: one is predicted ahead
    /// ([`SingularWatch::crossing`]), or was at the start of the last step (which then
    /// passed it, or ended just before it).
    pub(crate) fn near(&self) -> bool {
        self.near
    }

    /// Where a run whose step size collapsed stands with respect to a singular position:
    /// the predicted t* (when w was still falling) and w at the last accepted step, when
    /// that w is below [`COARSE`]; `None` farther away.
    pub(crate) fn stuck(&self) -> Option<(Option<f64>, f64)> {
        (self.last < COARSE).then_some((self.crossing, self.last))
    }

    /// The rank of Phi_q at regular points: its rows less those redundant at the start.
    pub(crate) fn rank(&self) -> usize {
        self.redundant.iter().filter(|&&r| !r).count()
    }

    /// The rows losing rank at the closest approach of the last accepted step (the rows
    /// of the weakest independence, w, and those within max(sqrt(w), threshold) of zero,
    /// as for a passage). Allocates: for a failure's message.
    pub(crate) fn weak_rows(&self) -> Vec<usize> {
        let rows = || (0..self.best.len()).filter(|&r| !self.redundant[r]);
        let weakest = rows().map(|r| self.best[r]).fold(1.0f64, f64::min);
        let cut = weakest.sqrt().max(self.threshold);
        rows().filter(|&r| self.best[r] <= cut).collect()
    }

    fn keep(&mut self, theta: f64, w: f64, best_theta: &mut f64, best_w: &mut f64) {
        if w < *best_w {
            *best_w = w;
            *best_theta = theta;
            self.best.copy_from_slice(&self.current);
        }
    }
}

/// The columns of each of the m rows of `pattern` ((row, column) pairs), ascending and
/// without repeats, as row starts and the columns one row after the other (compressed
/// rows).
fn row_columns(m: usize, pattern: &[(usize, usize)]) -> (Vec<usize>, Vec<usize>) {
    let mut sorted = pattern.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let mut starts = vec![0; m + 1];
    for &(r, _) in &sorted {
        starts[r + 1] += 1;
    }
    for r in 0..m {
        starts[r + 1] += starts[r];
    }
    (starts, sorted.into_iter().map(|(_, j)| j).collect())
}

/// |a_r| from the entries of row r of `a` in `columns` (ascending; every other entry of the
/// row zero): the squares summed in ascending column order, as nalgebra's dense row norm
/// sums them, so the result is that norm to the bit (a zero adds nothing to a sum of
/// squares) at the cost of the row's entries instead of n strided reads.
fn row_norm(a: &DMatrix<f64>, r: usize, columns: &[usize]) -> f64 {
    let (m, s) = (a.nrows(), a.as_slice());
    let squares = columns.iter().map(|&j| s[r + j * m] * s[r + j * m]);
    squares.fold(0.0, |sum, x| sum + x).sqrt()
}

/// The first zero after the step's end t0 + h of the parabola through w at the step's
/// start, middle and end (`w0`, `wm`, `w1`), when w falls over the step's second half;
/// `None` when it has none there.
fn predict_curved(t0: f64, h: f64, w0: f64, wm: f64, w1: f64) -> Option<f64> {
    if !wm.is_finite() || wm <= w1 {
        return None;
    }
    // w(theta) = w0 + b theta + c theta^2 on theta = (t - t0) / h.
    let c = 2.0 * (w1 - 2.0 * wm + w0);
    let b = w1 - w0 - c;
    let theta = if c.abs() <= 1e-12 * (w0.abs() + w1.abs()) {
        -w0 / b
    } else {
        let disc = b * b - 4.0 * c * w0;
        if disc < 0.0 {
            return None;
        }
        let r = disc.sqrt();
        let (x1, x2) = ((-b - r) / (2.0 * c), (-b + r) / (2.0 * c));
        let (lo, hi) = (x1.min(x2), x1.max(x2));
        if lo >= 1.0 { lo } else { hi }
    };
    (theta >= 1.0 && theta.is_finite()).then_some(t0 + theta * h)
}

/// The zero of the line through (t1 - h, w0) and (t1, w1) when w falls to below
/// [`COARSE`] (w1 < w0, w1 < COARSE), else `None`.
fn predict(t1: f64, h: f64, w0: f64, w1: f64) -> Option<f64> {
    (w1 < w0 && w1 < COARSE && h > 0.0).then(|| t1 + w1 * h / (w0 - w1))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sparse row norms over a pattern's columns equal nalgebra's dense row norms bit
    /// for bit (so the watch's w, and the passages and steering that follow from it, are
    /// those of the dense route), on a random pattern with repeated entries, empty rows and
    /// values from 1e-8 to 1e3 (where a different summation order would differ in the
    /// last bits).
    #[test]
    fn sparse_row_norms_are_the_dense_ones_to_the_bit() {
        let (m, n) = (40, 37);
        let mut seed = 0x5ca1_ab1eu64;
        let mut next = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            seed >> 11
        };
        let mut pattern = Vec::new();
        for r in (0..m).filter(|r| r % 7 != 3) {
            for _ in 0..1 + next() % 6 {
                pattern.push((r, (next() % n as u64) as usize));
            }
        }
        // A repeat, listed out of order.
        pattern.push(pattern[0]);
        let mut a = DMatrix::zeros(m, n);
        for &(r, j) in &pattern {
            let unit = (next() % 1_000_003) as f64 / 1_000_003.0 - 0.5;
            a[(r, j)] = unit * 10f64.powi((next() % 12) as i32 - 8);
        }
        let (starts, columns) = row_columns(m, &pattern);
        assert_eq!(starts.len(), m + 1);
        for r in 0..m {
            let sparse = row_norm(&a, r, &columns[starts[r]..starts[r + 1]]);
            let dense = a.row(r).norm();
            assert_eq!(
                sparse.to_bits(),
                dense.to_bits(),
                "row {r}: {sparse:e} vs {dense:e}"
            );
        }
    }

    /// On a w that is a parabola in t (w = 0.25 - 2 (t - 1) - 3 (t - 1)^2, zero at
    /// t* = 1 + (sqrt(7) - 2) / 6 ~ 1.10763), the curved prediction from the step
    /// [1 - h, 1] is t* to round-off, where the secant misses it by 0.04 (h = 0.1): the
    /// curvature the secant leaves out.
    #[test]
    fn the_curved_prediction_follows_the_curvature_of_w() {
        let w = |t: f64| 0.25 - 2.0 * (t - 1.0) - 3.0 * (t - 1.0) * (t - 1.0);
        let exact = 1.0 + (7.0f64.sqrt() - 2.0) / 6.0;
        let h = 0.1;
        let (w0, wm, w1) = (w(1.0 - h), w(1.0 - h / 2.0), w(1.0));
        let curved = predict_curved(1.0 - h, h, w0, wm, w1).unwrap();
        assert!((curved - exact).abs() < 1e-12, "{curved} vs {exact}");
        let secant = predict(1.0, h, w0, w1).unwrap();
        assert!((secant - exact).abs() > 1e-2, "{secant} vs {exact}");
        // Rising w, or a parabola that turns up before reaching zero: no prediction.
        assert_eq!(predict_curved(0.0, h, 0.1, 0.2, 0.3), None);
        assert_eq!(predict_curved(0.0, h, 0.3, 0.2, 0.19), None);
    }
}
