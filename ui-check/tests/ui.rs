//! Compile-fail cases of `mechanism!` (trybuild). Each `.stderr` pins the message and the
//! token it points at; regenerate with `TRYBUILD=overwrite cargo test -p mechanism-ui-check
//! --test ui` and review the diff. With no pass case trybuild runs `cargo check`, so the
//! runtime crate and the other dependencies are checked, not compiled to code. The cases
//! that must compile and run are tests of the root crate (`tests/macros/pass_cases.rs`).

#[test]
fn ui() {
    let t = trybuild::TestCases::new();
    for category in [
        "symbols",
        "declarations",
        "rates",
        "sizes",
        "syntax",
        "files",
        "bodies",
        "drawing",
        "physics",
        "links",
    ] {
        t.compile_fail(format!("tests/ui/{category}/*.rs"));
    }
}
