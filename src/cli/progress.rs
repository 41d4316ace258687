//! A progress bar for long runs: drawn on stderr only when stderr is a terminal and the run
//! has already taken longer than a threshold (1 s by default); otherwise nothing is printed
//! and [`Progress::set`] costs a clock read.

use std::io::IsTerminal;
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Progress of a simulation from t = 0 to `t_end`, reported through [`Progress::set`]
/// (`Progress::new(t_end)`, then `set(t)` as the run advances, then `finish()`).
#[derive(Debug)]
pub struct Progress {
    t_end: f64,
    start: Instant,
    delay: Duration,
    enabled: bool,
    bar: Option<ProgressBar>,
    last_draw: Option<Instant>,
}

/// Resolution of the bar: positions are in thousandths of `t_end`.
const TICKS: u64 = 1000;

impl Progress {
    /// A bar for a run to `t_end` (s), shown after 1 s when stderr is a terminal.
    pub fn new(t_end: f64) -> Self {
        Self::with_delay(t_end, Duration::from_secs(1))
    }

    /// Like [`Progress::new`], shown only once the run has lasted `delay`.
    pub fn with_delay(t_end: f64, delay: Duration) -> Self {
        let enabled = std::io::stderr().is_terminal() && t_end.is_finite() && t_end > 0.0;
        Self {
            t_end,
            start: Instant::now(),
            delay,
            enabled,
            bar: None,
            last_draw: None,
        }
    }

    /// A progress that never draws anything.
    #[cfg(test)]
    pub fn hidden() -> Self {
        let mut progress = Self::new(0.0);
        progress.enabled = false;
        progress
    }

    /// True once the bar is on screen.
    #[cfg(test)]
    pub fn is_visible(&self) -> bool {
        self.bar.is_some()
    }

    /// Reports that the run has reached time `t` (s). Cheap: redraws at most every 100 ms.
    pub fn set(&mut self, t: f64) {
        if !self.enabled {
            return;
        }
        let now = Instant::now();
        if self
            .last_draw
            .is_some_and(|last| now - last < Duration::from_millis(100))
        {
            return;
        }
        if self.bar.is_none() && now - self.start < self.delay {
            return;
        }
        self.last_draw = Some(now);
        let t_end = self.t_end;
        let bar = self.bar.get_or_insert_with(|| {
            let style = ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {wide_bar} {msg} (eta {eta})",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar());
            let bar = ProgressBar::with_draw_target(Some(TICKS), ProgressDrawTarget::stderr())
                .with_style(style);
            bar.reset_elapsed();
            bar
        });
        let fraction = (t / t_end).clamp(0.0, 1.0);
        bar.set_position((fraction * TICKS as f64) as u64);
        bar.set_message(format!("t = {t:.3} / {t_end} s"));
    }

    /// Removes the bar, if shown.
    pub fn finish(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}

#[cfg(test)]
mod tests {
    //! The progress bar is silent when stderr is not a terminal (as under `cargo test`).
    use std::time::Duration;

    use super::Progress;

    #[test]
    fn progress_is_a_no_op_off_terminal_and_for_short_runs() {
        let mut progress = Progress::with_delay(10.0, Duration::ZERO);
        for i in 0..=1000 {
            progress.set(f64::from(i) * 0.01);
        }
        // Under the test harness stderr is captured, not a terminal: nothing is drawn.
        if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
            assert!(!progress.is_visible());
        }
        progress.finish();
        assert!(!progress.is_visible());

        let mut hidden = Progress::hidden();
        hidden.set(f64::NAN);
        hidden.set(f64::INFINITY);
        assert!(!hidden.is_visible());

        // A run that ends before the delay never shows a bar, even on a terminal.
        let mut short = Progress::new(1.0);
        short.set(0.5);
        short.set(1.0);
        assert!(!short.is_visible());
    }
}
