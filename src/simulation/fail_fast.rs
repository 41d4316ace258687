//! The tests that stop a run which cannot succeed, long before its step limit.
//!
//! - **Fixed step too small** (checked in [`crate::Simulator::new`], before any work): RK4
//!   or HHT with step h needs ceil((t_end - t0) / h) steps; more than `max_steps` is
//!   [`Error::FixedStepTooSmall`].
//! - **Step-size collapse** (adaptive methods): after [`MIN_STEPS`] accepted steps, the
//!   mean step of the last [`WINDOW`] ones, h, projects (t_end - t) / h more steps. When the
//!   steps taken plus that projection exceed [`COLLAPSE_FACTOR`] times `max_steps`, the run
//!   is [`Error::StepSizeCollapse`]: it would need the step to grow more than tenfold, on
//!   average, over the rest of the run to finish within its limit, which a step size that
//!   has collapsed (stiffness, a parameter far out of scale, a force that blows up) does not
//!   do. With g = 1e23 on a 0.1 m four-bar this stops after 1000 steps instead of 10
//!   million.
//! - **Divergence** (every accepted step): a coordinate or a rate that is NaN, infinite, or
//!   larger than [`DIVERGENCE_FACTOR`] times its scale at the start is [`Error::Diverged`],
//!   naming the coordinate, the value and t. The scale of the positions is the largest of
//!   1, |q(t0)|_inf and |q'(t0)|_inf (t_end - t0) (where the starting rates alone would
//!   carry them); that of the rates the larger of 1 and |q'(t0)|_inf. Units mix (m, rad),
//!   but a factor of 1e12 leaves every physical range (a 1 m linkage 1e9 km away, a crank at
//!   1e12 rad/s) and 12 of the 16 digits of f64: whatever follows is meaningless.
//!
//! Nothing here allocates after [`FailFast::new`].

// Comparisons are written `!(x <= limit)` on purpose: NaN must fail them.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::error::Error;

/// Accepted steps whose mean size is the "recent step" of the collapse test.
pub const WINDOW: usize = 100;
/// Accepted steps before the collapse test starts: the first steps (the starting-step
/// estimate, the rejections while the controller finds its size) say little about the rest.
pub const MIN_STEPS: usize = 1000;
/// The collapse test stops a run whose projected step count exceeds this many times the
/// step limit (see the module docs).
pub const COLLAPSE_FACTOR: f64 = 10.0;
/// Growth of |q| or |q'| over its starting scale taken as divergence (see the module docs).
pub const DIVERGENCE_FACTOR: f64 = 1e12;

/// The state of the fail-fast tests along one run.
pub(crate) struct FailFast {
    /// t after each of the last [`WINDOW`] accepted steps (ring buffer, by step count).
    recent: [f64; WINDOW],
    /// Bounds on |q_i| and |q'_i|.
    position_limit: f64,
    rate_limit: f64,
    max_steps: usize,
    /// The start time of the run (s).
    start: f64,
}

impl FailFast {
    /// The tests for a run from (q0, q0') at t0 to t0 + span within `max_steps` accepted
    /// steps.
    pub(crate) fn new(q0: &[f64], qd0: &[f64], t0: f64, span: f64, max_steps: usize) -> Self {
        let (q_scale, v_scale) = (crate::linalg::inf_norm(q0), crate::linalg::inf_norm(qd0));
        Self {
            recent: [0.0; WINDOW],
            position_limit: DIVERGENCE_FACTOR * 1f64.max(q_scale).max(v_scale * span),
            rate_limit: DIVERGENCE_FACTOR * 1f64.max(v_scale),
            max_steps,
            start: t0,
        }
    }

    /// Refuses a fixed step h over `span` that needs more than `max_steps` steps (a step
    /// that is not positive is left to the options check).
    pub(crate) fn check_fixed_step(h: f64, span: f64, max_steps: usize) -> Result<(), Error> {
        let steps = (span / h).ceil();
        if h > 0.0 && steps > max_steps as f64 {
            return Err(Error::FixedStepTooSmall {
                h,
                span,
                steps,
                max_steps,
            });
        }
        Ok(())
    }

