//! Declaration-level errors: each rule fires with a message a mechanical engineer reads, at
//! the offending token (line and column), and all errors are reported at once.

use std::str::FromStr;

use mechanism_codegen::error::DeclarationError;
use mechanism_codegen::{Error, parse_declaration, parse_declaration_str, parse_model_str};

/// A declaration, one section per line (line 1: struct, 2: parameters, 3: coordinates,
/// 4: independent, 5: kinetic, 6: potential, 7: constraints, 8: forces). `None` omits a
/// section.
#[derive(Clone, Copy)]
struct D {
    parameters: Option<&'static str>,
    coordinates: Option<&'static str>,
    independent: Option<&'static str>,
    kinetic: Option<&'static str>,
    potential: Option<&'static str>,
    constraints: Option<&'static str>,
    forces: Option<&'static str>,
}

/// A point mass on a rod in Cartesian coordinates: n = 2, m = 1, one independent coordinate.
const BASE: D = D {
    parameters: Some("m = 1.0; l = 0.5; g = 9.81;"),
    coordinates: Some("x = 0.5; y = 0.0;"),
    independent: Some("x = 0.5; der(x) = 0.0;"),
    kinetic: Some("m/2*(der(x)^2 + der(y)^2)"),
    potential: Some("m*g*y"),
    constraints: Some("x^2 + y^2 - l^2;"),
    forces: Some(""),
};

impl D {
    fn text(&self) -> String {
        let line = |kw: &str, body: Option<&str>, block: bool| match body {
            None => String::new(),
            Some(b) if block => format!("{kw} {{ {b} }}"),
            Some(b) => format!("{kw} = {b};"),
        };
        [
            "pub struct S;".to_string(),
            line("parameters", self.parameters, true),
            line("coordinates", self.coordinates, true),
            line("independent", self.independent, true),
            line("kinetic", self.kinetic, false),
            line("potential", self.potential, false),
            line("constraints", self.constraints, true),
            line("forces", self.forces, true),
        ]
        .join("\n")
    }
}

fn location(e: &Error) -> (usize, usize) {
    let l = e
        .location()
        .unwrap_or_else(|| panic!("no location in {e:?}"));
    (l.line, l.column)
}

/// Expects an error containing `fragment` at (`line`, the column of `needle` in that line).
fn expect(d: D, fragment: &str, line: usize, needle: &str) {
    let text = d.text();
    let errors = parse_declaration_str(&text).expect_err(&text);
    let hit = errors.iter().find(|e| e.to_string().contains(fragment));
    let Some(e) = hit else {
        panic!("no error containing {fragment:?} in:\n{text}\nerrors: {errors:#?}");
    };
    let src_line = text.lines().nth(line - 1).unwrap();
    let column = src_line
        .find(needle)
        .unwrap_or_else(|| panic!("{needle:?} not in {src_line:?}"))
        + 1;
    assert_eq!(location(e), (line, column), "{e}\n{text}");
}

macro_rules! errors {
    ($($name:ident: $d:expr => $fragment:expr, line $line:expr, at $needle:expr;)*) => {$(
        #[test]
        fn $name() {
            expect($d, $fragment, $line, $needle);
        }
    )*};
}

