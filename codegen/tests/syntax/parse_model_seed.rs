//! The seed declaration parses into the model it describes, by both routes.

use std::str::FromStr;

use crate::parse_support::SEED;
use mechanism_codegen::internals::parse_model;
use mechanism_codegen::{Model, eval, parse_model_str, to_text};

fn check_seed(m: &Model) {
    assert_eq!(m.name, "SpatialCrankSlider");
    assert!(m.public);
    assert_eq!(
        m.doc,
        ["Spatial crank-slider of the seed paper (Section II), with ERRATA decisions."]
    );
    let names: Vec<&str> = m.coordinates.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, ["phi", "beta", "gamma", "x_c"]);
    assert_eq!(m.coordinates.len(), 4, "n");
    assert_eq!(m.constraints.len(), 3, "m");
    assert_eq!(m.parameters.len(), 13);
    let p = |name: &str| {
        m.parameters
            .iter()
            .find(|p| p.name == name)
            .unwrap()
            .default
    };
    assert_eq!(p("J1"), 1e-4);
    assert_eq!(p("a1"), 0.04);
    assert_eq!(p("Omega"), 2.0 * std::f64::consts::PI);
    let guesses: Vec<f64> = m.coordinates.iter().map(|c| c.guess).collect();
    assert_eq!(guesses, [0.0, 0.46, 0.84, 0.2]);
    assert_eq!(m.independent.len(), 1);
    assert_eq!(m.independent[0].coordinate, 0);
    assert_eq!(m.independent[0].position, 0.0);
    assert_eq!(m.independent[0].velocity, 2.0 * std::f64::consts::PI);

    let a = &m.arena;
    assert_eq!(to_text(a, m.forces[0]), "tau0*sin(Omega*t)");
    assert!(
        m.forces[1..].iter().all(|&f| a.is_zero(f)),
        "no force on beta, gamma, x_c"
    );
    assert_eq!(
        to_text(a, m.constraints[2].expr),
        "h + l1*cos(phi) - l2*cos(gamma)",
        "third constraint"
    );
    // Every expression is a function of declared symbols only, and reads back to itself.
    let mut copy = m.arena.clone();
    for e in [m.kinetic, m.potential]
        .into_iter()
        .chain(m.constraints.iter().map(|c| c.expr))
    {
        let text = to_text(a, e);
        assert_eq!(
            mechanism_codegen::parse_expr(&mut copy, &text).unwrap(),
            e,
            "{text}"
        );
    }
    // The energies have the declared values at a state (parameters at their defaults).
    let state = [0.3, 0.5, 0.8, 0.25];
    let rates = [1.5, -0.2, 0.7, 0.4];
    let env = |s: mechanism_codegen::SymbolId| {
        let node = a.symbol_node(s);
        if let Some(p) = m.parameters.iter().find(|p| p.symbol == node) {
            return Some(p.default);
        }
        m.coordinates.iter().enumerate().find_map(|(k, c)| {
            if c.q == node {
                Some(state[k])
            } else if c.qd == node {
                Some(rates[k])
            } else {
                None
            }
        })
    };
    let (j1, m1, m2, m3, l1, a1, h, g) = (1e-4, 0.12, 0.5, 2.0, 0.08, 0.04, 0.12, 9.81);
    let t_expected = 0.5 * (j1 + m2 / 2.0 * l1 * l1) * rates[0] * rates[0]
        + 0.5 * (m2 / 2.0 + m3) * rates[3] * rates[3];
    let pi_expected = m1 * g * (a1 * state[0].cos() + h) + m2 / 2.0 * g * (l1 * state[0].cos() + h);
    // Rounding differs only in the order of operations: a few ulps of values of order 1.
    assert!((eval(a, m.kinetic, &env).unwrap() - t_expected).abs() < 1e-14);
    assert!((eval(a, m.potential, &env).unwrap() - pi_expected).abs() < 1e-14);
}

#[test]
fn seed_parses_from_text() {
    let m = parse_model_str(SEED).unwrap();
    check_seed(&m);
}

#[test]
fn seed_parses_from_tokens() {
    let tokens = proc_macro2::TokenStream::from_str(SEED).unwrap();
    let m = parse_model(tokens).unwrap();
    check_seed(&m);
}

#[test]
fn seed_locations_point_at_the_declared_names() {
    let m = parse_model_str(SEED).unwrap();
    // `phi` in `coordinates { phi = 0.0; ...` is on line 9 (the text starts with a newline).
    let phi = &m.coordinates[0].location;
    assert_eq!((phi.line, phi.column), (9, 19));
    let h = &m.parameters[0].location;
    assert_eq!((h.line, h.column), (5, 9));
    assert_eq!(m.constraints[1].location.line, 15);
}

#[test]
fn token_route_spans_map_locations_to_tokens() {
    let tokens = proc_macro2::TokenStream::from_str(SEED).unwrap();
    let parsed = mechanism_codegen::parse_declaration(tokens).unwrap();
    let (m, spans) = (&parsed.model, &parsed.spans);
    // Outside a proc-macro, spans know their line and column: each recorded location is the
    // start of the span it maps to.
    let check = |loc: mechanism_codegen::Location| {
        let s = spans.span(loc).start();
        assert_eq!((s.line, s.column + 1), (loc.line, loc.column));
    };
    for c in &m.coordinates {
        check(c.location);
    }
    for p in &m.parameters {
        check(p.location);
    }
    for c in &m.constraints {
        check(c.location);
    }
    check(spans.kinetic);
    check(spans.constraints.unwrap());
    assert_eq!(spans.constraints.unwrap().line, 13);
    assert_eq!(
        spans.force_entries.iter().filter(|f| f.is_some()).count(),
        1
    );
    assert!(spans.force_entries[0].is_some(), "the force acts on phi");
}
