//! Empty: this package holds the compile-fail cases of `mechanism!` in `tests/ui/` and
//! their runner `tests/ui.rs` (a package needs a library or a binary to hold tests).
