//! The expansion: the parameter struct and the mechanism struct (the parameters and their
//! cached parameter-only values, read and written through `Deref`/`DerefMut`), their
//! `Default`, the inherent constants and the `impl ::mechanism::Mechanism<N, M>` (each
//! generated method's body in a generic inherent function, compiled a second time with AVX2
//! on x86-64 builds without it: [`crate::dispatch`]). `quote!` only; the bodies come from
//! [`crate::generate`].

use proc_macro2::{Span, TokenStream};
use quote::{format_ident, quote};
use syn::Ident;

use crate::ast::{Declaration, Source};
use crate::dispatch::{self, Method};
use crate::generate::{self, Generated};

/// Derives and expands one parsed and checked `mechanism!` declaration of a mechanism whose
/// q' is the rate of q (a floating base is [`crate::floating`]'s).
pub fn expand(decl: &mut Declaration) -> syn::Result<TokenStream> {
    let generated = generate::generate(decl)?;
    Ok(expand_declaration(decl, &generated))
}

/// An `f64` constant for the generated code: codegen's literal form, which names the
/// `core::f64::consts` values (`2*pi` is `TAU`) so that clippy's `approx_constant` stays
/// quiet in the user's crate. The checks reject non-finite defaults and guesses.
fn float(x: f64) -> TokenStream {
    mechanism_codegen::f64_tokens(x)
}

/// The tables of a declaration as the tokens that the expansion repeats.
pub(crate) struct Tables {
    pub(crate) name: Ident,
    pub(crate) n: usize,
    pub(crate) m: usize,
    pub(crate) p: usize,
    pub(crate) fields: Vec<Ident>,
    pub(crate) defaults: Vec<TokenStream>,
    pub(crate) field_docs: Vec<String>,
    pub(crate) parameter_names: Vec<String>,
    pub(crate) coordinate_names: Vec<String>,
    pub(crate) guesses: Vec<TokenStream>,
    pub(crate) independent: Vec<TokenStream>,
    /// The coordinate index of each independent entry.
    pub(crate) independent_coordinates: Vec<usize>,
    /// `Krate::ParameterRange::X` per parameter.
    pub(crate) ranges: Vec<TokenStream>,
    pub(crate) row_joints: Vec<String>,
    pub(crate) row_components: Vec<String>,
    pub(crate) velocity_rows: usize,
}