errors! {
    unknown_symbol: D { kinetic: Some("m/2*(der(x)^2 + der(y)^2) + k"), ..BASE }
        => "unknown symbol `k`", line 5, at "k;";
    unknown_symbol_suggests: D { potential: Some("m*gg*y"), ..BASE }
        => "unknown symbol `gg`; did you mean `g`?", line 6, at "gg";
    duplicate_coordinate: D { coordinates: Some("x = 0.5; y = 0.0; x = 1.0;"), ..BASE }
        => "the coordinate `x` is declared twice", line 3, at "x = 1.0";
    duplicate_parameter: D { parameters: Some("m = 1.0; l = 0.5; g = 9.81; m = 2.0;"), ..BASE }
        => "the parameter `m` is declared twice", line 2, at "m = 2.0";
    parameter_named_like_coordinate: D { parameters: Some("m = 1.0; l = 0.5; g = 9.81; x = 1.0;"), ..BASE }
        => "`x` is declared both as a parameter", line 3, at "x = 0.5";
    parameter_named_t: D { parameters: Some("m = 1.0; l = 0.5; g = 9.81; t = 1.0;"), ..BASE }
        => "a parameter cannot be called `t`", line 2, at "t = 1.0";
    coordinate_named_pi: D { coordinates: Some("x = 0.5; y = 0.0; pi = 1.0;"), constraints: Some("x^2 + y^2 - l^2; x - y;"), ..BASE }
        => "a coordinate cannot be called `pi`", line 3, at "pi";
    rate_in_potential: D { potential: Some("m*g*y + der(x)"), ..BASE }
        => "the potential energy may depend on the coordinates and t only; `der(x)` appears in it", line 6, at "der(x)";
    rate_in_constraint: D { constraints: Some("x^2 + y^2 - l^2; der(x) - y;"), ..BASE }
        => "constraints must be holonomic: der(x) appears in constraint 2", line 7, at "der(x)";
    der_of_parameter: D { kinetic: Some("m/2*(der(x)^2 + der(m)^2)"), ..BASE }
        => "der() takes a coordinate; `m` is a parameter", line 5, at "m)^2";
    der_of_time: D { kinetic: Some("m/2*(der(x)^2 + der(y)^2) + der(t)"), ..BASE }
        => "der() takes a coordinate; `t` is time", line 5, at "t);";
    der_of_expression: D { kinetic: Some("m/2*(der(x)^2 + der(x + y)^2)"), ..BASE }
        => "der() takes the name of a coordinate", line 5, at "der(x + y)";
    acceleration: D { forces: Some("x: der2(x);"), ..BASE }
        => "accelerations cannot appear in a declaration", line 8, at "der2";
    empty_coordinates: D { coordinates: Some(""), ..BASE }
        => "`coordinates` is empty", line 3, at "coordinates";
    no_coordinates: D { coordinates: None, independent: None, constraints: None, kinetic: Some("m"), potential: None, ..BASE }
        => "`S` declares no coordinates", line 1, at "S;";
    force_on_unknown_coordinate: D { forces: Some("z: 1.0;"), ..BASE }
        => "a force acts along a coordinate, but `z` is not declared (the coordinates are x, y)", line 8, at "z:";
    force_on_parameter: D { forces: Some("l: 1.0;"), ..BASE }
        => "but `l` is a parameter", line 8, at "l:";
    force_twice: D { forces: Some("x: 1.0; x: 2.0;"), ..BASE }
        => "two forces on `x`", line 8, at "x: 2.0";
    independent_on_unknown_coordinate: D { independent: Some("x = 0.5; der(w) = 0.0;"), ..BASE }
        => "`w` is not declared", line 4, at "w)";
    independent_twice: D { independent: Some("x = 0.5; x = 0.6;"), ..BASE }
        => "`x` is set twice in `independent`", line 4, at "x = 0.6";
    default_uses_coordinate: D { parameters: Some("m = 1.0; l = 0.5*x; g = 9.81;"), ..BASE }
        => "a parameter default must be a constant; `x` is a coordinate", line 2, at "x;";
    default_uses_time: D { parameters: Some("m = 1.0 + t; l = 0.5; g = 9.81;"), ..BASE }
        => "a parameter default must be a constant; `t` is time", line 2, at "t;";
    default_uses_rate: D { parameters: Some("m = der(x); l = 0.5; g = 9.81;"), ..BASE }
        => "a parameter default must be a constant; `der(x)` is a rate", line 2, at "der";
    default_uses_later_parameter: D { parameters: Some("m = l; l = 0.5; g = 9.81;"), ..BASE }
        => "`l` is declared later", line 2, at "l;";
    default_uses_itself: D { parameters: Some("m = 2*m; l = 0.5; g = 9.81;"), ..BASE }
        => "the default of `m` refers to `m` itself", line 2, at "m;";
    guess_uses_coordinate: D { coordinates: Some("x = 0.5; y = x;"), ..BASE }
        => "an initial value must be a constant; `x` is a coordinate", line 3, at "x;";
    missing_kinetic: D { kinetic: None, ..BASE }
        => "`S` declares no kinetic energy", line 1, at "S;";
    too_few_independent: D { independent: Some(""), ..BASE }
        => "n - m = 2 - 1 = 1 degree of freedom but `independent` sets 0 (none); set 1 more of x, y", line 4, at "independent";
    no_independent_section: D { independent: None, ..BASE }
        => "set 1 more of x, y", line 1, at "S;";
    division_by_zero_default: D { parameters: Some("m = 1.0/(2-2); l = 0.5; g = 9.81;"), ..BASE }
        => "division by zero", line 2, at "/";
    unknown_function: D { kinetic: Some("m/2*(der(x)^2 + der(y)^2)*sine(x)"), ..BASE }
        => "unknown function `sine`", line 5, at "sine";
    parse_error: D { kinetic: Some("m/2 * * der(x)^2"), ..BASE }
        => "parse error", line 5, at "* der";
    constant_constraint: D { constraints: Some("x^2 + y^2 - l^2 + 0*x; l - 2*l + l;"), coordinates: Some("x = 0.5; y = 0.0; z = 1.0;"), kinetic: Some("m/2*(der(x)^2 + der(y)^2 + der(z)^2)"), ..BASE }
        => "constraint 2 does not depend on the coordinates or t (it simplifies to `0`)", line 7, at "l - 2*l";
    kinetic_without_rates: D { kinetic: Some("m*x^2"), ..BASE }
        => "the kinetic energy does not depend on any rate der(q) (it is `m*x^2`)", line 5, at "kinetic";
    vector_length_mismatch: D { constraints: Some("[x, y] = [l, 0, 1];"), ..BASE }
        => "differ in length: 2 on the left, 3 on the right", line 7, at "=";
    // A missing `;` after the last statement of a block, at the `}` where it was expected.
    missing_semicolon_parameters: D { parameters: Some("m = 1.0; l = 0.5; g = 9.81"), ..BASE }
        => "expected `;` after the last statement of the block, found `}`", line 2, at "}";
    missing_semicolon_coordinates: D { coordinates: Some("x = 0.5; y = 0.0"), ..BASE }
        => "expected `;` after the last statement", line 3, at "}";
    missing_semicolon_independent: D { independent: Some("x = 0.5; der(x) = 0.0"), ..BASE }
        => "expected `;` after the last statement", line 4, at "}";
    missing_semicolon_constraints: D { constraints: Some("x^2 + y^2 - l^2"), ..BASE }
        => "expected `;` after the last statement", line 7, at "}";
    missing_semicolon_vector_constraint: D { constraints: Some("[x, y] = [l, 0]"), ..BASE }
        => "expected `;` after the last statement", line 7, at "}";
    missing_semicolon_forces: D { forces: Some("x: 1.0"), ..BASE }
        => "expected `;` after the last statement", line 8, at "}";
    missing_semicolon_between_statements: D { constraints: Some("x^2 + y^2 - l^2 x - y;"), ..BASE }
        => "expected `;` or an operator, found `x`", line 7, at "x - y";
    unknown_symbol_lists_known_names: D { potential: Some("m*g*w"), ..BASE }
        => "unknown symbol `w`; known: m, l, g, x, y, t, pi (at line 6, column 17)", line 6, at "w";
}

