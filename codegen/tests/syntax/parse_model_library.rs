//! Every declaration shipped under `mechanisms/` parses and checks, and every expression in it
//! prints to text that reads back to the same node.

use mechanism_codegen::{parse_declaration_str, parse_expr, to_text};

#[test]
fn every_shipped_declaration_parses_and_round_trips() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../mechanisms");
    let mut count = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "mech") {
            continue;
        }
        let text = std::fs::read_to_string(&path).unwrap();
        let parsed =
            parse_declaration_str(&text).unwrap_or_else(|e| panic!("{}: {e:#?}", path.display()));
        let m = parsed.model;
        assert!(!m.coordinates.is_empty(), "{}", path.display());
        let mut arena = m.arena.clone();
        let exprs = [m.kinetic, m.potential]
            .into_iter()
            .chain(m.constraints.iter().map(|c| c.expr))
            .chain(m.forces.iter().copied());
        for e in exprs {
            let printed = to_text(&m.arena, e);
            assert_eq!(
                parse_expr(&mut arena, &printed).unwrap(),
                e,
                "{}: {printed}",
                path.display()
            );
        }
        count += 1;
    }
    assert!(
        count >= 6,
        "found {count} declarations in {}",
        dir.display()
    );
}
