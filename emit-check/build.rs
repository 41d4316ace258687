//! Emits the random expressions of `src/random.rs` as Rust functions into OUT_DIR:
//! - `P::e{k}`: expression k returned as a scalar;
//! - `P::m{k}`: expressions 6k..6k+6 as a 2 x 3 nalgebra matrix (zero entries not written);
//! - `P::all`: all matrices at once, into `&mut [SMatrix; n]`, sharing sin_cos and
//!   subexpressions;
//!
//! with `x0 -> q[0]`, `x1 -> q[1]`, `k -> self.k`, `t -> t`, and sines and cosines by
//! `mechanism_math::sin_cos` (as the interpreter computes them). Also writes
//! `exprs.txt` (the expressions as text, one a line) and `op_counts.txt` (ops per emitted
//! function).

#[path = "src/random.rs"]
#[allow(dead_code)]
mod random;

use std::fmt::Write as _;
use std::path::PathBuf;

use mechanism_codegen::{EmitBindings, Matrix, OutputTarget, Program, emit_body, to_text};
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};

fn bindings(a: &mechanism_codegen::Arena) -> EmitBindings {
    let mut b = EmitBindings::new();
    b.set_math(quote!(::mechanism_math));
    let reads = [quote!(q[0]), quote!(q[1]), quote!(self.k), quote!(t)];
    for (name, read) in random::SYMBOLS.iter().zip(reads) {
        if let Some(s) = a.lookup(name) {
            b.bind(s, read);
        }
    }
    b
}

/// `let _ = ...;` for parameters the body does not read (no unused-variable warnings).
fn unused(p: &Program, a: &mechanism_codegen::Arena) -> TokenStream {
    let used = |n: &str| p.symbols().iter().any(|(s, _)| Some(*s) == a.lookup(n));
    let mut t = TokenStream::new();
    if !used("x0") && !used("x1") {
        t.extend(quote!(let _ = q;));
    }
    if !used("t") {
        t.extend(quote!(let _ = t;));
    }
    t
}

fn main() {
    println!("cargo::rerun-if-changed=build.rs");
    println!("cargo::rerun-if-changed=src/random.rs");
    let (mut a, ids) = random::generate();
    let mats = random::matrices(&mut a, &ids);
    let b = bindings(&a);
    let mut items = TokenStream::new();
    let mut counts = String::new();
    let mut text = String::new();
    for (k, &id) in ids.iter().enumerate() {
        writeln!(text, "{}", to_text(&a, id)).unwrap();
        let p = Program::new(&a, &[&Matrix::column(vec![id])]).expect("program");
        let body = emit_body(&p, &b, &[OutputTarget::Return]).expect("emit");
        let name = format_ident!("e{}", k);
        let stub = unused(&p, &a);
        let tokens = body.tokens;
        items.extend(quote! {
            /// Expression k, returned.
            pub fn #name(&self, q: &SVector<f64, 2>, t: f64) -> f64 { #stub #tokens }
        });
        writeln!(counts, "e{k} {}", body.counts).unwrap();
    }
    for (k, m) in mats.iter().enumerate() {
        let p = Program::new(&a, &[m]).expect("program");
        let name = format_ident!("m{}", k);
        let stub = unused(&p, &a);
        let all_zero = p.outputs()[0]
            .entries
            .iter()
            .all(|e| *e == mechanism_codegen::Operand::Const(0.0));
        let fn_body = if all_zero {
            quote!(#stub SMatrix::zeros())
        } else {
            let body = emit_body(
                &p,
                &b,
                &[OutputTarget::Matrix {
                    name: quote!(out),
                    zeroed: true,
                }],
            )
            .expect("emit");
            writeln!(counts, "m{k} {}", body.counts).unwrap();
            let tokens = body.tokens;
            quote! {
                #stub
                let mut out = SMatrix::<f64, 2, 3>::zeros();
                #tokens
                out
            }
        };
        items.extend(quote! {
            /// Expressions 6k..6k+6 as a matrix.
            pub fn #name(&self, q: &SVector<f64, 2>, t: f64) -> SMatrix<f64, 2, 3> { #fn_body }
        });
    }
    let refs: Vec<&Matrix> = mats.iter().collect();
    let p = Program::new(&a, &refs).expect("program");
    let targets: Vec<OutputTarget> = (0..mats.len())
        .map(|k| {
            let k = Literal::usize_unsuffixed(k);
            OutputTarget::Matrix {
                name: quote!(out[#k]),
                zeroed: false,
            }
        })
        .collect();
    let body = emit_body(&p, &b, &targets).expect("emit");
    writeln!(counts, "all {}", body.counts).unwrap();
    // How many groups of sines and cosines `all` computes side by side (emit's lanes).
    let lanes = body.tokens.to_string().matches("sin_cos_lanes").count();
    writeln!(counts, "all-lanes {lanes}").unwrap();
    let separate: usize = (0..mats.len())
        .map(|k| p.output_op_counts(k).map_or(0, |c| c.total()))
        .sum();
    writeln!(counts, "all-separately {separate}").unwrap();
    let tokens = body.tokens;
    let nm = mats.len();
    let ne = ids.len();
    let es: Vec<_> = (0..ids.len()).map(|k| format_ident!("e{}", k)).collect();
    let ms: Vec<_> = (0..mats.len()).map(|k| format_ident!("m{}", k)).collect();
    let file = quote! {
        use ::nalgebra::{SMatrix, SVector};

        /// The parameter holder: `k` is read as `self.k`.
        #[derive(Clone, Copy, Debug)]
        pub struct P {
            /// The parameter k.
            pub k: f64,
        }

        impl P {
            #items

            /// All matrices at once.
            pub fn all(&self, q: &SVector<f64, 2>, t: f64, out: &mut [SMatrix<f64, 2, 3>; #nm]) { #tokens }
        }

        /// A scalar function.
        pub type Scalar = fn(&P, &SVector<f64, 2>, f64) -> f64;
        /// A matrix function.
        pub type MatrixFn = fn(&P, &SVector<f64, 2>, f64) -> SMatrix<f64, 2, 3>;
        /// `P::e{k}`, by k.
        pub const SCALARS: [Scalar; #ne] = [#(P::#es),*];
        /// `P::m{k}`, by k.
        pub const MATRICES: [MatrixFn; #nm] = [#(P::#ms),*];
    };
    let out = PathBuf::from(std::env::var_os("OUT_DIR").expect("OUT_DIR"));
    std::fs::write(out.join("generated.rs"), file.to_string()).expect("write");
    std::fs::write(out.join("exprs.txt"), text).expect("write");
    std::fs::write(out.join("op_counts.txt"), counts).expect("write");
}