/// The known names are listed closest first, at most eight of them.
#[test]
fn unknown_symbol_lists_the_closest_known_names_first() {
    let d = D {
        parameters: Some("m = 1.0; l = 0.5; g = 9.81; psi0 = 0.0; k1 = 1; k2 = 2; k3 = 3; k4 = 4;"),
        coordinates: Some("x = 0.5; y = 0.0; phi = 0.0;"),
        constraints: Some("x^2 + y^2 - l^2; phi - psi0;"),
        independent: Some("x = 0.5; der(x) = 0.0;"),
        potential: Some("m*g*y + phl"),
        ..BASE
    };
    let errors = parse_declaration_str(&d.text()).unwrap_err();
    let Error::Declaration { kind, .. } = &errors[0] else {
        panic!("{errors:?}")
    };
    let DeclarationError::UnknownSymbol {
        suggestion, known, ..
    } = kind.as_ref()
    else {
        panic!("{errors:?}")
    };
    assert_eq!(suggestion.as_deref(), Some("phi"));
    assert_eq!(
        known[..5],
        ["phi", "l", "pi", "m", "g"],
        "phi (1 edit), then l and pi (2), then the rest in declaration order"
    );
    assert_eq!(known.len(), 13, "every declared name, t and pi");
    assert_eq!(
        errors[0].message(),
        "unknown symbol `phl`; did you mean `phi`? known: phi, l, pi, m, g, psi0, k1, k2, ..."
    );
}

