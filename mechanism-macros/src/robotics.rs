//! The robotics methods of the emitted `impl Mechanism`: the bias with M in one program and
//! alone, the inverse dynamics, the forward dynamics (for a mechanism without constraint
//! rows), and the placement and Jacobian of each link frame (a `match` on
//! the frame's index, one straight-line arm per frame). A new method here is one more
//! [`Method`], compiled for the CPU's instruction set like the others
//! ([`crate::dispatch`]).

use proc_macro2::TokenStream;
use quote::quote;

use crate::dispatch::Method;
use crate::generate::Generated;

/// `mass_and_bias`, `bias`, `inverse_dynamics`, `forward_dynamics` (where its routine is
/// compiled), `frame_placement` and `frame_jacobian` (the frames' names, `FRAMES`, are a
/// constant of the impl).
pub fn methods(krate: &TokenStream, n: usize, m: usize, g: &Generated) -> Vec<Method> {
    let sv = |k: usize| quote!(#krate::__private::SVector<f64, #k>);
    let sm = |r: usize, c: usize| quote!(#krate::__private::SMatrix<f64, #r, #c>);
    let Generated {
        mass_and_bias,
        bias,
        inverse_dynamics,
        forward_dynamics,
        constrained_dynamics,
        frame_placements,
        frame_jacobians,
        frame_names,
        ..
    } = g;
    let indices: Vec<usize> = (0..frame_names.len()).collect();
    let (svn, smn, sv3, sm3, sm6) = (sv(n), sm(n, n), sv(3), sm(3, 3), sm(6, n));
    let (t, q, qd) = (
        ("t", quote!(f64)),
        ("q", quote!(&#svn)),
        ("qd", quote!(&#svn)),
    );
    let frame = ("frame", quote!(usize));
    let mut methods = vec![
        Method::new(
            "mass_and_bias",
            &[t.clone(), q.clone(), qd.clone()],
            quote!(-> (#smn, #svn)),
            mass_and_bias.clone(),
        ),
        Method::new(
            "bias",
            &[t.clone(), q.clone(), qd.clone()],
            quote!(-> #svn),
            bias.clone(),
        ),
        Method::new(
            "inverse_dynamics",
            &[t.clone(), q.clone(), qd.clone(), ("qdd", quote!(&#svn))],
            quote!(-> #svn),
            inverse_dynamics.clone(),
        ),
        Method::new(
            "frame_placement",
            &[frame.clone(), q.clone()],
            quote!(-> ::core::option::Option<(#sm3, #sv3)>),
            quote! {
                match frame {
                    #(#indices => ::core::option::Option::Some({ #frame_placements }),)*
                    _ => ::core::option::Option::None,
                }
            },
        ),
        Method::new(
            "frame_jacobian",
            &[frame, q.clone()],
            quote!(-> ::core::option::Option<#sm6>),
            quote! {
                match frame {
                    #(#indices => ::core::option::Option::Some({ #frame_jacobians }),)*
                    _ => ::core::option::Option::None,
                }
            },
        ),
    ];
    if let Some(body) = forward_dynamics {
        methods.push(Method::new(
            "forward_dynamics",
            &[t.clone(), q.clone(), qd.clone(), ("effort", quote!(&#svn))],
            quote!(-> ::core::option::Option<#svn>),
            body.clone(),
        ));
    }
    if let Some(body) = constrained_dynamics {
        let solution = quote!(#krate::__private::KktSolution<#n, #m>);
        methods.push(Method::new(
            "constrained_dynamics",
            &[t, q, qd],
            quote!(-> ::core::result::Result<#solution, #krate::__private::FixedError>),
            body.clone(),
        ));
    }
    methods
}
