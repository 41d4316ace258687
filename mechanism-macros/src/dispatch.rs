//! Every generated method compiled for two instruction sets, one mechanism for all of them:
//! a method's body is written once, in a generic inherent function over
//! `mechanism_math::Isa` (the value `isa` that computes its grouped sines and cosines), and
//! on an x86-64 build without AVX2 (the default target) a second function, compiled with
//! `#[target_feature(enable = "avx2")]`, runs that body handed an `Avx2` (a proof that the
//! CPU has it, made by run-time detection). The trait's method calls that one where the CPU
//! has AVX2 (one cached read per call) and the baseline copy elsewhere:
//!
//! ```text
//! fn mass_matrix(&self, q) -> M {                       // the trait's method
//!     if let Some(isa) = Avx2::detected() { return unsafe { self.__mass_matrix_avx2(isa, q) } }
//!     self.__mass_matrix(Baseline, q)
//! }
//! #[target_feature(enable = "avx2")] fn __mass_matrix_avx2(&self, isa: Avx2, q) -> M {
//!     self.__mass_matrix(isa, q)                         // inlined: compiled with AVX2
//! }
//! #[inline(always)] fn __mass_matrix<I: Isa>(&self, isa: I, q) -> M { /* the body */ }
//! ```
//!
//! The two copies give the same bits (the lanes compute each lane as `sin_cos` does, and
//! `avx2` enables no `fma`, so `math::mul_add` fuses in neither); the AVX copy gains the
//! three-operand encoding (fewer register copies) and four sines and cosines to a register.
//! rustc type-checks and borrow-checks the body once (it is one generic function); only
//! code generation sees it twice. Builds with AVX2 enabled (`-C target-cpu=native` on such
//! a CPU), other architectures and `no_std` x86-64 builds (where detection is never
//! claimed) have the baseline copy alone.

use proc_macro2::{Ident, Span, TokenStream};
use quote::{format_ident, quote};

/// One method of the `Mechanism` impl whose body comes from a routine.
pub struct Method {
    /// The trait method's name (`mass_matrix`).
    pub name: &'static str,
    /// Its parameters after `&self`, with their types (`q: &SVector<f64, 7>`).
    pub params: TokenStream,
    /// The same parameters as arguments (`q`).
    pub args: TokenStream,
    /// `-> Type`, or nothing.
    pub output: TokenStream,
    /// The body, generic: it may read `isa`, a `mechanism_math::Isa`.
    pub body: TokenStream,
}

impl Method {
    /// A method named `name` taking `params` (`name: Type` pairs after `&self`).
    pub fn new(
        name: &'static str,
        params: &[(&str, TokenStream)],
        output: TokenStream,
        body: TokenStream,
    ) -> Method {
        let names: Vec<Ident> = params
            .iter()
            .map(|(p, _)| Ident::new(p, Span::call_site()))
            .collect();
        let types = params.iter().map(|(_, t)| t);
        Method {
            name,
            params: quote!(#(#names: #types),*),
            args: quote!(#(#names),*),
            output,
            body,
        }
    }
}

/// The `cfg` under which a second copy compiled with AVX2 exists.
fn avx2_cfg() -> TokenStream {
    quote!(#[cfg(all(target_arch = "x86_64", not(target_feature = "avx2")))])
}

/// The inherent functions behind `methods` (each body generic over the instruction set, and
/// its copy compiled with AVX2), to go inside `impl Name { .. }`.
pub fn bodies(krate: &TokenStream, methods: &[Method]) -> TokenStream {
    let cfg = avx2_cfg();
    let mut out = TokenStream::new();
    for m in methods {
        let (generic, avx2) = names(m);
        let Method {
            params,
            args,
            output,
            body,
            ..
        } = m;
        out.extend(quote! {
            #[doc(hidden)]
            #[inline(always)]
            fn #generic<I: #krate::math::Isa>(&self, isa: I, #params) #output {
                #body
            }
            #cfg
            #[doc(hidden)]
            #[target_feature(enable = "avx2")]
            fn #avx2(&self, isa: #krate::math::avx2::Avx2, #params) #output {
                self.#generic(isa, #args)
            }
        });
    }
    out
}

/// The trait's methods: each picks the AVX2 copy where the CPU has it.
pub fn trait_methods(krate: &TokenStream, methods: &[Method]) -> TokenStream {
    let cfg = avx2_cfg();
    let mut out = TokenStream::new();
    for m in methods {
        let (generic, avx2) = names(m);
        let name = Ident::new(m.name, Span::call_site());
        let Method {
            params,
            args,
            output,
            ..
        } = m;
        out.extend(quote! {
            fn #name(&self, #params) #output {
                #cfg
                if let ::core::option::Option::Some(isa) = #krate::math::avx2::Avx2::detected() {
                    // SAFETY: the CPU has AVX2 (`isa` proves it), all that the copy needs
                    // beyond this build's features.
                    return unsafe { self.#avx2(isa, #args) };
                }
                self.#generic(#krate::math::Baseline, #args)
            }
        });
    }
    out
}

/// `__name` (the generic body) and `__name_avx2`.
fn names(m: &Method) -> (Ident, Ident) {
    (
        format_ident!("__{}", m.name),
        format_ident!("__{}_avx2", m.name),
    )
}