#[test]
fn every_error_is_reported_at_once_in_source_order() {
    let d = D {
        coordinates: Some("x = 0.5; y = 0.0; x = 1.0;"),
        kinetic: Some("m/2*(der(x)^2 + der(y)^2) + k"),
        potential: Some("m*g*y + der(x)"),
        ..BASE
    };
    let errors = parse_declaration_str(&d.text()).unwrap_err();
    let lines: Vec<usize> = errors.iter().map(|e| location(e).0).collect();
    assert_eq!(lines, [3, 5, 6], "{errors:#?}");
}

#[test]
fn vector_constraint_expands_to_rows() {
    let d = D {
        coordinates: Some("x = 0.5; y = 0.0; z = 0.0;"),
        independent: Some("x = 0.5;"),
        constraints: Some("[x - l, y] = [0, z];"),
        ..BASE
    };
    let m = parse_model_str(&d.text()).unwrap();
    let rows: Vec<String> = m
        .constraints
        .iter()
        .map(|c| mechanism_codegen::to_text(&m.arena, c.expr))
        .collect();
    assert_eq!(rows, ["x - l", "y - z"]);
}

/// Redundant rows are legitimate (an overconstrained mechanism): m > n parses, and the
/// runtime reports the rank of Phi_q and the mobility.
#[test]
fn more_rows_than_coordinates_are_allowed() {
    let d = D {
        constraints: Some("x^2 + y^2 - l^2; 2*(x^2 + y^2 - l^2); x - y;"),
        ..BASE
    };
    let m = parse_model_str(&d.text()).unwrap();
    assert_eq!((m.coordinates.len(), m.constraints.len()), (2, 3));
}

/// Rows of `constraints { .. }` are labelled by statement (1-based), vector equations by
/// component.
#[test]
fn constraint_rows_are_labelled_by_statement_and_component() {
    let d = D {
        coordinates: Some("x = 0.5; y = 0.0; z = 0.0; w = 0.0;"),
        independent: Some("x = 0.5;"),
        constraints: Some("x^2 + y^2 - l^2; [x - l, y, w] = [0, z, 0]; [z, w] = [0, 0]; z = w;"),
        ..BASE
    };
    let m = parse_model_str(&d.text()).unwrap();
    let labels: Vec<(&str, &str)> = m
        .constraints
        .iter()
        .map(|c| (c.joint.as_str(), c.component.as_str()))
        .collect();
    assert_eq!(
        labels,
        [
            ("constraint 1", ""),
            ("constraint 2", "x"),
            ("constraint 2", "y"),
            ("constraint 2", "z"),
            ("constraint 3", "x"),
            ("constraint 3", "y"),
            ("constraint 4", ""),
        ]
    );
    let text: Vec<String> = m.constraints.iter().map(|c| c.label()).collect();
    assert_eq!(text[0], "constraint 1");
    assert_eq!(text[2], "constraint 2 y");
}

#[test]
fn sections_in_any_order_and_optional_ones() {
    let text =
        "struct Free; kinetic = der(x)^2/2; coordinates { x = 1.0; } independent { x = 2.0; }";
    let m = parse_model_str(text).unwrap();
    assert!(!m.public);
    assert!(m.arena.is_zero(m.potential), "potential defaults to 0");
    assert!(m.parameters.is_empty() && m.constraints.is_empty());
    assert_eq!(
        (m.independent[0].position, m.independent[0].velocity),
        (2.0, 0.0)
    );
    assert!(m.arena.is_zero(m.forces[0]));
}

#[test]
fn defaults_use_earlier_parameters_and_pi() {
    let d = D {
        parameters: Some("m = 1.0; l = 2*m/4; g = 9.81; w = 2*pi*sqrt(g/l);"),
        ..BASE
    };
    let m = parse_model_str(&d.text()).unwrap();
    let w = m.parameters.iter().find(|p| p.name == "w").unwrap().default;
    assert_eq!(w, 2.0 * std::f64::consts::PI * (9.81f64 / 0.5).sqrt());
}

