//! Table tests of the expression parser and printer: text => printed form, text => error.

use mechanism_codegen::error::DeclarationError;
use mechanism_codegen::{Arena, Error, SymbolKind, parse_expr, to_text};

/// An arena with free symbols x, y, z, parameters a, b, c, m1, l1, m2 and a coordinate phi.
fn arena() -> Arena {
    let mut a = Arena::new();
    for s in ["x", "y", "z"] {
        a.symbol(s, SymbolKind::Free);
    }
    for s in ["a", "b", "c", "m1", "l1", "m2"] {
        a.symbol(s, SymbolKind::Parameter);
    }
    a.coordinate("phi");
    a
}

/// `text => printed`: parses, prints, and checks that the printed form reads back to the
/// same node.
macro_rules! prints {
    ($($name:ident: $text:expr => $printed:expr;)*) => {$(
        #[test]
        fn $name() {
            let mut a = arena();
            let e = parse_expr(&mut a, $text).unwrap_or_else(|err| panic!("{}: {err}", $text));
            let p = to_text(&a, e);
            assert_eq!(p, $printed, "printed form of {}", $text);
            let back = parse_expr(&mut a, &p).unwrap_or_else(|err| panic!("{p}: {err}"));
            assert_eq!(back, e, "{p} reads back to another node");
        }
    )*};
}

prints! {
    integer: "2" => "2";
    rational_stays_exact: "1/2" => "1/2";
    negative_rational: "-1/2" => "-1/2";
    float_decimal: "0.04" => "0.04";
    float_exponent: "1e-4" => "0.0001";
    float_tiny: "1e-9" => "1e-9";
    float_integral: "2.0" => "2.0";
    pow_tighter_than_unary_minus: "-x^2" => "-x^2";
    pow_tighter_than_mul: "a*b^2" => "a*b^2";
    pow_right_assoc: "2^3^2" => "512";
    pow_right_assoc_symbolic: "x^y^z" => "x^y^z";
    pow_of_pow_left: "(x^y)^z" => "(x^y)^z";
    pow_negative_exponent: "x^-1" => "1/x";
    pow_negative_exponent_two: "x^-2*y" => "y/x^2";
    half_times_x: "1/2*x" => "x/2";
    left_assoc_div: "a/b/c" => "a/(b*c)";
    div_then_mul: "a/b*c" => "a*c/b";
    coefficient_first: "x*3" => "3*x";
    mass_term: "m2/2*l1^2" => "m2*l1^2/2";
    positive_terms_first: "-x + y" => "y - x";
    all_negative: "-x - y" => "-x - y";
    sqrt_is_half_power: "x^(1/2)" => "sqrt(x)";
    sqrt_call: "sqrt(x*y)" => "sqrt(x*y)";
    inverse_sqrt: "1/sqrt(x)" => "1/sqrt(x)";
    three_halves: "x^(3/2)" => "x^(3/2)";
    pi_and_t: "2*pi*t" => "2*pi*t";
    der_is_rate: "der(phi)^2" => "der(phi)^2";
    der2_is_acceleration: "der2(phi)" => "der2(phi)";
    functions: "sin(x) + cos(y) + tan(z) + exp(x) + ln(y) + abs(z)" => "sin(x) + cos(y) + tan(z) + exp(x) + ln(y) + abs(z)";
    atan2_order: "atan2(y, x)" => "atan2(y, x)";
    pow_call: "pow(x, 3)" => "x^3";
    sin_odd: "sin(-x)" => "-sin(x)";
    cos_even: "cos(-x)" => "cos(x)";
    pythagoras: "a*sin(x)^2 + a*cos(x)^2" => "a";
    sum_in_product: "2*(a + b)*x" => "2*x*(a + b)";
    distribute_single_sum: "2*(a + b)" => "2*a + 2*b";
    sum_in_denominator: "a/(b + c)" => "a/(b + c)";
    negative_base: "(-x)^y" => "(-x)^y";
    rational_base: "(1/2)^x" => "(1/2)^x";
    symbolic_negative_exponent: "x^(-y)" => "1/x^y";
    float_coefficient: "0.5*x" => "0.5*x";
    float_negative_exponent: "x^-0.5" => "1/x^0.5";
    float_minus_one_exponent: "x^-1.0" => "x^(-1.0)";
    unary_plus: "+x" => "x";
    double_negation: "--x" => "x";
    constant_last: "1 + x" => "x + 1";
    negative_constant: "x - 1" => "x - 1";
    nested_funcs: "sin(cos(x)^2)" => "sin(cos(x)^2)";
    underscore_digits: "1_000" => "1000";
    // Regressions found by the round-trip proptest.
    float_minus_one_coefficient: "-1.0*sqrt(x)" => "-1.0*sqrt(x)";
    float_minus_one_term: "y + (-1.0)*sqrt(x)" => "y + (-1.0*sqrt(x))";
    number_and_sum_below_the_bar: "x/(-2)/(x + z)" => "-x/2/(x + z)";
    minus_before_a_sum_factor: "-1*(x + 1)*x^x" => "-1*(x + 1)*x^x";
    minus_sum_factor_in_sum: "-1*(x + 1)*x^x - 1" => "-1*(x + 1)*x^x - 1";
    unfoldable_power_stays: "(1/2)^(-1/1e-4)" => "(1/2)^(-10000.0)";
    overflowing_power_stays: "0.0016^(-125)" => "0.0016^(-125)";
}

/// The rule of the language an error reports, when it is a declaration error.
fn rule(err: &Error) -> Option<&DeclarationError> {
    match err {
        Error::Declaration { kind, .. } => Some(kind),
        _ => None,
    }
}