impl Tables {
    pub(crate) fn of(decl: &Declaration) -> Tables {
        let model = &decl.model;
        let krate = &decl.krate;
        let independent = model
            .independent
            .iter()
            .map(|s| {
                let k = s.coordinate;
                let position = float(s.position);
                let velocity = float(s.velocity);
                quote!(#krate::Independent { coordinate: #k, position: #position, velocity: #velocity })
            })
            .collect();
        // The position rows, then the velocity rows (the order of the stacked Phi_q).
        let rows = || model.constraints.iter().chain(&model.velocity_constraints);
        Tables {
            name: Ident::new(&model.name, Span::call_site()),
            n: model.coordinates.len(),
            m: model.constraints.len() + model.velocity_constraints.len(),
            velocity_rows: model.velocity_constraints.len(),
            p: model.parameters.len(),
            fields: (model.parameters.iter())
                .map(|p| Ident::new(&p.name, Span::call_site()))
                .collect(),
            defaults: model.parameters.iter().map(|p| float(p.default)).collect(),
            field_docs: (model.parameters.iter())
                .map(|p| format!(" Parameter `{}` (declared default {}).", p.name, p.default))
                .collect(),
            parameter_names: model.parameters.iter().map(|p| p.name.clone()).collect(),
            coordinate_names: model.coordinates.iter().map(|c| c.name.clone()).collect(),
            guesses: model.coordinates.iter().map(|c| float(c.guess)).collect(),
            independent,
            independent_coordinates: model.independent.iter().map(|s| s.coordinate).collect(),
            ranges: (model.parameters.iter())
                .map(|p| {
                    let range = match p.range {
                        mechanism_codegen::ParameterRange::Any => quote!(Any),
                        mechanism_codegen::ParameterRange::Positive => quote!(Positive),
                        mechanism_codegen::ParameterRange::NonNegative => quote!(NonNegative),
                    };
                    quote!(#krate::ParameterRange::#range)
                })
                .collect(),
            row_joints: rows().map(|c| c.joint.clone()).collect(),
            row_components: rows().map(|c| c.component.clone()).collect(),
        }
    }
}

/// The whole expansion: the struct and its `Default`, the inherent constants, the trait.
fn expand_declaration(decl: &Declaration, g: &Generated) -> TokenStream {
    let t = Tables::of(decl);
    let rebuild = match &decl.source {
        Source::File { path, .. } => {
            let path = path.display().to_string();
            quote!(
                const _: &str = ::core::include_str!(#path);
            )
        }
        Source::Inline => quote!(),
    };
    let parameter_struct = expand_struct(decl, &t, g);
    let constants = expand_constants(decl, &t, g);
    let trait_impl = expand_trait_impl(decl, &t, g);
    quote! {
        #rebuild
        #parameter_struct
        #constants
        #trait_impl
    }
}

/// The parameter struct (`<Name>Parameters`, one `pub f64` field per parameter) and its
/// `Default`, and the mechanism struct with the declaration's docs: the parameters, their
/// cached parameter-only values and whether the cache is current. `Deref` reads the
/// parameters (`model.l2`); `DerefMut` writes them (`model.l2 = 0.35`) and marks the cache
/// stale, so a body then computes the values itself until `refresh` (or `set_parameter`,
/// `new`, `Compiled::new`) stores them again: a stale value is never read.
pub(crate) fn expand_struct(decl: &Declaration, t: &Tables, g: &Generated) -> TokenStream {
    let vis = if decl.model.public {
        quote!(pub)
    } else {
        quote!()
    };
    let params = format_ident!("{}Parameters", t.name);
    let parameters = expand_parameters(t, &params, &vis);
    let mechanism = expand_mechanism(decl, t, g, &params, &vis);
    let cache = expand_cache_methods(t, g, &params);
    quote! {
        #parameters
        #mechanism
        #cache
    }
}

/// The parameter struct `<Name>Parameters` (one `pub f64` field per parameter) and its
/// `Default` (the declared values).
fn expand_parameters(t: &Tables, params: &Ident, vis: &TokenStream) -> TokenStream {
    let Tables {
        name,
        fields,
        defaults,
        field_docs,
        ..
    } = t;
    let params_doc =
        format!(" The parameters of [`{name}`], with their declared defaults in `Default`.");
    quote! {
        #[doc = #params_doc]
        #[derive(Clone, Debug, PartialEq)]
        #[allow(non_snake_case)]
        #vis struct #params {
            #(
                #[doc = #field_docs]
                pub #fields: f64,
            )*
        }

        // Declared values are the user's numbers: a guess such as 1.570796 is not pi/2.
        #[allow(clippy::approx_constant, clippy::excessive_precision)]
        impl ::core::default::Default for #params {
            fn default() -> Self {
                Self { #(#fields: #defaults,)* }
            }
        }

    }
}

/// The mechanism struct with the declaration's docs (the parameters, the cache and whether
/// it is current) and its `Default`, `From` the parameters, `Deref` and `DerefMut` to them
/// (marking the cache stale), `PartialEq` and `Debug`.
fn expand_mechanism(
    decl: &Declaration,
    t: &Tables,
    g: &Generated,
    params: &Ident,
    vis: &TokenStream,
) -> TokenStream {
    let Tables {
        name,
        n,
        m,
        p,
        fields,
        parameter_names,
        ..
    } = t;
    let k = g.cache_len;
    let name_str = name.to_string();
    let mut doc: Vec<String> = decl.model.doc.clone();
    if !doc.is_empty() {
        doc.push(String::new());
    }
    doc.push(format!(
        " Generated by `mechanism!`: {n} coordinates, {m} constraint rows, {p} parameters \
         (the fields of [`{params}`], read and written through this struct: \
         `model.{first} = ...`), {k} values that depend on parameters only, cached.",
        first = parameter_names.first().map_or("x", String::as_str),
    ));
    quote! {
        #(#[doc = #doc])*
        #[derive(Clone)]
        #vis struct #name {
            __parameters: #params,
            __cache: [f64; #k],
            __cached: bool,
        }

        impl ::core::default::Default for #name {
            fn default() -> Self {
                Self::new(::core::default::Default::default())
            }
        }

        impl ::core::convert::From<#params> for #name {
            fn from(parameters: #params) -> Self {
                Self::new(parameters)
            }
        }

