//! The robotics methods of the emitted `impl Mechanism`: the bias with M in one program,
//! the inverse dynamics, and the placement and Jacobian of each link frame (a `match` on
//! the frame's index, one straight-line arm per frame).

use proc_macro2::TokenStream;
use quote::quote;

use crate::generate::Generated;

/// `FRAMES`, `mass_and_bias`, `inverse_dynamics`, `frame_placement` and `frame_jacobian`.
pub fn methods(krate: &TokenStream, n: usize, g: &Generated) -> TokenStream {
    let sv = quote!(#krate::__private::SVector);
    let sm = quote!(#krate::__private::SMatrix);
    let Generated {
        mass_and_bias,
        inverse_dynamics,
        frame_placements,
        frame_jacobians,
        frame_names,
        ..
    } = g;
    let indices: Vec<usize> = (0..frame_names.len()).collect();
    quote! {
        const FRAMES: &'static [&'static str] = &[#(#frame_names),*];
        fn mass_and_bias(
            &self,
            t: f64,
            q: &#sv<f64, #n>,
            qd: &#sv<f64, #n>,
        ) -> (#sm<f64, #n, #n>, #sv<f64, #n>) {
            #mass_and_bias
        }
        fn inverse_dynamics(
            &self,
            t: f64,
            q: &#sv<f64, #n>,
            qd: &#sv<f64, #n>,
            qdd: &#sv<f64, #n>,
        ) -> #sv<f64, #n> {
            #inverse_dynamics
        }
        fn frame_placement(
            &self,
            frame: usize,
            q: &#sv<f64, #n>,
        ) -> ::core::option::Option<(#sm<f64, 3, 3>, #sv<f64, 3>)> {
            match frame {
                #(#indices => ::core::option::Option::Some({ #frame_placements }),)*
                _ => ::core::option::Option::None,
            }
        }
        fn frame_jacobian(
            &self,
            frame: usize,
            q: &#sv<f64, #n>,
        ) -> ::core::option::Option<#sm<f64, 6, #n>> {
            match frame {
                #(#indices => ::core::option::Option::Some({ #frame_jacobians }),)*
                _ => ::core::option::Option::None,
            }
        }
    }
}
