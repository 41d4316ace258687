//! The events inside an accepted step: each sign change of an event function located on
//! the stepper's dense output ([`illinois`]), the crossings recorded in time order and the
//! first stopping one reported.

// Comparisons are written `!(x <= 0.0)` on purpose: NaN must fail them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use super::Simulator;
use crate::algorithms::stabilization::Stabilization;
use crate::error::Error;
use crate::simulation::events::{EventAction, EventHit, illinois};

impl Simulator<'_> {
    /// Finds the sign changes of the event functions between the step start (g_old) and
    /// its end, locates each by the Illinois variant of regula falsi on the dense output,
    /// records the crossings up to the first stopping one and reports that one.
    #[allow(clippy::needless_range_loop)] // events, g_old and roots share the index
    pub(super) fn locate_events(
        &mut self,
        h: f64,
        t_stop: &mut f64,
        stop_event: &mut Option<usize>,
    ) -> Result<(), Error> {
        let n = self.n;
        let events = &self.options.events;
        let t0 = self.t;
        for i in 0..events.len() {
            self.events.roots[i] = f64::NAN;
            let g = &events[i].g;
            let g0 = self.events.g_old[i];
            let g1 = g(t0 + h, &self.state.y_new[..n], &self.state.y_new[n..2 * n]);
            if g0 == 0.0 || !(g0 * g1 <= 0.0) {
                continue;
            }
            let b = illinois(g0, g1, h, t0, |c| {
                self.dense_at(c)?;
                let y = &self.state.y_dense;
                Ok(g(t0 + c * h, &y[..n], &y[n..2 * n]))
            })?;
            self.events.roots[i] = t0 + b * h;
            if events[i].action == EventAction::Stop && self.events.roots[i] < *t_stop {
                *t_stop = self.events.roots[i];
                *stop_event = Some(i);
            }
        }
        self.record_crossings(h, *t_stop)
    }

    /// Records the located crossings up to t_stop, in time order (projected onto the
    /// constraints when the stabilisation is projection).
    fn record_crossings(&mut self, h: f64, t_stop: f64) -> Result<(), Error> {
        let (n, t0) = (self.n, self.t);
        loop {
            let roots = &self.events.roots;
            let best = (0..roots.len())
                .filter(|&i| roots[i].is_finite() && roots[i] <= t_stop)
                .min_by(|&a, &b| roots[a].total_cmp(&roots[b]));
            let Some(i) = best else { break };
            let tr = self.events.roots[i];
            self.events.roots[i] = f64::NAN;
            self.dense_at(((tr - t0) / h).clamp(0.0, 1.0))?;
            let (q, rest) = self.state.y_dense.split_at_mut(n);
            if self.options.stabilization == Stabilization::Projection {
                self.rhs
                    .projector
                    .project(self.rhs.system, tr, q, &mut rest[..n])?;
            }
            self.events.hits.push(EventHit {
                event: i,
                t: tr,
                q: q.to_vec(),
                qd: rest[..n].to_vec(),
            });
        }
        Ok(())
    }
}
