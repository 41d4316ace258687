//! Table tests of the lowering rules: each expression, emitted as a returned value with
//! x, y, z read as `x`, `y`, `z`, gives exactly this code (whitespace ignored), and these
//! op counts (adds, muls, divs, calls).

use mechanism_codegen::{
    Arena, EmitBindings, Func, Id, Matrix, OutputTarget, Program, SymbolKind, emit_body,
};
use quote::format_ident;

struct Xyz {
    a: Arena,
    x: Id,
    y: Id,
    z: Id,
}

fn xyz() -> Xyz {
    let mut a = Arena::new();
    let x = a.symbol("x", SymbolKind::Free);
    let y = a.symbol("y", SymbolKind::Free);
    let z = a.symbol("z", SymbolKind::Free);
    Xyz { a, x, y, z }
}

/// The emitted returned body and its (adds, muls, divs, calls).
fn lower(s: &Xyz, e: Id) -> (String, [usize; 4]) {
    lower_with(s, e, None)
}

/// [`lower`], calling the real functions of the module `math` when given.
fn lower_with(s: &Xyz, e: Id, math: Option<proc_macro2::TokenStream>) -> (String, [usize; 4]) {
    let p = Program::new(&s.a, &[&Matrix::column(vec![e])]).unwrap();
    let mut b = EmitBindings::new();
    if let Some(m) = math {
        b.set_math(m);
    }
    for (sym, name) in p.symbols() {
        let id = format_ident!("{}", name);
        b.bind(*sym, quote::quote!(#id));
    }
    let body = emit_body(&p, &b, &[OutputTarget::Return]).unwrap();
    let c = body.counts;
    let text: String = body
        .tokens
        .to_string()
        .chars()
        .filter(|c| !c.is_whitespace())
        .collect();
    (text, [c.adds, c.muls, c.divs, c.calls])
}

macro_rules! lowering {
    ($($name:ident: |$s:ident| $build:expr => $code:expr, $counts:expr;)*) => {$(
        #[test]
        fn $name() {
            let mut $s = xyz();
            let e: Id = $build;
            let (got, counts) = lower(&$s, e);
            let want: String = $code.chars().filter(|c: &char| !c.is_whitespace()).collect();
            assert_eq!(got, want);
            assert_eq!(counts, $counts, "op counts (adds, muls, divs, calls)");
        }
    )*};
}

lowering! {
    square_is_a_product: |s| s.a.powi(s.x, 2).unwrap() => "x * x", [0, 1, 0, 0];
    cube_is_a_chain: |s| s.a.powi(s.x, 3).unwrap() => "let x0: f64 = x * x; x0 * x", [0, 2, 0, 0];
    fourth_power_squares_the_square: |s| s.a.powi(s.x, 4).unwrap() => "let x0: f64 = x * x; x0 * x0", [0, 2, 0, 0];
    large_power_is_powi: |s| s.a.powi(s.x, 7).unwrap() => "x.powi(7)", [0, 0, 0, 1];
    reciprocal_is_a_division: |s| s.a.powi(s.x, -1).unwrap() => "1.0_f64 / x", [0, 0, 1, 0];
    negative_power_divides_by_the_power: |s| s.a.powi(s.x, -2).unwrap() => "let x0: f64 = x * x; 1.0_f64 / x0", [0, 1, 1, 0];
    sqrt_is_sqrt: |s| s.a.sqrt(s.x).unwrap() => "x.sqrt()", [0, 0, 0, 1];
    three_halves: |s| { let h = s.a.rational(3, 2).unwrap(); s.a.pow(s.x, h).unwrap() }
        => "let x0: f64 = x.sqrt(); x * x0", [0, 1, 0, 1];
    reciprocal_sqrt: |s| { let h = s.a.rational(-1, 2).unwrap(); s.a.pow(s.x, h).unwrap() }
        => "let x0: f64 = x.sqrt(); 1.0_f64 / x0", [0, 0, 1, 1];
    real_power_is_powf: |s| { let h = s.a.rational(1, 3).unwrap(); s.a.pow(s.x, h).unwrap() }
        => "x.powf(0.3333333333333333_f64)", [0, 0, 0, 1];
    symbolic_power_is_powf: |s| s.a.pow(s.x, s.y).unwrap() => "x.powf(y)", [0, 0, 0, 1];
    difference_subtracts: |s| s.a.sub(s.x, s.y) => "x - y", [1, 0, 0, 0];
    scaled_difference: |s| { let two = s.a.int(2); let ty = s.a.mul2(two, s.y); s.a.sub(s.x, ty) }
        => "x - 2.0_f64 * y", [1, 1, 0, 0];
    negative_product_is_negation: |s| { let p = s.a.mul2(s.x, s.y); s.a.neg(p) }
        => "let x0: f64 = x * y; -x0", [1, 1, 0, 0];
    all_negative_sum: |s| { let t = s.a.add2(s.x, s.y); s.a.neg(t) }
        => "let x0: f64 = -x; x0 - y", [2, 0, 0, 0];
    constant_minus_symbol: |s| { let one = s.a.int(1); s.a.sub(one, s.x) } => "1.0_f64 - x", [1, 0, 0, 0];
    symbol_minus_constant: |s| { let one = s.a.int(1); s.a.sub(s.x, one) } => "x - 1.0_f64", [1, 0, 0, 0];
    quotient_has_one_division: |s| {
        let yz = s.a.mul2(s.y, s.z);
        s.a.div(s.x, yz).unwrap()
    } => "let x0: f64 = y * z; x / x0", [0, 1, 1, 0];
    mixed_quotient: |s| {
        let xy = s.a.mul2(s.x, s.y);
        let z2 = s.a.powi(s.z, 2).unwrap();
        s.a.div(xy, z2).unwrap()
    } => "let x0: f64 = x * y; let x1: f64 = z * z; x0 / x1", [0, 2, 1, 0];
    coefficient_applies_last: |s| {
        let h = s.a.rational(1, 2).unwrap();
        s.a.mul(&[h, s.x, s.y])
    } => "let x0: f64 = x * y; 0.5_f64 * x0", [0, 2, 0, 0];
    division_by_a_constant_multiplies: |s| { let three = s.a.int(3); s.a.div(s.x, three).unwrap() }
        => "0.3333333333333333_f64 * x", [0, 1, 0, 0];
    pi_is_a_named_constant: |s| { let pi = s.a.pi(); s.a.mul2(pi, s.x) }
        => "::core::f64::consts::PI * x", [0, 1, 0, 0];
    constant_factors_fold: |s| { let pi = s.a.pi(); let two = s.a.int(2); s.a.mul(&[two, pi, s.x]) }
        => "::core::f64::consts::TAU * x", [0, 1, 0, 0];
    negative_constant_receiver: |s| { let m1 = s.a.int(-1); s.a.atan2(m1, s.x) }
        => "(-1.0_f64).atan2(x)", [0, 0, 0, 1];
    atan2_keeps_its_order: |s| s.a.atan2(s.y, s.x) => "y.atan2(x)", [0, 0, 0, 1];
    sin_and_cos_pair: |s| { let a = s.a.sin(s.x); let b = s.a.cos(s.x); s.a.add2(a, b) }
        => "let (x0, x1): (f64, f64) = x.sin_cos(); x0 + x1", [1, 0, 0, 1];
    lone_sin_is_sin: |s| { let a = s.a.sin(s.x); s.a.mul2(a, s.y) } => "let x0: f64 = x.sin(); y * x0", [0, 1, 0, 1];
    tan_with_its_pair: |s| {
        let a = s.a.sin(s.x);
        let b = s.a.cos(s.x);
        let t = s.a.func(Func::Tan, s.x).unwrap();
        s.a.add(&[a, b, t])
    } => "let (x0, x1): (f64, f64) = x.sin_cos(); let x2: f64 = x0 + x1; let x3: f64 = x0 / x1; x2 + x3", [2, 0, 1, 1];
    other_calls: |s| {
        let e = s.a.func(Func::Exp, s.x).unwrap();
        let l = s.a.func(Func::Ln, s.y).unwrap();
        let b = s.a.func(Func::Abs, s.z).unwrap();
        s.a.mul(&[e, l, b])
    } => "let x0: f64 = x.exp(); let x1: f64 = y.ln(); let x2: f64 = x0 * x1; let x3: f64 = z.abs(); x2 * x3", [0, 2, 0, 3];
    shared_square_in_a_sum: |s| {
        let x2 = s.a.powi(s.x, 2).unwrap();
        let x3 = s.a.powi(s.x, 3).unwrap();
        s.a.add2(x2, x3)
    } => "let x0: f64 = x * x; x0 * x + x0", [1, 2, 0, 0];
}

/// With a math module, a product used by one sum alone is one `mul_add` call (fused where
/// the target has the instruction); its sign moves onto an operand.
#[test]
fn fused_multiply_add_calls_the_math_module() {
    let mut s = xyz();
    let xy = s.a.mul2(s.x, s.y);
    let sum = s.a.add2(xy, s.z);
    let difference = s.a.sub(s.z, xy);
    for (e, want) in [
        (sum, "m::mul_add(x,y,z)"),
        (difference, "m::mul_add(-x,y,z)"),
    ] {
        let (text, counts) = lower_with(&s, e, Some(quote::quote!(m)));
        assert_eq!(text, want);
        assert_eq!(counts, [1, 1, 0, 0]);
    }
}
