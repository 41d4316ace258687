//! Compile-fail and pass cases of `mechanism!` (trybuild). Each `.stderr` pins the message
//! and the token it points at; regenerate with `TRYBUILD=overwrite` and review the diff.

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
    t.pass("tests/ui/pass/*.rs");
}