/// `text => (error, rule)`: the error and the declaration rule it reports, and its 1-based
/// column (all cases are one line).
macro_rules! fails {
    ($($name:ident: $text:expr => $kind:pat, $column:expr;)*) => {$(
        #[test]
        fn $name() {
            let mut a = arena();
            let err = parse_expr(&mut a, $text).expect_err($text);
            assert!(matches!((&err, rule(&err)), $kind), "{}: wrong error kind: {err:?}", $text);
            let loc = err
                .location()
                .unwrap_or_else(|| panic!("no location in {err:?}"));
            assert_eq!((loc.line, loc.column), (1, $column), "{}: {err}", $text);
        }
    )*};
}

fails! {
    unknown_symbol: "x + q" => (_, Some(DeclarationError::UnknownSymbol { .. })), 5;
    unknown_function: "x + sine(x)" => (_, Some(DeclarationError::UnknownFunction { .. })), 5;
    division_by_zero: "x/0" => (_, Some(DeclarationError::ZeroDivisor { .. })), 2;
    division_by_zero_constant_expr: "x/(2-2)" => (_, Some(DeclarationError::ZeroDivisor { .. })), 2;
    zero_to_negative_power: "y + 0^-1" => (_, Some(DeclarationError::ZeroDivisor { .. })), 6;
    der_of_parameter: "der(m1)" => (Error::Declaration { .. }, _), 5;
    der_of_expression: "der(x + y)" => (Error::Declaration { .. }, _), 5;
    dangling_operator: "x +" => (Error::Parse { .. }, _), 4;
    missing_operand: "x * * y" => (Error::Parse { .. }, _), 5;
    trailing_tokens: "x y" => (Error::Parse { .. }, _), 3;
    caret_without_base: "^x" => (Error::Parse { .. }, _), 1;
    wrong_arity: "atan2(x)" => (Error::Parse { .. }, _), 1;
    unbalanced: "sin(x" => (Error::Parse { .. }, _), 4;
    type_suffix: "2f64*x" => (Error::Parse { .. }, _), 1;
    string_literal: "\"x\"" => (Error::Parse { .. }, _), 1;
    ln_of_zero: "ln(0)" => (Error::Declaration { .. }, _), 1;
    huge_float: "1e999" => (Error::Parse { .. }, _), 1;
    double_star_power: "x**2" => (Error::Parse { .. }, _), 3;
}

#[test]
fn unknown_symbol_suggests_a_close_name() {
    let mut a = arena();
    let err = parse_expr(&mut a, "l2 + 1").unwrap_err();
    match rule(&err) {
        Some(DeclarationError::UnknownSymbol {
            name, suggestion, ..
        }) => {
            assert_eq!(name, "l2");
            assert_eq!(suggestion.as_deref(), Some("l1"));
        }
        other => panic!("{other:?}"),
    }
    assert!(err.to_string().contains("did you mean `l1`?"), "{err}");
    // No suggestion for a one-letter name: `w` is not a typo of `x`.
    let err = parse_expr(&mut a, "w").unwrap_err();
    assert!(
        matches!(
            rule(&err),
            Some(DeclarationError::UnknownSymbol {
                suggestion: None,
                ..
            })
        ),
        "{err:?}"
    );
}

#[test]
fn der_of_parameter_message_names_the_kind() {
    let mut a = arena();
    let err = parse_expr(&mut a, "der(m1)").unwrap_err();
    assert!(
        err.to_string()
            .contains("der() takes a coordinate; `m1` is a parameter"),
        "{err}"
    );
}

#[test]
fn multi_line_error_has_line_and_column() {
    let mut a = arena();
    let err = parse_expr(&mut a, "x +\n  y *\n   unknown").unwrap_err();
    assert!(
        matches!(rule(&err), Some(DeclarationError::UnknownSymbol { .. }))
            && err.location().map(|l| (l.line, l.column)) == Some((3, 4)),
        "{err:?}"
    );
    let err = parse_expr(&mut a, "(x +\n  (y * 2)").unwrap_err();
    assert!(
        matches!(err, Error::Parse { location, .. } if location.line >= 1),
        "{err:?}"
    );
}

#[test]
fn deep_nesting_is_an_error_not_a_stack_overflow() {
    let mut a = arena();
    let text = format!("{}x{}", "(".repeat(5000), ")".repeat(5000));
    assert!(matches!(
        parse_expr(&mut a, &text),
        Err(Error::Parse { .. })
    ));
    let text = format!("{}x", "-".repeat(5000));
    assert!(matches!(
        parse_expr(&mut a, &text),
        Err(Error::Parse { .. })
    ));
    // Moderate nesting is fine.
    let text = format!("{}x{}", "(".repeat(50), ")".repeat(50));
    assert!(parse_expr(&mut a, &text).is_ok());
}

#[test]
fn precedence_builds_the_intended_tree() {
    // Each pair must denote the same node in one arena.
    let pairs = [
        ("-x^2", "-(x^2)"),
        ("a*b^2", "a*(b^2)"),
        ("2^3^2", "2^9"),
        ("a - b - c", "(a - b) - c"),
        ("a/b/c", "(a/b)/c"),
        ("a/b*c", "(a/b)*c"),
        ("1/2*x", "(1/2)*x"),
        ("-a*b", "(-a)*b"),
        ("x^-y^2", "x^(-(y^2))"),
        ("2*pi", "pi*2"),
    ];
    let mut a = arena();
    for (l, r) in pairs {
        let el = parse_expr(&mut a, l).unwrap();
        let er = parse_expr(&mut a, r).unwrap();
        assert_eq!(el, er, "{l} vs {r}");
    }
    // And these differ.
    let x2 = parse_expr(&mut a, "(-x)^2").unwrap();
    let mx2 = parse_expr(&mut a, "-x^2").unwrap();
    assert_ne!(x2, mx2);
}
