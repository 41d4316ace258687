//! The expansion of a floating-base declaration (a root link with `joint = floating(..)`):
//! the same parameter struct and cache as any mechanism, the inherent `NQ` and `NV`, and
//! `impl FloatingBase<NQ, NV>` instead of `impl Mechanism<N, M>` (why: the runtime's
//! `system/floating.rs`). The bodies come from `mechanism_codegen::compile_floating`'s
//! routines, q read in the configuration's layout (NQ entries), v, a and the efforts in
//! the velocities' (NV).

use mechanism_codegen::Role;
use proc_macro2::TokenStream;
use quote::quote;

use crate::ast::Declaration;
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
    frame_placements: Vec<TokenStream>,
    frame_jacobians: Vec<TokenStream>,
    frame_names: Vec<String>,
}

/// Derives, compiles and expands a floating-base declaration.
pub fn expand(decl: &mut Declaration) -> syn::Result<TokenStream> {
    let eqs = mechanism_codegen::derive(&mut decl.model).map_err(|e| codegen_error(decl, &e))?;
    let routines = mechanism_codegen::compile_floating(&mut decl.model, &eqs)
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

/// `impl FloatingBase<NQ, NV>`.
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
    let indices: Vec<usize> = (0..*p).collect();
    let sv = quote!(#krate::__private::SVector);
    let sm = quote!(#krate::__private::SMatrix);
    let FloatingBodies {
        mass_matrix,
        coriolis_forces,
        gravity,
        generalized_forces,
        kinetic_energy,
        potential_energy,
        mass_and_bias,
        bias,
        inverse_dynamics,
        forward_dynamics,
        frame_placements,
        frame_jacobians,
        frame_names,
    } = b;
    let frames: Vec<usize> = (0..frame_names.len()).collect();
    let allows = method_allows();
    quote! {
        #allows
        impl #krate::FloatingBase<#nq, #nv> for #name {
            const NAME: &'static str = #name_str;
            const CONFIGURATION: [&'static str; #nq] = [#(#configuration),*];
            const VELOCITIES: [&'static str; #nv] = [#(#coordinate_names),*];
            const PARAMETERS: &'static [&'static str] = &[#(#parameter_names),*];
            const NEUTRAL: [f64; #nq] = [#(#neutral),*];
            const FRAMES: &'static [&'static str] = &[#(#frame_names),*];

            fn parameter(&self, index: usize) -> ::core::option::Option<f64> {
                match index {
                    #(#indices => ::core::option::Option::Some(self.__parameters.#fields),)*
                    _ => ::core::option::Option::None,
                }
            }
            fn set_parameter(&mut self, index: usize, value: f64) -> bool {
                match index {
                    #(#indices => {
                        self.__parameters.#fields = value;
                        #name::refresh(self);
                        true
                    })*
                    _ => false,
                }
            }
            fn mass_matrix(&self, q: &#sv<f64, #nq>) -> #sm<f64, #nv, #nv> {
                #mass_matrix
            }
            fn coriolis_forces(&self, q: &#sv<f64, #nq>, qd: &#sv<f64, #nv>) -> #sv<f64, #nv> {
                #coriolis_forces
            }
            fn gravity(&self, q: &#sv<f64, #nq>) -> #sv<f64, #nv> {
                #gravity
            }
            fn generalized_forces(
                &self,
                t: f64,
                q: &#sv<f64, #nq>,
                qd: &#sv<f64, #nv>,
            ) -> #sv<f64, #nv> {
                #generalized_forces
            }
            fn kinetic_energy(&self, q: &#sv<f64, #nq>, qd: &#sv<f64, #nv>) -> f64 {
                #kinetic_energy
            }
            fn potential_energy(&self, q: &#sv<f64, #nq>) -> f64 {
                #potential_energy
            }
            fn mass_and_bias(
                &self,
                t: f64,
                q: &#sv<f64, #nq>,
                qd: &#sv<f64, #nv>,
            ) -> (#sm<f64, #nv, #nv>, #sv<f64, #nv>) {
                #mass_and_bias
            }
            fn bias(&self, t: f64, q: &#sv<f64, #nq>, qd: &#sv<f64, #nv>) -> #sv<f64, #nv> {
                #bias
            }
            fn inverse_dynamics(
                &self,
                t: f64,
                q: &#sv<f64, #nq>,
                qd: &#sv<f64, #nv>,
                qdd: &#sv<f64, #nv>,
            ) -> #sv<f64, #nv> {
                #inverse_dynamics
            }
            fn forward_dynamics(
                &self,
                t: f64,
                q: &#sv<f64, #nq>,
                qd: &#sv<f64, #nv>,
                effort: &#sv<f64, #nv>,
            ) -> ::core::option::Option<#sv<f64, #nv>> {
                #forward_dynamics
            }
            fn frame_placement(
                &self,
                frame: usize,
                q: &#sv<f64, #nq>,
            ) -> ::core::option::Option<(#sm<f64, 3, 3>, #sv<f64, 3>)> {
                match frame {
                    #(#frames => ::core::option::Option::Some({ #frame_placements }),)*
                    _ => ::core::option::Option::None,
                }
            }
            fn frame_jacobian(
                &self,
                frame: usize,
                q: &#sv<f64, #nq>,
            ) -> ::core::option::Option<#sm<f64, 6, #nv>> {
                match frame {
                    #(#frames => ::core::option::Option::Some({ #frame_jacobians }),)*
                    _ => ::core::option::Option::None,
                }
            }
        }
    }
}
