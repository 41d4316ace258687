//! The progress bar is silent when stderr is not a terminal (as under `cargo test`).

use std::time::Duration;

use mechanism::Progress;

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
