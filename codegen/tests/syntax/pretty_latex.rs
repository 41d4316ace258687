//! LaTeX of expressions and matrices: one line per case, text => LaTeX.

use mechanism_codegen::internals::{matrix_to_latex, to_latex};
use mechanism_codegen::{
    Arena, Matrix, SymbolKind, derive, equations_latex, parse_expr, parse_model_str,
};

fn arena() -> Arena {
    let mut a = Arena::new();
    for s in ["x", "y", "a", "b", "c"] {
        a.symbol(s, SymbolKind::Free);
    }
    for s in ["Omega", "x_c", "l1", "tau0", "m2", "J1", "Dx"] {
        a.symbol(s, SymbolKind::Parameter);
    }
    for q in ["phi", "beta", "gamma", "th1"] {
        a.coordinate(q);
    }
    a
}

macro_rules! latex {
    ($($name:ident: $text:expr => $latex:expr;)*) => {$(
        #[test]
        fn $name() {
            let mut a = arena();
            let e = parse_expr(&mut a, $text).unwrap();
            assert_eq!(to_latex(&a, e), $latex, "{}", $text);
        }
    )*};
}

latex! {
    greek_upper: "Omega" => r"\Omega";
    greek_lower: "phi + beta + gamma" => r"\phi + \beta + \gamma";
    underscore_subscript: "x_c" => r"x_{c}";
    digit_subscript: "l1 + J1" => r"l_{1} + J_{1}";
    greek_with_digit: "tau0" => r"\tau_{0}";
    word_with_digit: "th1" => r"\mathrm{th}_{1}";
    word: "Dx" => r"\mathrm{Dx}";
    rate_is_dot: "der(phi)" => r"\dot{\phi}";
    acceleration_is_ddot: "der2(gamma)" => r"\ddot{\gamma}";
    fraction: "a/(b*c)" => r"\frac{a}{b c}";
    coefficient_fraction: "m2/2*l1^2" => r"\frac{m_{2} l_{1}^{2}}{2}";
    rational: "3/4" => r"\frac{3}{4}";
    sqrt: "sqrt(a + b)" => r"\sqrt{a + b}";
    inverse_sqrt: "1/sqrt(a)" => r"\frac{1}{\sqrt{a}}";
    sin_squared: "sin(phi)^2" => r"\sin^{2}{\left(\phi\right)}";
    exp: "exp(-x)" => r"e^{-x}";
    abs: "abs(x)" => r"\left|x\right|";
    ln: "ln(x)" => r"\ln{\left(x\right)}";
    atan2: "atan2(y, x)" => r"\operatorname{atan2}\left(y, x\right)";
    sum_in_product: "a*(b + c)*x" => r"x a \left(b + c\right)";
    negative_terms_last: "-a + b" => r"b - a";
    power_of_sum: "(a + b)^3" => r"\left(a + b\right)^{3}";
    pi: "2*pi*t" => r"2 \pi t";
    float: "0.04*x" => r"0.04 x";
    float_exponent: "1e-9*x" => r"10^{-9} x";
    float_mantissa: "2.5e-9*x" => r"2.5 \cdot 10^{-9} x";
}

#[test]
fn matrix_is_a_bmatrix() {
    let mut a = arena();
    let e = parse_expr(&mut a, "der(phi)^2").unwrap();
    let z = a.int(0);
    let m = Matrix::new(2, 2, vec![e, z, z, e]).unwrap();
    assert_eq!(
        matrix_to_latex(&a, &m),
        "\\begin{bmatrix}\n\\dot{\\phi}^{2} & 0 \\\\\n0 & \\dot{\\phi}^{2}\n\\end{bmatrix}"
    );
}

#[test]
fn seed_equations_latex() {
    let mut m = parse_model_str(crate::parse_support::SEED).unwrap();
    let eqs = derive(&mut m).unwrap();
    let tex = equations_latex(&m, &eqs);
    assert!(
        tex.contains(r"\[ q = \begin{bmatrix} \phi & \beta & \gamma & x_{c} \end{bmatrix}^T \]"),
        "{tex}"
    );
    for name in [
        "M",
        "C",
        r"C \dot{q}",
        "g",
        r"\tau",
        r"\Phi",
        r"\Phi_q",
        r"\Phi_t",
        r"\gamma",
    ] {
        assert!(
            tex.contains(&format!("\\[ {name} = \\begin{{bmatrix}}")),
            "{name} missing:\n{tex}"
        );
    }
    assert!(tex.contains(r"\[ \Pi = "), "{tex}");
    // M[1,1] = J1 + m2 l1^2 / 2 as the first entry of the mass matrix.
    assert!(
        tex.contains(
            "\\[ M = \\begin{bmatrix}\nJ_{1} + \\frac{m_{2} l_{1}^{2}}{2} & 0 & 0 & 0 \\\\\n"
        ),
        "{tex}"
    );
    // Braces balance.
    let depth = tex.chars().try_fold(0i64, |d, c| match c {
        '{' => Some(d + 1),
        '}' => (d > 0).then(|| d - 1),
        _ => Some(d),
    });
    assert_eq!(depth, Some(0));
}
