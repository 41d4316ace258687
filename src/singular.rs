//! Singular configurations that a motion passes through.
//!
//! A singular configuration is one where Phi_q loses rank for an instant: a chain of
//! four-bar loops lying flat, a press at toggle. The solvers integrate through them (see
//! [`crate::Dynamics`]); this module only records where they happened.
//!
//! The test is the one [`crate::mobility`] uses for the rank, applied after every accepted
//! step: the independence of each row (its distance to the span of the rows before it,
//! relative to its norm; [`crate::linalg::RowBasis`]). Rows redundant at the start are left
//! out; the **weakest** independence w of the others measures the distance to a singular
//! configuration (w = 0 at one). A passage is recorded where w has a local minimum over the
//! accepted steps that is below [`SingularWatch::threshold`] (default 0.05: a row within
//! about 3 degrees of the span of the others). Its time is estimated by assuming w falls and
//! rises at the same rate on both sides (w ~ |t - t*| near a simple passage), from the two
//! steps around the minimum; its rank drop is the number of rows whose independence is below
//! sqrt(w_min) there (the rows that fall together; the others stay near 1).

use nalgebra::DMatrix;

use crate::linalg::RowBasis;
use crate::mechanism::System;

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
}

/// Watches the rank of Phi_q along a simulation; allocates only when it records a passage.
#[derive(Clone, Debug)]
pub(crate) struct SingularWatch {
    basis: RowBasis,
    phi_q: DMatrix<f64>,
    phi_t: Vec<f64>,
    /// Rows redundant at the start, left out of the weakest independence.
    redundant: Vec<bool>,
    /// (t, w) at the last two observations, oldest first.
    history: [(f64, f64); 2],
    seen: usize,
    /// Row independences at the previous observation.
    previous: Vec<f64>,
    current: Vec<f64>,
    /// Local minima of w below this are recorded (default 0.05).
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
            redundant: vec![false; m],
            history: [(t0, 1.0); 2],
            seen: 0,
            previous: vec![1.0; m],
            current: vec![1.0; m],
            threshold: 0.05,
        };
        w.measure(system, t0, q0);
        for r in 0..m {
            w.redundant[r] = w.basis.is_redundant(r);
        }
        w
    }

    fn measure(&mut self, system: &dyn System, t: f64, q: &[f64]) -> f64 {
        system.constraint_jacobian(t, q, &mut self.phi_q, &mut self.phi_t);
        self.basis.factor(&self.phi_q);
        let mut weakest = 1.0f64;
        for r in 0..self.current.len() {
            self.current[r] = self.basis.independence(r);
            if !self.redundant[r] {
                weakest = weakest.min(self.current[r]);
            }
        }
        weakest
    }

    /// Observes the accepted state at (t, q); returns a passage when the previous
    /// observation was a local minimum of w below the threshold.
    pub(crate) fn observe(
        &mut self,
        system: &dyn System,
        t: f64,
        q: &[f64],
    ) -> Option<SingularPassage> {
        std::mem::swap(&mut self.previous, &mut self.current);
        let w = self.measure(system, t, q);
        let [(t0, w0), (t1, w1)] = self.history;
        self.history = [(t1, w1), (t, w)];
        self.seen += 1;
        if self.seen < 2 || !(w1 < w0 && w1 <= w && w1 < self.threshold) {
            return None;
        }
        // The side of the V on which the zero lies is the one with the lower neighbour.
        let t_star = if w <= w0 {
            t1 + (t - t1) * w1 / (w1 + w).max(f64::MIN_POSITIVE)
        } else {
            t1 - (t1 - t0) * w1 / (w1 + w0).max(f64::MIN_POSITIVE)
        };
        let cut = w1.sqrt();
        let rows: Vec<usize> = (0..self.previous.len())
            .filter(|&r| !self.redundant[r] && self.previous[r] <= cut)
            .collect();
        Some(SingularPassage {
            t: t_star,
            rank_drop: rows.len().max(1),
            rows,
            independence: w1,
        })
    }
}
