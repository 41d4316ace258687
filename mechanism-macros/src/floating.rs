//! The expansion of a floating-base declaration (a root link with `joint = floating(..)`):
//! the same parameter struct and cache as any mechanism, the inherent `NQ` and `NV`, and
//! `impl FloatingBase<NQ, NV>` instead of `impl Mechanism<N, M>` (why: the runtime's
//! `system/floating.rs`). The bodies come from `mechanism_codegen::compile_floating`'s
//! routines, q read in the configuration's layout (NQ entries), v, a and the efforts in
//! the velocities' (NV), and `inverse_dynamics_derivatives` from
//! `compile_floating_with_derivatives` (by the tangent of the configuration manifold). The neutral configuration takes the joints' declared guesses (the
//! inherent `initial_values` gives them at other parameters).

use mechanism_codegen::Role;
use proc_macro2::TokenStream;
use quote::quote;

use crate::ast::Declaration;
use crate::dispatch::{self, Method};
use crate::expand::{Tables, expand_struct, method_allows};
use crate::generate::{Bodies, Generated, codegen_error};

/// The method bodies of a floating-base type.
struct FloatingBodies {
    mass_matrix: TokenStream,
    coriolis_forces: TokenStream,
    gravity: TokenStream,
    generalized_forces: TokenStream,
    kinetic_energy: TokenStream,
    potential_energy: TokenStream,
    mass_and_bias: TokenStream,
    bias: TokenStream,
    inverse_dynamics: TokenStream,
    forward_dynamics: TokenStream,
    /// `(dtau/dq, dtau/dv)`; `None` past the derivative programs' cap.
    inverse_dynamics_derivatives: Option<TokenStream>,
    frame_placements: Vec<TokenStream>,
    frame_jacobians: Vec<TokenStream>,
    frame_names: Vec<String>,
}

/// Derives, compiles and expands a floating-base declaration.
pub fn expand(decl: &mut Declaration) -> syn::Result<TokenStream> {
    let eqs = mechanism_codegen::derive(&mut decl.model).map_err(|e| codegen_error(decl, &e))?;
    let routines = mechanism_codegen::compile_floating_with_derivatives(&mut decl.model, &eqs)
        .map_err(|e| codegen_error(decl, &e))?;
    let b = Bodies {
        model: &decl.model,
        krate: &decl.krate,
        routines: &routines,
    };
    let nv = eqs.n;
    let frames = eqs.frames.len();
    let result = (|| -> mechanism_codegen::Result<(FloatingBodies, Generated)> {
        let forward = b.forward_dynamics(nv)?.unwrap_or_default();
        let bodies = FloatingBodies {
            mass_matrix: b.matrix(Role::Mass)?,
            coriolis_forces: b.matrix(Role::CoriolisForces)?,
            gravity: b.matrix(Role::Gravity)?,
            generalized_forces: b.matrix(Role::Forces)?,
            kinetic_energy: b.scalar(Role::Kinetic)?,
            potential_energy: b.scalar(Role::Potential)?,
            mass_and_bias: b.mass_and_bias(nv)?,
            bias: b.matrix(Role::Bias)?,
            inverse_dynamics: b.inverse_dynamics()?,
            forward_dynamics: forward,
            inverse_dynamics_derivatives: b.inverse_dynamics_derivatives(nv)?,
            frame_placements: (0..frames)
                .map(|k| b.placement(Role::FramePlacement(k)))
                .collect::<mechanism_codegen::Result<_>>()?,
            frame_jacobians: (0..frames)
                .map(|k| b.matrix(Role::FrameJacobian(k)))
                .collect::<mechanism_codegen::Result<_>>()?,
            frame_names: eqs.frames.iter().map(|f| f.name.clone()).collect(),
        };
        let generated = Generated {
            cache_len: routines.cache_len(),
            cache: b.cache()?,
            initial_values: b.initial_values()?,
            routines: routines.fingerprint(),
            ..Default::default()
        };
        Ok((bodies, generated))
    })();
    let (bodies, generated) = result.map_err(|e| codegen_error(decl, &e))?;
    let t = Tables::of(decl);
    let parameter_struct = expand_struct(decl, &t, &generated);
    let constants = constants(decl, &t);
    let trait_impl = trait_impl(decl, &t, &bodies);
    Ok(quote! {
        #parameter_struct
        #constants
        #trait_impl
    })
}