        impl ::core::ops::Deref for #name {
            type Target = #params;
            fn deref(&self) -> &#params {
                &self.__parameters
            }
        }

        /// Marks the cached parameter-only values stale: the methods compute them anew at
        /// every call until `refresh` stores them again.
        impl ::core::ops::DerefMut for #name {
            fn deref_mut(&mut self) -> &mut #params {
                self.__cached = false;
                &mut self.__parameters
            }
        }

        /// Equal parameters (the cache follows from them).
        impl ::core::cmp::PartialEq for #name {
            fn eq(&self, other: &Self) -> bool {
                self.__parameters == other.__parameters
            }
        }

        impl ::core::fmt::Debug for #name {
            fn fmt(&self, f: &mut ::core::fmt::Formatter<'_>) -> ::core::fmt::Result {
                f.debug_struct(#name_str)
                    #(.field(#parameter_names, &self.__parameters.#fields))*
                    .finish()
            }
        }

    }
}

/// The mechanism's inherent `new`, `parameters`, `refresh`, `is_cached` and the private
/// `parameter_cache` (the values that depend on parameters only, in cache order).
fn expand_cache_methods(t: &Tables, g: &Generated, params: &Ident) -> TokenStream {
    let name = &t.name;
    let k = g.cache_len;
    let cache = &g.cache;
    let initial_values = &g.initial_values;
    let n = t.n;
    let k2 = 2 * t.independent.len();
    quote! {
        #[allow(
            dead_code,
            non_snake_case,
            unused_variables,
            unused_mut,
            clippy::approx_constant,
            clippy::excessive_precision,
            clippy::unreadable_literal,
            clippy::neg_multiply,
            clippy::double_neg,
            clippy::suboptimal_flops,
            clippy::identity_op,
            clippy::let_and_return
        )]
        impl #name {
            /// The mechanism with these parameters, its parameter-only values computed.
            pub fn new(parameters: #params) -> Self {
                let cache = Self::parameter_cache(&parameters);
                Self {
                    __parameters: parameters,
                    __cache: cache,
                    __cached: true,
                }
            }

            /// The parameters.
            pub fn parameters(&self) -> &#params {
                &self.__parameters
            }

            /// Stores the parameter-only values of the current parameters (after a change
            /// through `DerefMut`, `model.l2 = 0.35`, the methods compute them at every call
            /// until this is called).
            pub fn refresh(&mut self) {
                self.__cache = Self::parameter_cache(&self.__parameters);
                self.__cached = true;
            }

            /// Whether the stored parameter-only values are those of the current parameters.
            pub fn is_cached(&self) -> bool {
                self.__cached
            }

            /// The parameter-only values of `p`, in cache order.
            fn parameter_cache(p: &#params) -> [f64; #k] {
                #cache
            }

            /// The declared initial guesses, and the position and rate of each independent
            /// coordinate in turn, at the parameters `p` (the declared expressions, read
            /// from the parameters themselves, never from the cache).
            fn initial_values(p: &#params) -> ([f64; #n], [f64; #k2]) {
                #initial_values
            }
        }
    }
}

