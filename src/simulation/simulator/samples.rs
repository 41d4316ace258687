//! The driver's outputs inside an accepted step: the samples at the output times and the
//! singular passages, read off the stepper's dense output.

use super::Simulator;
use crate::algorithms::stabilization::Stabilization;
use crate::error::Error;
use crate::simulation::apex::classify;

impl Simulator<'_> {
    /// Records the output samples that fall inside (t, t_stop] of the step of size h (before
    /// t_stop itself when an event stops the run there).
    pub(super) fn record_outputs(
        &mut self,
        h: f64,
        t_stop: f64,
        stopping: bool,
    ) -> Result<(), Error> {
        while self.next_output <= self.outputs {
            let to = self.output_time(self.next_output);
            if to > t_stop + 1e-12 * t_stop.abs().max(1.0) || (stopping && to >= t_stop) {
                break;
            }
            self.dense_at(((to - self.t) / h).clamp(0.0, 1.0))?;
            self.record(to)?;
            self.next_output += 1;
        }
        Ok(())
    }

    /// The singular watch's w at the end of the step just taken (self.t + h, y_new), NaN
    /// without a watch.
    pub(super) fn measure_end(&mut self, h: f64) -> f64 {
        let (n, t1, system) = (self.n, self.t + h, self.system());
        match self.watch.as_mut() {
            Some(watch) => watch.measure(system, t1, &self.state.y_new[..n]),
            None => f64::NAN,
        }
    }

    /// Whether the step just taken (from self.t to self.t + h, w1 its end's
    /// [`Simulator::measure_end`]) ends just before a singular position that the watch
    /// predicts only now; if so the stepper has been told to take it again, steered
    /// ([`crate::simulation::stepper::Stepper::retake`]), with its stages projected.
    pub(super) fn retake_before_singular(&mut self, h: f64, w1: f64) -> Result<bool, Error> {
        if !self.stepper.retakes() {
            return Ok(false);
        }
        let Some(mut watch) = self.watch.take() else {
            return Ok(false);
        };
        let (n, t0, system) = (self.n, self.t, self.system());
        let ahead = watch.ahead_of_step(t0, h, w1, |w, theta| {
            self.dense_at(theta)?;
            Ok::<f64, Error>(w.measure(system, t0 + theta * h, &self.state.y_dense[..n]))
        });
        self.watch = Some(watch);
        let retake = ahead?.is_some_and(|ts| self.stepper.retake(t0, h, ts));
        if retake {
            self.rhs.near_singular(true);
        }
        Ok(retake)
    }

    /// Records the singular configurations passed inside the step just taken (from self.t
    /// to self.t + h, before it is accepted, w1 its end's [`Simulator::measure_end`]): see
    /// [`crate::SingularPassage`].
    pub(super) fn watch_singular(&mut self, h: f64, w1: f64) -> Result<(), Error> {
        let Some(mut watch) = self.watch.take() else {
            return Ok(());
        };
        let (n, t0, system) = (self.n, self.t, self.system());
        let probe = self.stepper.dense_built();
        let found = watch.observe_step(t0, h, w1, probe, |w, theta| {
            self.dense_at(theta)?;
            Ok::<f64, Error>(w.measure(system, t0 + theta * h, &self.state.y_dense[..n]))
        });
        self.stepper.steer(watch.crossing());
        self.rhs.near_singular(watch.near());
        let rank = watch.rank();
        self.watch = Some(watch);
        if let Some(mut p) = found? {
            // The closest approach's state, for the passage's geometry.
            self.dense_at(((p.t - t0) / h).clamp(0.0, 1.0))?;
            let q = &self.state.y_dense[..n];
            p.geometry = classify(system, p.t, q, rank, p.rank_drop, p.independence);
            self.trajectory.singular_passages.push(p);
        }
        Ok(())
    }

    fn output_time(&self, k: usize) -> f64 {
        let o = self.options;
        if k >= self.outputs {
            o.t_end
        } else {
            (o.t_start + k as f64 / o.output_rate).min(o.t_end)
        }
    }

    /// Fills `y_dense` with the continuous extension of the last step at theta.
    pub(super) fn dense_at(&mut self, theta: f64) -> Result<(), Error> {
        let state = &mut self.state;
        self.stepper.dense(
            &mut self.rhs,
            self.t,
            &state.y,
            &state.y_new,
            theta,
            &mut state.y_dense,
        )
    }

    /// Projects `y_dense` when the stabilisation is projection, solves the augmented system
    /// there and appends the sample at time `ts`.
    pub(super) fn record(&mut self, ts: f64) -> Result<(), Error> {
        let n = self.n;
        let system = self.rhs.system;
        let (q, rest) = self.state.y_dense.split_at_mut(n);
        let (qd, w) = rest.split_at_mut(n);
        if self.options.stabilization == Stabilization::Projection {
            self.rhs.projector.project(system, ts, q, qd)?;
        }
        let d = &mut self.rhs.dynamics;
        d.solve(system, ts, q, qd)?;
        // Redundant rows leave lambda undetermined: record the minimum-norm choice.
        d.min_norm_multipliers();
        let e = d.evaluation();
        self.trajectory.push(
            ts,
            q,
            qd,
            d.accelerations(),
            d.multipliers(),
            d.constraint_error(),
            d.velocity_constraint_error(qd),
            [e.kinetic, e.potential, w[0]],
        );
        Ok(())
    }
}
