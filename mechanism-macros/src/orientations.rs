//! The bodies' declared orientation products as the constant `ORIENTATIONS` of the
//! emitted `impl Mechanism` (the runtime names a singularity of orientation angles by them).

use proc_macro2::TokenStream;
use quote::quote;

use crate::ast::Declaration;

/// `ORIENTATIONS`: each body's declared orientation product, factor by factor (nothing
/// without bodies, where the trait's default, empty, stands).
pub fn orientation_constants(decl: &Declaration) -> TokenStream {
    let rotations = &decl.model.rotations;
    if rotations.is_empty() {
        return quote!();
    }
    let krate = &decl.krate;
    let option = |v: Option<usize>| match v {
        Some(v) => quote!(::core::option::Option::Some(#v)),
        None => quote!(::core::option::Option::None),
    };
    let entries = rotations.iter().map(|r| {
        let body = &r.body;
        let factors = r.factors.iter().map(|&(axis, coordinate)| {
            let (axis, coordinate) = (option(axis), option(coordinate));
            quote!(#krate::RotationFactor { axis: #axis, coordinate: #coordinate })
        });
        quote!((#body, &[#(#factors),*]))
    });
    quote! {
        const ORIENTATIONS: &'static [(&'static str, &'static [#krate::RotationFactor])] =
            &[#(#entries),*];
    }
}