    /// Records that accepted step number `steps` (1-based) ended at `t`, and applies the
    /// collapse test towards `t_end`.
    pub(crate) fn after_step(&mut self, steps: usize, t: f64, t_end: f64) -> Result<(), Error> {
        let slot = steps % WINDOW;
        let before = self.recent[slot]; // t after step number steps - WINDOW
        self.recent[slot] = t;
        if steps < MIN_STEPS.max(WINDOW) {
            return Ok(());
        }
        let h = (t - before) / WINDOW as f64;
        let steps_needed = (t_end - t) / h;
        let allowed = COLLAPSE_FACTOR * self.max_steps as f64;
        // h = 0 (no progress at all) projects infinitely many steps; NaN cannot pass.
        if !(steps as f64 + steps_needed <= allowed) {
            // A step as large as a tenth of the run's mean has not collapsed: the span is
            // too long for the step the motion needs.
            let h_run = (t - self.start) / steps as f64;
            if h >= 0.1 * h_run && h > 0.0 {
                return Err(Error::SpanTooLong {
                    t,
                    t_end,
                    h,
                    h_run,
                    steps_needed,
                    max_steps: self.max_steps,
                });
            }
            return Err(Error::StepSizeCollapse {
                t,
                h,
                steps_needed,
                max_steps: self.max_steps,
            });
        }
        Ok(())
    }

    /// The divergence test on the state q (`names` in order), q' at time t.
    pub(crate) fn check_state(
        &self,
        q: &[f64],
        qd: &[f64],
        names: &[String],
        t: f64,
    ) -> Result<(), Error> {
        let bounds = [("q", q, self.position_limit), ("q'", qd, self.rate_limit)];
        for (quantity, values, limit) in bounds {
            // Written so that NaN fails the test.
            if let Some(i) = values.iter().position(|v| !(v.abs() <= limit)) {
                return Err(Error::Diverged {
                    t,
                    quantity,
                    coordinate: names.get(i).cloned().unwrap_or_default(),
                    value: values[i],
                    limit,
                });
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_steady_step_passes_and_a_collapsed_one_stops() {
        // 1e-3 s steps over 10 s need 1e4 steps: fine within 1e5.
        let mut ok = FailFast::new(&[0.0], &[0.0], 0.0, 10.0, 100_000);
        for k in 1..=2000 {
            ok.after_step(k, k as f64 * 1e-3, 10.0).expect("steady");
        }
        // 1000 steps of 1e-3 s, then of 1e-9 s: once the last 100 are all 1e-9 s (step
        // 1100) the rest needs about 1e10 steps, and 1e-9 s is far below the run's mean
        // (1 s / 1100): a collapse.
        let mut bad = FailFast::new(&[0.0], &[0.0], 0.0, 10.0, 100_000);
        let time = |k: usize| {
            if k <= 1000 {
                k as f64 * 1e-3
            } else {
                1.0 + (k - 1000) as f64 * 1e-9
            }
        };
        let (k, err) = (1..=2000)
            .find_map(|k| bad.after_step(k, time(k), 10.0).err().map(|e| (k, e)))
            .expect("collapse");
        assert_eq!(k, 1100);
        match err {
            Error::StepSizeCollapse {
                h, steps_needed, ..
            } => {
                assert!((h / 1e-9 - 1.0).abs() < 1e-6, "{h}");
                assert!((steps_needed / 9e9 - 1.0).abs() < 1e-6, "{steps_needed}");
            }
            other => panic!("{other}"),
        }
    }

    #[test]
    fn a_steady_step_over_a_span_too_long_is_named_as_such() {
        // A steady 1e-3 s over 1e9 s needs 1e12 steps: stopped after MIN_STEPS, as a span
        // too long, not a collapse (the step is the run's mean).
        let mut long = FailFast::new(&[0.0], &[0.0], 0.0, 1e9, 100_000);
        let err = (1..=2000)
            .find_map(|k| long.after_step(k, k as f64 * 1e-3, 1e9).err())
            .expect("too long");
        match err {
            Error::SpanTooLong {
                h, h_run, t_end, ..
            } => {
                assert!((h / 1e-3 - 1.0).abs() < 1e-9, "{h}");
                assert!((h_run / 1e-3 - 1.0).abs() < 1e-9, "{h_run}");
                assert_eq!(t_end, 1e9);
            }
            other => panic!("{other}"),
        }
    }

    #[test]
    fn divergence_is_relative_to_the_starting_scale() {
        let names = vec!["x".to_string()];
        let f = FailFast::new(&[2.0], &[3.0], 0.0, 10.0, 1000);
        // Positions may reach 1e12 * max(1, 2, 3 * 10); rates 1e12 * 3.
        f.check_state(&[2.9e13], &[2.9e12], &names, 1.0)
            .expect("inside");
        assert!(f.check_state(&[3.1e13], &[0.0], &names, 1.0).is_err());
        assert!(f.check_state(&[0.0], &[3.1e12], &names, 1.0).is_err());
        assert!(f.check_state(&[f64::NAN], &[0.0], &names, 1.0).is_err());
    }
}