/// The names of q's entries: the root's configuration, then each joint's coordinate.
fn configuration_names(decl: &Declaration) -> Vec<String> {
    let model = &decl.model;
    let Some(root) = model.floating_root() else {
        return Vec::new();
    };
    let arena = &model.arena;
    let mut names: Vec<String> = (root.configuration.iter())
        .filter_map(|&c| arena.as_symbol(c))
        .map(|s| arena.symbol_info(s).name.clone())
        .collect();
    let joints = (model.coordinates.iter().enumerate())
        .filter(|(i, _)| model.configuration_index(*i).is_some())
        .map(|(_, c)| c.name.clone());
    names.extend(joints);
    names
}

/// The inherent `NQ`, `NV` and the fingerprint of the routines.
fn constants(decl: &Declaration, t: &Tables) -> TokenStream {
    let name = &t.name;
    let nv = t.n;
    let nq = decl.model.configuration_size();
    quote! {
        #[allow(dead_code)]
        impl #name {
            /// The size of q: 7 for the root (position, quaternion) plus the joints.
            pub const NQ: usize = #nq;
            /// The size of v: 6 for the root (velocity, angular velocity) plus the joints.
            pub const NV: usize = #nv;
        }
    }
}

/// The dispatched methods (`crate::dispatch`: each body generic over the instruction set,
/// with its AVX2 copy) of a floating-base type, q of `nq` entries and v of `nv`.
fn methods(krate: &TokenStream, nq: usize, nv: usize, b: &FloatingBodies) -> Vec<Method> {
    let sv = |n: usize| quote!(#krate::__private::SVector<f64, #n>);
    let sm = |r: usize, c: usize| quote!(#krate::__private::SMatrix<f64, #r, #c>);
    let (svq, svv, smv) = (sv(nq), sv(nv), sm(nv, nv));
    let (sv3, sm3, sm6) = (sv(3), sm(3, 3), sm(6, nv));
    let t = ("t", quote!(f64));
    let q = ("q", quote!(&#svq));
    let qd = ("qd", quote!(&#svv));
    let frame = ("frame", quote!(usize));
    let frames: Vec<usize> = (0..b.frame_names.len()).collect();
    let (placements, jacobians) = (&b.frame_placements, &b.frame_jacobians);
    let tq = || [t.clone(), q.clone(), qd.clone()];
    let mut methods = vec![
        Method::new(
            "mass_matrix",
            std::slice::from_ref(&q),
            quote!(-> #smv),
            b.mass_matrix.clone(),
        ),
        Method::new(
            "coriolis_forces",
            &[q.clone(), qd.clone()],
            quote!(-> #svv),
            b.coriolis_forces.clone(),
        ),
        Method::new(
            "gravity",
            std::slice::from_ref(&q),
            quote!(-> #svv),
            b.gravity.clone(),
        ),
        Method::new(
            "generalized_forces",
            &tq(),
            quote!(-> #svv),
            b.generalized_forces.clone(),
        ),
        Method::new(
            "kinetic_energy",
            &[q.clone(), qd.clone()],
            quote!(-> f64),
            b.kinetic_energy.clone(),
        ),
        Method::new(
            "potential_energy",
            std::slice::from_ref(&q),
            quote!(-> f64),
            b.potential_energy.clone(),
        ),
        Method::new(
            "mass_and_bias",
            &tq(),
            quote!(-> (#smv, #svv)),
            b.mass_and_bias.clone(),
        ),
        Method::new("bias", &tq(), quote!(-> #svv), b.bias.clone()),
        Method::new(
            "inverse_dynamics",
            &[t.clone(), q.clone(), qd.clone(), ("qdd", quote!(&#svv))],
            quote!(-> #svv),
            b.inverse_dynamics.clone(),
        ),
        Method::new(
            "forward_dynamics",
            &[t.clone(), q.clone(), qd.clone(), ("effort", quote!(&#svv))],
            quote!(-> ::core::option::Option<#svv>),
            b.forward_dynamics.clone(),
        ),
        Method::new(
            "frame_placement",
            &[frame.clone(), q.clone()],
            quote!(-> ::core::option::Option<(#sm3, #sv3)>),
            quote! {
                match frame {
                    #(#frames => ::core::option::Option::Some({ #placements }),)*
                    _ => ::core::option::Option::None,
                }
            },
        ),
        Method::new(
            "frame_jacobian",
            &[frame, q],
            quote!(-> ::core::option::Option<#sm6>),
            quote! {
                match frame {
                    #(#frames => ::core::option::Option::Some({ #jacobians }),)*
                    _ => ::core::option::Option::None,
                }
            },
        ),
    ];
    methods.extend(derivatives(krate, nq, nv, b));
    methods
}

/// `inverse_dynamics_derivatives` (dtau/dq by the manifold's tangent, dtau/dv), unless its
/// program is past the cap.
fn derivatives(krate: &TokenStream, nq: usize, nv: usize, b: &FloatingBodies) -> Option<Method> {
    let body = b.inverse_dynamics_derivatives.as_ref()?;
    let (svq, svv) = (
        quote!(#krate::__private::SVector<f64, #nq>),
        quote!(#krate::__private::SVector<f64, #nv>),
    );
    let smv = quote!(#krate::__private::SMatrix<f64, #nv, #nv>);
    Some(Method::new(
        "inverse_dynamics_derivatives",
        &[
            ("t", quote!(f64)),
            ("q", quote!(&#svq)),
            ("qd", quote!(&#svv)),
            ("qdd", quote!(&#svv)),
        ],
        quote!(-> (#smv, #smv)),
        body.clone(),
    ))
}

/// `impl FloatingBase<NQ, NV>` and the inherent functions behind its methods.
fn trait_impl(decl: &Declaration, t: &Tables, b: &FloatingBodies) -> TokenStream {
    let krate = &decl.krate;
    let name_str = &decl.model.name;
    let Tables {
        name,
        n: nv,
        p,
        fields,
        parameter_names,
        coordinate_names,
        guesses,
        ranges,
        ..
    } = t;
    let nq = decl.model.configuration_size();
    let configuration = configuration_names(decl);
    let one = mechanism_codegen::f64_tokens(1.0);
    let zero = mechanism_codegen::f64_tokens(0.0);
    let neutral = [&zero, &zero, &zero, &zero, &zero, &zero, &one]
        .into_iter()
        .cloned()
        .chain(guesses.iter().skip(6).cloned());
    let parameter_methods = crate::expand::parameter_methods(
        krate,
        &quote!(#krate::FloatingBase<#nq, #nv>),
        *p,
        fields,
    );
    let frame_names = &b.frame_names;
    let dispatched = methods(krate, nq, *nv, b);
    let bodies = dispatch::bodies(krate, &dispatched);
    let trait_methods = dispatch::trait_methods(krate, &dispatched);
    let allows = method_allows();
    quote! {
        #allows
        impl #name {
            #bodies
        }
        #allows
        impl #krate::FloatingBase<#nq, #nv> for #name {
            const NAME: &'static str = #name_str;
            const CONFIGURATION: [&'static str; #nq] = [#(#configuration),*];
            const VELOCITIES: [&'static str; #nv] = [#(#coordinate_names),*];
            const PARAMETERS: &'static [&'static str] = &[#(#parameter_names),*];
            const NEUTRAL: [f64; #nq] = [#(#neutral),*];
            const FRAMES: &'static [&'static str] = &[#(#frame_names),*];
            const PARAMETER_RANGES: &'static [#krate::ParameterRange] = &[#(#ranges),*];

            #parameter_methods
            #trait_methods
        }
    }
}