/// The inherent constants (`NAME`, `N`, `M`, names, defaults, guesses, rows) and
/// `equations()`.
fn expand_constants(decl: &Declaration, t: &Tables, g: &Generated) -> TokenStream {
    let krate = &decl.krate;
    let name_str = &decl.model.name;
    let Tables {
        name,
        n,
        m,
        p,
        defaults,
        ranges,
        parameter_names,
        coordinate_names,
        guesses,
        independent,
        row_joints,
        row_components,
        ..
    } = t;
    let k = independent.len();
    let equations = &g.equations;
    let routines = g.routines;
    let param_const = format_ident!("PARAMETERS");
    quote! {
        #[allow(dead_code, clippy::approx_constant, clippy::excessive_precision)]
        impl #name {
            /// Name of the mechanism.
            pub const NAME: &'static str = #name_str;
            /// Number of coordinates n.
            pub const N: usize = #n;
            /// Number of constraint rows m.
            pub const M: usize = #m;
            /// Coordinate names, in the order of q.
            pub const COORDINATES: [&'static str; #n] = [#(#coordinate_names),*];
            /// Parameter names, in declaration order (the struct's fields).
            pub const #param_const: [&'static str; #p] = [#(#parameter_names),*];
            /// Declared parameter defaults, in declaration order.
            pub const PARAMETER_DEFAULTS: [f64; #p] = [#(#defaults),*];
            /// Declared parameter ranges (`positive`, `nonnegative`), in declaration order.
            pub const PARAMETER_RANGES: [#krate::ParameterRange; #p] = [#(#ranges),*];
            /// Declared initial guesses for q, at the declared parameter defaults
            /// (`initial_guess()` gives them at the current values).
            pub const INITIAL_GUESS: [f64; #n] = [#(#guesses),*];
            /// The independent coordinates and their initial values, at the declared
            /// parameter defaults (`independent(k)` gives them at the current values).
            pub const INDEPENDENT: [#krate::Independent; #k] = [#(#independent),*];
            /// The joint and the component of each constraint row, in row order.
            pub const CONSTRAINT_ROWS: [(&'static str, &'static str); #m] =
                [#((#row_joints, #row_components)),*];
            /// The fingerprint of the compiled routines every method runs
            /// (`mechanism_codegen::Routines::fingerprint`), for the tests that hold the
            /// interpreter route to the same routines.
            #[doc(hidden)]
            pub const __ROUTINES: u64 = #routines;

            /// The derived equations as readable text.
            pub fn equations() -> &'static str {
                #equations
            }
        }
    }
}

/// `impl Mechanism<N, M>`: the constants, parameter access and the equation methods.
fn expand_trait_impl(decl: &Declaration, t: &Tables, g: &Generated) -> TokenStream {
    let krate = &decl.krate;
    let name_str = &decl.model.name;
    let Tables {
        name,
        n,
        m,
        p,
        fields,
        parameter_names,
        coordinate_names,
        guesses,
        independent,
        independent_coordinates,
        ranges,
        row_joints,
        row_components,
        velocity_rows,
        ..
    } = t;
    let parameter_methods =
        parameter_methods(krate, &quote!(#krate::Mechanism<#n, #m>), *p, fields);
    let entries: Vec<usize> = (0..independent.len()).collect();
    let dispatched = dispatched_methods(krate, *n, *m, g);
    let bodies = dispatch::bodies(krate, &dispatched);
    let methods = expand_equation_methods(decl, t, g, &dispatched);
    let drawing = drawing_constants(decl);
    let joint_limits = joint_limit_constants(decl);
    let orientations = crate::orientations::orientation_constants(decl);
    let allows = method_allows();
    quote! {
        #allows
        impl #name {
            #bodies
        }
        #allows
        impl #krate::Mechanism<#n, #m> for #name {
            const NAME: &'static str = #name_str;
            const COORDINATES: [&'static str; #n] = [#(#coordinate_names),*];
            const PARAMETERS: &'static [&'static str] = &[#(#parameter_names),*];
            const INITIAL_GUESS: [f64; #n] = [#(#guesses),*];
            const INDEPENDENT: &'static [#krate::Independent] = &[#(#independent),*];
            const PARAMETER_RANGES: &'static [#krate::ParameterRange] = &[#(#ranges),*];
            const CONSTRAINT_ROWS: &'static [(&'static str, &'static str)] =
                &[#((#row_joints, #row_components)),*];
            const VELOCITY_ROWS: usize = #velocity_rows;
            #drawing
            #joint_limits
            #orientations

            #parameter_methods
            fn initial_guess(&self) -> [f64; #n] {
                #name::initial_values(&self.__parameters).0
            }
            fn independent(&self, k: usize) -> ::core::option::Option<#krate::Independent> {
                let values = #name::initial_values(&self.__parameters).1;
                let coordinate = match k {
                    #(#entries => #independent_coordinates,)*
                    _ => return ::core::option::Option::None,
                };
                ::core::option::Option::Some(#krate::Independent {
                    coordinate,
                    position: *values.get(2 * k)?,
                    velocity: *values.get(2 * k + 1)?,
                })
            }
            fn refresh(&mut self) {
                #name::refresh(self);
            }
            #methods
        }
    }
}

/// The lints allowed on the impls of generated methods: their bodies are straight-line SSA
/// with many short names, long literals and unsimplified signs.
pub(crate) fn method_allows() -> TokenStream {
    quote! {
        #[allow(
            non_snake_case,
            unused_variables,
            unused_mut,
            clippy::approx_constant,
            clippy::excessive_precision,
            clippy::unreadable_literal,
            clippy::too_many_lines,
            clippy::many_single_char_names,
            clippy::similar_names,
            clippy::neg_multiply,
            clippy::double_neg,
            clippy::suboptimal_flops,
            clippy::unnecessary_cast,
            clippy::identity_op,
            clippy::let_and_return,
            clippy::redundant_locals,
            clippy::inline_always
        )]
    }
}

/// `DRAW_POINTS`, `DRAW_LINES` and `DRAW_TRACES` of the declared drawing (nothing without one:
/// the trait's defaults are empty).
fn drawing_constants(decl: &Declaration) -> TokenStream {
    let d = &decl.model.drawing;
    if d.points.is_empty() {
        return quote!();
    }
    let names = d.points.iter().map(|p| &p.name);
    let ground = d.points.iter().map(|p| p.ground);
    let lines = d.lines.iter().map(|l| quote!(&[#(#l),*]));
    let traces = &d.traces;
    quote! {
        const DRAW_POINTS: &'static [(&'static str, bool)] = &[#((#names, #ground)),*];
        const DRAW_LINES: &'static [&'static [usize]] = &[#(#lines),*];
        const DRAW_TRACES: &'static [usize] = &[#(#traces),*];
    }
}

/// `JOINT_LIMITS`: the link tree's declared joint limits (nothing without any).
fn joint_limit_constants(decl: &Declaration) -> TokenStream {
    let limits = mechanism_codegen::declared_limits(&decl.model.links);
    if limits.is_empty() {
        return quote!();
    }
    let krate = &decl.krate;
    let option = |v: Option<TokenStream>| match v {
        Some(v) => quote!(::core::option::Option::Some(#v)),
        None => quote!(::core::option::Option::None),
    };
    let entries = limits.iter().map(|l| {
        let coordinate = l.coordinate;
        let linear = l.linear;
        let position = option(l.position.map(|[lo, hi]| {
            let (lo, hi) = (float(lo), float(hi));
            quote!([#lo, #hi])
        }));
        let velocity = option(l.velocity.map(float));
        let effort = option(l.effort.map(float));
        quote! {
            #krate::JointLimits {
                coordinate: #coordinate,
                linear: #linear,
                position: #position,
                velocity: #velocity,
                effort: #effort,
            }
        }
    });
    quote! {
        const JOINT_LIMITS: &'static [#krate::JointLimits] = &[#(#entries),*];
    }
}

/// The trait's equation methods: those of [`dispatched_methods`] (each picking its copy
/// for the CPU), `equations` and the constants `evaluate`, `SPARSITY` and `FRAMES`.
fn expand_equation_methods(
    decl: &Declaration,
    t: &Tables,
    g: &Generated,
    dispatched: &[Method],
) -> TokenStream {
    let krate = &decl.krate;
    let (n, m) = (t.n, t.m);
    let methods = dispatch::trait_methods(krate, dispatched);
    let evaluation = expand_evaluation_methods(krate, n, m, g);
    let equations = &g.equations;
    let frame_names = &g.frame_names;
    quote! {
    #methods
    #evaluation
    fn equations() -> &'static str {
        #equations
    }
    const FRAMES: &'static [&'static str] = &[#(#frame_names),*];
    }
}

/// Every method whose body comes from a routine, with its signature: M, C, C q', g, tau,
/// Phi, Phi_q, Phi_t, gamma, T, Pi, the combined and sparse evaluations, the residual's
/// tangent, the drawing, the robotics methods ([`crate::robotics`]) and the derivatives
/// ([`crate::derivatives`]). Each is compiled
/// for the CPU's instruction set ([`crate::dispatch`]).
fn dispatched_methods(krate: &TokenStream, n: usize, m: usize, g: &Generated) -> Vec<Method> {
    let sv = |k: usize| quote!(&#krate::__private::SVector<f64, #k>);
    let ret_v = |k: usize| quote!(-> #krate::__private::SVector<f64, #k>);
    let ret_m = |r: usize, c: usize| quote!(-> #krate::__private::SMatrix<f64, #r, #c>);
    let (t, q, qd) = (("t", quote!(f64)), ("q", sv(n)), ("qd", sv(n)));
    let c = |b: &TokenStream| b.clone();
    let mut methods = vec![
        Method::new(
            "mass_matrix",
            std::slice::from_ref(&q),
            ret_m(n, n),
            c(&g.mass_matrix),
        ),
        Method::new(
            "coriolis_matrix",
            &[q.clone(), qd.clone()],
            ret_m(n, n),
            c(&g.coriolis_matrix),
        ),
        Method::new(
            "coriolis_forces",
            &[q.clone(), qd.clone()],
            ret_v(n),
            c(&g.coriolis_forces),
        ),
        Method::new("gravity", std::slice::from_ref(&q), ret_v(n), c(&g.gravity)),
        Method::new(
            "generalized_forces",
            &[t.clone(), q.clone(), qd.clone()],
            ret_v(n),
            c(&g.generalized_forces),
        ),
        Method::new(
            "constraints",
            &[t.clone(), q.clone()],
            ret_v(m),
            c(&g.constraints),
        ),
        Method::new(
            "constraint_jacobian",
            &[t.clone(), q.clone()],
            ret_m(m, n),
            c(&g.constraint_jacobian),
        ),
        Method::new(
            "constraint_time_derivative",
            &[t.clone(), q.clone()],
            ret_v(m),
            c(&g.constraint_time_derivative),
        ),
        Method::new(
            "constraint_gamma",
            &[t.clone(), q.clone(), qd.clone()],
            ret_v(m),
            c(&g.constraint_gamma),
        ),
        Method::new(
            "kinetic_energy",
            &[q.clone(), qd.clone()],
            quote!(-> f64),
            c(&g.kinetic_energy),
        ),
        Method::new(
            "potential_energy",
            std::slice::from_ref(&q),
            quote!(-> f64),
            c(&g.potential_energy),
        ),
    ];
    methods.extend(evaluation_methods(krate, n, m, g));
    let sm = quote!(#krate::__private::SMatrix<f64, #n, #n>);
    methods.push(Method::new(
        "residual_tangent",
        &[
            t.clone(),
            q.clone(),
            qd.clone(),
            ("qdd", sv(n)),
            ("lambda", sv(m)),
        ],
        quote!(-> ::core::option::Option<(#sm, #sm)>),
        crate::derivatives::residual_tangent_body(&g.residual_tangent, &g.derivatives),
    ));
    methods.push(Method::new(
        "draw_points",
        &[t, q, ("out", quote!(&mut [f64]))],
        quote!(),
        c(&g.draw_points),
    ));
    methods.extend(crate::robotics::methods(krate, n, m, g));
    methods.extend(crate::derivatives::methods(krate, n, m, &g.derivatives));
    methods
}

/// `evaluate_into`, `evaluate_sparse_into` and `constraint_jacobian_sparse_into`.
fn evaluation_methods(krate: &TokenStream, n: usize, m: usize, g: &Generated) -> Vec<Method> {
    let sv = quote!(&#krate::__private::SVector<f64, #n>);
    let (t, q, qd) = (("t", quote!(f64)), ("q", sv.clone()), ("qd", sv));
    vec![
        Method::new(
            "evaluate_into",
            &[
                t.clone(),
                q.clone(),
                qd.clone(),
                ("out", quote!(&mut #krate::StaticEvaluation<#n, #m>)),
            ],
            quote!(),
            g.evaluate_into.clone(),
        ),
        Method::new(
            "evaluate_sparse_into",
            &[
                t.clone(),
                q.clone(),
                qd,
                ("out", quote!(&mut #krate::EvaluationSlices<'_>)),
            ],
            quote!(-> bool),
            g.evaluate_sparse_into.clone(),
        ),
        Method::new(
            "constraint_jacobian_sparse_into",
            &[
                t,
                q,
                ("phi_q", quote!(&mut [f64])),
                ("phi_t", quote!(&mut [f64])),
            ],
            quote!(-> bool),
            g.constraint_jacobian_sparse_into.clone(),
        ),
    ]
}

/// `evaluate` (through `evaluate_into`) and `SPARSITY`, the structural pattern of M and
/// Phi_q.
fn expand_evaluation_methods(
    krate: &TokenStream,
    n: usize,
    m: usize,
    g: &Generated,
) -> TokenStream {
    let sv = quote!(#krate::__private::SVector);
    let (mass_pattern, jacobian_pattern) = &g.sparsity;
    let as_u32 = |p: &[(usize, usize)], col: bool| -> Vec<u32> {
        p.iter()
            .map(|&(i, j)| u32::try_from(if col { j } else { i }).unwrap_or(u32::MAX))
            .collect()
    };
    let (mass_rows, mass_cols) = (as_u32(mass_pattern, false), as_u32(mass_pattern, true));
    let (jac_rows, jac_cols) = (
        as_u32(jacobian_pattern, false),
        as_u32(jacobian_pattern, true),
    );
    quote! {
    fn evaluate(
        &self,
        t: f64,
        q: &#sv<f64, #n>,
        qd: &#sv<f64, #n>,
    ) -> #krate::StaticEvaluation<#n, #m> {
        let mut out = #krate::StaticEvaluation::<#n, #m>::zeros();
        self.evaluate_into(t, q, qd, &mut out);
        out
    }
    const SPARSITY: ::core::option::Option<#krate::StaticSparsity> =
        ::core::option::Option::Some(#krate::StaticSparsity {
            mass: &[#((#mass_rows, #mass_cols)),*],
            jacobian: &[#((#jac_rows, #jac_cols)),*],
        });
    }
}

/// `parameter(index)` and `set_parameter(index, value)` of the trait `trait_path` (the
/// `p` parameters are the fields `fields` of `self.__parameters`): set_parameter checks the
/// value against the trait's `PARAMETER_RANGES`, stores it and refreshes the cached
/// parameter-only values.
pub(crate) fn parameter_methods(
    krate: &TokenStream,
    trait_path: &TokenStream,
    p: usize,
    fields: &[Ident],
) -> TokenStream {
    let indices: Vec<usize> = (0..p).collect();
    quote! {
        fn parameter(&self, index: usize) -> ::core::option::Option<f64> {
            match index {
                #(#indices => ::core::option::Option::Some(self.__parameters.#fields),)*
                _ => ::core::option::Option::None,
            }
        }
        fn set_parameter(
            &mut self,
            index: usize,
            value: f64,
        ) -> ::core::result::Result<(), #krate::ParameterError> {
            #krate::__private::check_parameter(
                index,
                value,
                #p,
                <Self as #trait_path>::PARAMETER_RANGES,
            )?;
            match index {
                #(#indices => self.__parameters.#fields = value,)*
                _ => {}
            }
            Self::refresh(self);
            ::core::result::Result::Ok(())
        }
    }
}