#[test]
fn unbalanced_text_gives_line_and_column() {
    let text = "struct S;\ncoordinates { x = 0.0; }\nkinetic = (der(x)^2;\n";
    let errors = parse_declaration_str(text).unwrap_err();
    let e = &errors[0];
    assert!(matches!(e, Error::Parse { .. }), "{e:?}");
    assert_eq!(
        location(e),
        (3, 11),
        "at the bracket that is never closed: {e}"
    );
    assert!(
        e.to_string().contains("a bracket that is not closed"),
        "{e}"
    );
}

#[test]
fn unknown_section_suggests_the_keyword() {
    let text = "struct S;\ncoordinates { x = 0.0; }\nkinetik = der(x)^2;\n";
    let e = &parse_declaration_str(text).unwrap_err()[0];
    assert!(e.to_string().contains("did you mean `kinetic`?"), "{e}");
    assert_eq!(location(e), (3, 1));
}

#[test]
fn doc_attributes_other_than_doc_are_refused() {
    let text = "#[derive(Debug)] struct S; coordinates { x = 0.0; } kinetic = der(x)^2;";
    let e = &parse_declaration_str(text).unwrap_err()[0];
    assert!(e.to_string().contains("only doc comments"), "{e}");
}

#[test]
fn token_route_errors_carry_the_offending_span() {
    let d = D {
        potential: Some("m*gg*y"),
        ..BASE
    };
    let tokens = proc_macro2::TokenStream::from_str(&d.text()).unwrap();
    let errors = parse_declaration(tokens).unwrap_err();
    assert_eq!(errors.len(), 1);
    let e = &errors[0];
    let start = e.span.start();
    assert_eq!(
        (start.line, start.column + 1),
        location(&e.error),
        "the span is the token's"
    );
    assert_eq!(
        e.message(),
        "unknown symbol `gg`; did you mean `g`? known: g, m, l, x, y, t, pi"
    );
}

/// Errors are typed: the kind says which rule or which token, with its data.
#[test]
fn errors_carry_their_kind_and_data() {
    use mechanism_codegen::error::{
        CoordinatePlace, DeclarationError, Expected, NameKind, ParseError, SymbolRole,
    };
    let first = |d: D| parse_declaration_str(&d.text()).unwrap_err().remove(0);
    let rule = |d: D| match first(d) {
        Error::Declaration { kind, .. } => *kind,
        other => panic!("{other:?}"),
    };
    let grammar = |d: D| match first(d) {
        Error::Parse { kind, .. } => *kind,
        other => panic!("{other:?}"),
    };
    let forces = Some("x: 1.0; x: 2.0;");
    let kind = rule(D { forces, ..BASE });
    assert!(
        matches!(&kind, DeclarationError::TwoForces { name, first } if name == "x" && first.line == 8),
        "{kind:?}"
    );
    let coordinates = Some("x = 0.5; y = 0.0; x = 1.0;");
    let kind = rule(D {
        coordinates,
        ..BASE
    });
    assert!(
        matches!(
            kind,
            DeclarationError::DeclaredTwice {
                kind: NameKind::Coordinate,
                ..
            }
        ),
        "{kind:?}"
    );
    let kind = rule(D {
        forces: Some("l: 1.0;"),
        ..BASE
    });
    assert!(
        matches!(
            kind,
            DeclarationError::NotACoordinate {
                place: CoordinatePlace::Force,
                role: SymbolRole::Parameter,
                ..
            }
        ),
        "{kind:?}"
    );
    let constraints = Some("x^2 + y^2 - l^2");
    assert_eq!(
        grammar(D {
            constraints,
            ..BASE
        }),
        ParseError::Expected {
            expected: Expected::LastSemicolon,
            found: "`}`".into()
        }
    );
    let constraints = Some("[x, y] = [l, 0, 1];");
    assert_eq!(
        grammar(D {
            constraints,
            ..BASE
        }),
        ParseError::VectorLengths { left: 2, right: 3 }
    );
}
