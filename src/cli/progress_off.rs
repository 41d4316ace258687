//! Without the `progress` feature: a progress report that draws nothing.

/// Progress of a run to `t_end`; this build draws no bar.
#[derive(Debug)]
pub struct Progress;

impl Progress {
    /// A progress report for a run to `t_end` (s).
    pub fn new(t_end: f64) -> Self {
        let _ = t_end;
        Progress
    }

    /// The run has reached `t` (s).
    pub fn set(&mut self, t: f64) {
        let _ = t;
    }

    /// The run is over.
    pub fn finish(&mut self) {}
}
