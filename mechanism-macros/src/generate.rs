//! Derivation and code generation: the Lagrange equations with multipliers of the declared
//! model (`mechanism_codegen::derive`), compiled into one program per role
//! (`mechanism_codegen::compile`, the routines the interpreter runs too), then one
//! straight-line, allocation-free body per trait method (`emit_body`).
//!
//! The values that depend on parameters only are computed by the routines' parameter cache
//! when the parameters are set and read as `cache[k]`; a body then computes only what
//! depends on t, q and q'. Matrix bodies start from zeroed nalgebra
//! matrices (stack values, no allocation) and write the non-zero entries with constant
//! indices; `evaluate_into` writes every entry of the caller's buffer. Symbols are read as
//! the routines' source table says: `self.__parameters.<parameter>`, `cache[k]`, `q[i]`,
//! `qd[i]`, `qdd[i]`, `lambda[k]` and `t`. The combined evaluation is one
//! program over all outputs, so sin/cos pairs and common subexpressions are computed once.

use mechanism_codegen::{
    EmitBindings, EvaluationOutput, LEAN_ABOVE, Model, Operand, OutputTarget, Program, Role,
    Routines, Source, emit_body, full_tangent,
};
use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;

use crate::ast::{self, Declaration};

/// An output with more zero entries than this is zeroed with one `fill` by
/// `evaluate_into` and then gets its nonzero entries; smaller ones get every entry written
/// (a store per structural zero instead of a memset per call, and no thousands of zero
/// stores for a large sparse Phi_q).
const FILL_ZEROS_ABOVE: usize = 32;

/// Largest residual tangent emitted, in instructions. Past it `residual_tangent` returns
/// `None` (implicit integrators then difference the residual) instead of code that rustc
/// cannot compile within the budget of issue 50 (1.5 GB, 15 s of CPU for `cargo check
/// --release`): the tangent is one generic function (`crate::dispatch`), whose optimised
/// MIR `cargo check` builds and writes into the crate's metadata. Talos with its grippers
/// free (44 coordinates) has a tangent of 81,700 instructions, which took that peak from
/// 1.1 GB (without the tangent) to 2.8 GB; the 30-coordinate Talos' 31,500 and the
/// Panda's 12,000 are emitted.
pub const TANGENT_INSTRUCTIONS_MAX: usize = 60_000;

/// (row, column) pairs of a matrix's structural nonzeros, row-major.
pub type Pattern = Vec<(usize, usize)>;

/// The bodies of the derivative methods; `None` for a program past
/// [`TANGENT_INSTRUCTIONS_MAX`] (as the residual's tangent: code rustc could not compile in
/// a laptop's memory), whose method is then the trait's default (central differences of
/// the inverse dynamics, `false`, `None`).
#[derive(Default)]
pub struct DerivativeBodies {
    /// `inverse_dynamics_derivatives(&self, t, q, qd, qdd)`: (dtau/dq, dtau/dq').
    pub inverse_dynamics: Option<TokenStream>,
    /// `inverse_dynamics_parameter_derivatives(&self, t, q, qd, qdd, out)`: dtau/dp into
    /// the column-major slice `out`.
    pub parameters: Option<TokenStream>,
    /// `constraint_tangent(&self, t, q, qd, qdd)`: (D, R_q, R_q').
    pub constraint_tangent: Option<TokenStream>,
    /// `forward_dynamics_derivatives(&self, t, q, qd, effort)`: (dq''/dq, dq''/dq', M^-1)
    /// (a mechanism without constraint rows).
    pub forward_dynamics: Option<TokenStream>,
    /// Whether the residual's tangent is the same program (a mechanism without constraint
    /// rows): `residual_tangent` then calls `inverse_dynamics_derivatives` instead of
    /// repeating its body.
    pub tangent_is_inverse_dynamics: bool,
}

/// The bodies of the trait methods and the equations text.
#[derive(Default)]
pub struct Generated {
    /// `mass_matrix(&self, q)`.
    pub mass_matrix: TokenStream,
    /// `coriolis_matrix(&self, q, qd)`.
    pub coriolis_matrix: TokenStream,
    /// `coriolis_forces(&self, q, qd)`.
    pub coriolis_forces: TokenStream,
    /// `gravity(&self, q)`.
    pub gravity: TokenStream,
    /// `generalized_forces(&self, t, q, qd)`.
    pub generalized_forces: TokenStream,
    /// `constraints(&self, t, q)`.
    pub constraints: TokenStream,
    /// `constraint_jacobian(&self, t, q)`.
    pub constraint_jacobian: TokenStream,
    /// `constraint_time_derivative(&self, t, q)`.
    pub constraint_time_derivative: TokenStream,
    /// `constraint_gamma(&self, t, q, qd)`.
    pub constraint_gamma: TokenStream,
    /// `kinetic_energy(&self, q, qd)`.
    pub kinetic_energy: TokenStream,
    /// `potential_energy(&self, q)`.
    pub potential_energy: TokenStream,
    /// `evaluate_into(&self, t, q, qd, out)`: everything, sharing subexpressions, written
    /// into every entry of `out`.
    pub evaluate_into: TokenStream,
    /// `evaluate_sparse_into(&self, t, q, qd, out)`: the same program, M and Phi_q written
    /// into column-major slices at their structural pattern only.
    pub evaluate_sparse_into: TokenStream,
    /// `constraint_jacobian_sparse_into(&self, t, q, phi_q, phi_t)`: Phi_q at its pattern
    /// (column-major slice), Phi_t.
    pub constraint_jacobian_sparse_into: TokenStream,
    /// The structural nonzeros of M and of Phi_q, row-major (`Routines::sparsity`).
    pub sparsity: (Pattern, Pattern),
    /// `residual_tangent(&self, t, q, qd, qdd, lambda)`: dF/dq and dF/dq' of the residual.
    pub residual_tangent: TokenStream,
    /// The bodies of the derivative methods (`crate::derivatives`).
    pub derivatives: DerivativeBodies,
    /// `draw_points(&self, t, q, out)`: the drawn points' world positions (empty without a
    /// drawing).
    pub draw_points: TokenStream,
    /// The derived equations as readable text (`mechanism_codegen::equations_text`).
    pub equations: String,
    /// `mass_and_bias(&self, t, q, qd)`: M and b = C q' + g - tau, one program.
    pub mass_and_bias: TokenStream,
    /// `inverse_dynamics(&self, t, q, qd, qdd)`: M q'' + C q' + g - tau.
    pub inverse_dynamics: TokenStream,
    /// `bias(&self, t, q, qd)`: b = C q' + g - tau, M-free.
    pub bias: TokenStream,
    /// `forward_dynamics(&self, t, q, qd, effort)`: q'' from M q'' + b = u by the
    /// factorisation that follows M's pattern; `None` (the trait's default, for a mechanism
    /// with constraint rows) when no such routine is compiled.
    pub forward_dynamics: Option<TokenStream>,
    /// `constrained_dynamics(&self, t, q, qd)`: q'' and lambda of the KKT system by the
    /// factorisation that follows M's pattern; `None` (the trait's default, the dense
    /// solve) when no such routine is compiled or it has no outputs.
    pub constrained_dynamics: Option<TokenStream>,
    /// Per link frame: the body of one arm of `frame_placement`'s match, giving `(R, p)`.
    pub frame_placements: Vec<TokenStream>,
    /// Per link frame: the body of one arm of `frame_jacobian`'s match, giving J (6 x n).
    pub frame_jacobians: Vec<TokenStream>,
    /// The link frames' names.
    pub frame_names: Vec<String>,
    /// `fn(p: &Parameters) -> ([f64; n], [f64; 2 k])`'s body: the initial guesses and the
    /// independent coordinates' positions and rates at the parameters `p`.
    pub initial_values: TokenStream,
    /// The number of cached parameter-only values.
    pub cache_len: usize,
    /// `fn(p: &Parameters) -> [f64; cache_len]`'s body: the cached values.
    pub cache: TokenStream,
    /// The fingerprint of the routines every body comes from (`Routines::fingerprint`).
    pub routines: u64,
}

/// Derives the equations of `decl`, compiles them into routines and generates every body.
pub fn generate(decl: &mut Declaration) -> syn::Result<Generated> {
    let eqs = mechanism_codegen::derive(&mut decl.model).map_err(|e| codegen_error(decl, &e))?;
    // Every tangent: the residual's, the constraint rows' and the inverse dynamics'
    // derivatives by the motion and the parameters (the derivative methods).
    let tangent = full_tangent(&mut decl.model, &eqs).map_err(|e| codegen_error(decl, &e))?;
    let routines = mechanism_codegen::compile(&mut decl.model, &eqs, &tangent);
    let routines = routines.map_err(|e| codegen_error(decl, &e))?;
    let b = Bodies {
        model: &decl.model,
        krate: &decl.krate,
        routines: &routines,
    };
    let frames = eqs.frames.len();
    let result = (|| -> mechanism_codegen::Result<Generated> {
        Ok(Generated {
            mass_matrix: b.matrix(Role::Mass)?,
            coriolis_matrix: b.matrix(Role::CoriolisMatrix)?,
            coriolis_forces: b.matrix(Role::CoriolisForces)?,
            gravity: b.matrix(Role::Gravity)?,
            generalized_forces: b.matrix(Role::Forces)?,
            constraints: b.matrix(Role::Constraints)?,
            constraint_jacobian: b.matrix(Role::ConstraintJacobian)?,
            constraint_time_derivative: b.matrix(Role::ConstraintTimeDerivative)?,
            constraint_gamma: b.matrix(Role::Gamma)?,
            kinetic_energy: b.scalar(Role::Kinetic)?,
            potential_energy: b.scalar(Role::Potential)?,
            evaluate_into: b.evaluate_into()?,
            evaluate_sparse_into: b.evaluate_sparse_into()?,
            constraint_jacobian_sparse_into: b.constraint_jacobian_sparse_into(eqs.n, eqs.m)?,
            sparsity: (
                routines.sparsity(EvaluationOutput::Mass)?.entries,
                routines.sparsity(EvaluationOutput::PhiQ)?.entries,
            ),
            residual_tangent: b.tangent(eqs.n)?,
            derivatives: DerivativeBodies {
                inverse_dynamics: b.inverse_dynamics_derivatives(eqs.n)?,
                parameters: b.parameter_derivatives()?,
                constraint_tangent: b.constraint_tangent(eqs.n, eqs.m)?,
                forward_dynamics: b.forward_dynamics_derivatives(eqs.n)?,
                tangent_is_inverse_dynamics: routines.program(Role::Tangent)?
                    == routines.program(Role::InverseDynamicsDerivatives)?,
            },
            draw_points: b.draw_points()?,
            equations: mechanism_codegen::equations_text(&decl.model, &eqs),
            mass_and_bias: b.mass_and_bias(eqs.n)?,
            inverse_dynamics: b.inverse_dynamics()?,
            bias: b.matrix(Role::Bias)?,
            forward_dynamics: b.forward_dynamics(eqs.n)?,
            constrained_dynamics: b.constrained_dynamics(eqs.n, eqs.m)?,
            frame_placements: (0..frames)
                .map(|k| b.placement(Role::FramePlacement(k)))
                .collect::<mechanism_codegen::Result<_>>()?,
            frame_jacobians: (0..frames)
                .map(|k| b.matrix(Role::FrameJacobian(k)))
                .collect::<mechanism_codegen::Result<_>>()?,
            frame_names: eqs.frames.iter().map(|f| f.name.clone()).collect(),
            initial_values: b.initial_values()?,
            cache_len: routines.cache_len(),
            cache: b.cache()?,
            routines: routines.fingerprint(),
        })
    })();
    result.map_err(|e| codegen_error(decl, &e))
}

/// A codegen error as a compile error at the user's token (or the file literal). An error
/// without a location of its own (one found while deriving) points at the mechanism's name.
pub(crate) fn codegen_error(decl: &Declaration, e: &mechanism_codegen::Error) -> syn::Error {
    let at = ast::location(e).unwrap_or(decl.spans.name);
    decl.error_at(Some(at), &ast::message(e))
}

/// Emits bodies for one model.
pub(crate) struct Bodies<'a> {
    pub(crate) model: &'a Model,
    pub(crate) krate: &'a TokenStream,
    pub(crate) routines: &'a Routines,
}

impl Bodies<'_> {
    /// How the emitted body of `role` reads each symbol its role provides, from the
    /// routines' source table: parameters from `self.__parameters`, cached values from
    /// `cache`, coordinates, rates and accelerations from `q`, `qd` and `qdd`, multipliers
    /// from `lambda`, time from `t`. Real functions call the runtime crate's `math` module
    /// (`sin_cos` is the function the interpreter, `Tape`, uses; the others exist without
    /// std, where the f64 methods do not).
    /// The bodies are generic over the instruction set: grouped sines and cosines are
    /// computed by `isa` ([`crate::dispatch`]).
    fn bindings(&self, role: Role) -> EmitBindings {
        let mut b = self.bindings_with(role, quote!(self.__parameters));
        b.set_isa(quote!(isa));
        b
    }

    /// [`Bodies::bindings`] with the parameters read from the struct at `params`.
    fn bindings_with(&self, role: Role, params: TokenStream) -> EmitBindings {
        let krate = self.krate;
        let mut b = EmitBindings::new();
        b.set_prefix("v");
        b.set_math(quote!(#krate::math));
        for (symbol, source) in self.routines.sources().iter() {
            if !role.provides(source) {
                continue;
            }
            let tokens = match source {
                Source::Coordinate(i) => quote!(q[#i]),
                Source::Rate(i) => quote!(qd[#i]),
                Source::Acceleration(i) => quote!(qdd[#i]),
                Source::Parameter(k) => {
                    let Some(p) = self.model.parameters.get(k) else {
                        continue;
                    };
                    let field = Ident::new(&p.name, Span::call_site());
                    quote!(#params.#field)
                }
                Source::Cache(k) => quote!(cache[#k]),
                Source::Time => quote!(t),
                Source::Multiplier(k) => quote!(lambda[#k]),
                Source::Effort(k) => quote!(effort[#k]),
            };
            b.bind(symbol, tokens);
        }
        b
    }

    /// The program of `role` and its bindings.
    pub(crate) fn routine(
        &self,
        role: Role,
    ) -> mechanism_codegen::Result<(&Program, EmitBindings)> {
        Ok((self.routines.program(role)?, self.bindings(role)))
    }

    /// `let cache = ...;` when `program` reads a cached value: the struct's cache while it
    /// is current, else the values computed here from the parameters (after a change
    /// through `DerefMut` that was not followed by `refresh`).
    pub(crate) fn cache_read(&self, program: &Program) -> TokenStream {
        let sources = self.routines.sources();
        let reads = program
            .symbols()
            .iter()
            .any(|(s, _)| matches!(sources.get(*s), Some(Source::Cache(_))));
        if !reads {
            return quote!();
        }
        let k = self.routines.cache_len();
        quote! {
            let computed: [f64; #k];
            let cache: &[f64; #k] = if self.__cached {
                &self.__cache
            } else {
                computed = Self::parameter_cache(&self.__parameters);
                &computed
            };
        }
    }

    /// Where an output matrix `name` (a nalgebra matrix starting at zero) is written: entry
    /// by entry, zeros skipped; in a body of more than [`LEAN_ABOVE`] instructions, all at
    /// once into its storage (one statement instead of one indexed store per entry).
    pub(crate) fn place(program: &Program, name: TokenStream) -> OutputTarget {
        if program.instructions().len() > LEAN_ABOVE {
            OutputTarget::Columns {
                name: quote!(#name.data.0),
            }
        } else {
            OutputTarget::Matrix { name, zeroed: true }
        }
    }

    /// The statements of `role`'s program writing its output k into the local matrix
    /// `names[k]` (each placed as [`Bodies::place`]).
    pub(crate) fn named_outputs(
        &self,
        role: Role,
        program: &Program,
        names: &[TokenStream],
    ) -> mechanism_codegen::Result<TokenStream> {
        let targets: Vec<_> = names
            .iter()
            .map(|x| Self::place(program, x.clone()))
            .collect();
        Ok(emit_body(program, &self.bindings(role), &targets)?.tokens)
    }

    /// `let definite = ..;`: every pivot of M = L^T D L (the local `pivots`, in elimination
    /// order) finite and above `ratio` of M's diagonal entry there (the local `diagonal`).
    pub(crate) fn definite_pivots(ratio: TokenStream) -> TokenStream {
        quote! {
            let definite = pivots
                .iter()
                .zip(diagonal.iter())
                .all(|(d, m)| d.is_finite() && *d > #ratio * *m);
        }
    }

    /// A body returning one nalgebra matrix (or vector) of the shape of `role`'s output.
    pub(crate) fn matrix(&self, role: Role) -> mechanism_codegen::Result<TokenStream> {
        let (program, bindings) = self.routine(role)?;
        let targets = [Self::place(program, quote!(out))];
        let body = emit_body(program, &bindings, &targets)?.tokens;
        let o = &program.outputs()[0];
        let (r, c, krate) = (o.rows, o.cols, self.krate);
        let mutable = if body.is_empty() {
            quote!()
        } else {
            quote!(mut)
        };
        let cache = self.cache_read(program);
        Ok(quote! {
            #cache
            let #mutable out = #krate::__private::SMatrix::<f64, #r, #c>::zeros();
            #body
            out
        })
    }

    /// `(M, b)`: M (n x n) and the bias b = C q' + g - tau (n x 1), one program.
    pub(crate) fn mass_and_bias(&self, n: usize) -> mechanism_codegen::Result<TokenStream> {
        self.tuple(
            Role::MassAndBias,
            &[(quote!(mass), n, n), (quote!(bias), n, 1)],
        )
    }

    /// A body returning the outputs of `role`'s program as a tuple of nalgebra matrices,
    /// `(name, rows, cols)` each.
    pub(crate) fn tuple(
        &self,
        role: Role,
        outputs: &[(TokenStream, usize, usize)],
    ) -> mechanism_codegen::Result<TokenStream> {
        let (program, bindings) = self.routine(role)?;
        let targets: Vec<OutputTarget> = (outputs.iter())
            .map(|(name, _, _)| Self::place(program, name.clone()))
            .collect();
        let body = emit_body(program, &bindings, &targets)?.tokens;
        let (krate, cache) = (self.krate, self.cache_read(program));
        let names = outputs.iter().map(|(name, _, _)| name);
        let zeros = outputs.iter().map(|(name, r, c)| {
            quote!(let mut #name = #krate::__private::SMatrix::<f64, #r, #c>::zeros();)
        });
        Ok(quote! {
            #cache
            #(#zeros)*
            #body
            (#(#names),*)
        })
    }

    /// M q'' + C q' + g - tau, with q'' read from `qdd`.
    pub(crate) fn inverse_dynamics(&self) -> mechanism_codegen::Result<TokenStream> {
        let (program, bindings) = self.routine(Role::InverseDynamics)?;
        let targets = [Self::place(program, quote!(out))];
        let body = emit_body(program, &bindings, &targets)?.tokens;
        let n = self.model.coordinates.len();
        let (krate, cache) = (self.krate, self.cache_read(program));
        Ok(quote! {
            #cache
            let mut out = #krate::__private::SVector::<f64, #n>::zeros();
            #body
            out
        })
    }

    /// `Some(q'')` when every pivot of M = L^T D L is finite and above 1e-14 of its
    /// diagonal entry (M positive definite beyond round-off) and q'' is finite, else
    /// `None`; `None` overall for a mechanism without the routine.
    pub(crate) fn forward_dynamics(
        &self,
        n: usize,
    ) -> mechanism_codegen::Result<Option<TokenStream>> {
        let Some(program) = self.routines.get(Role::ForwardDynamics) else {
            return Ok(None);
        };
        let names = [quote!(qdd), quote!(pivots), quote!(diagonal)];
        let body = self.named_outputs(Role::ForwardDynamics, program, &names)?;
        let (krate, cache) = (self.krate, self.cache_read(program));
        let v = quote!(#krate::__private::SVector::<f64, #n>);
        let definite = Self::definite_pivots(quote!(1e-14));
        Ok(Some(quote! {
            let _ = t;
            #cache
            let mut qdd = #v::zeros();
            let mut pivots = #v::zeros();
            let mut diagonal = #v::zeros();
            #body
            #definite
            (definite && qdd.iter().all(|x| x.is_finite())).then_some(qdd)
        }))
    }

    /// `Ok(solution)` from `kkt_tree_solve` on the emitted u, Y, S and c when every pivot of
    /// M = L^T D L is finite and above 1e-12 of its diagonal entry (the dense solve's
    /// threshold for M~) and the result is finite, else what the dense `kkt_solve` gives on
    /// `evaluate` (the same semantics and errors); `None` overall for a mechanism without
    /// the routine or whose program is past [`TANGENT_INSTRUCTIONS_MAX`].
    pub(crate) fn constrained_dynamics(
        &self,
        n: usize,
        m: usize,
    ) -> mechanism_codegen::Result<Option<TokenStream>> {
        let Some(program) = self.routines.get(Role::ConstrainedDynamics) else {
            return Ok(None);
        };
        // Past the cap the trait's default (the dense `kkt_solve` on `evaluate`) answers:
        // A02 with N = 80 (162 coordinates, 161 rows) writes 1.9 million operations here,
        // which rustc cannot compile within issue 50's build budget.
        if program.outputs().is_empty() || program.instructions().len() > TANGENT_INSTRUCTIONS_MAX {
            return Ok(None);
        }
        let names = [
            quote!(u),
            quote!(y),
            quote!(s),
            quote!(c),
            quote!(pivots),
            quote!(diagonal),
        ];
        let body = self.named_outputs(Role::ConstrainedDynamics, program, &names)?;
        let definite = Self::definite_pivots(quote!(1e-12));
        let (krate, cache) = (self.krate, self.cache_read(program));
        let sm = |r: usize, c: usize| quote!(#krate::__private::SMatrix::<f64, #r, #c>);
        let (vn, mnm, mmm, vm) = (sm(n, 1), sm(n, m), sm(m, m), sm(m, 1));
        Ok(Some(quote! {
            #cache
            let mut u = #vn::zeros();
            let mut y = #mnm::zeros();
            let mut s = #mmm::zeros();
            let mut c = #vm::zeros();
            let mut pivots = #vn::zeros();
            let mut diagonal = #vn::zeros();
            #body
            #definite
            if definite {
                if let ::core::option::Option::Some(solution) =
                    #krate::__private::kkt_tree_solve(&u, &y, &s, &c)
                {
                    return ::core::result::Result::Ok(solution);
                }
            }
            #krate::__private::kkt_solve(&#krate::Mechanism::<#n, #m>::evaluate(self, t, q, qd), t)
        }))
    }

    /// `(R, p)` of one link frame.
    pub(crate) fn placement(&self, role: Role) -> mechanism_codegen::Result<TokenStream> {
        self.tuple(role, &[(quote!(rotation), 3, 3), (quote!(position), 3, 1)])
    }

    /// The drawn points' x, y, z into the slice `out` (3 per point, in drawing order),
    /// after a length check so that the constant indices cannot panic.
    fn draw_points(&self) -> mechanism_codegen::Result<TokenStream> {
        let Some(program) = self.routines.get(Role::Draw) else {
            return Ok(quote!(let _ = (t, q, out);));
        };
        let targets = [OutputTarget::Vector {
            name: quote!(out),
            zeroed: false,
        }];
        let body = emit_body(program, &self.bindings(Role::Draw), &targets)?.tokens;
        let len = 3 * self.model.drawing.points.len();
        let cache = self.cache_read(program);
        Ok(quote! {
            let _ = (t, q);
            if out.len() < #len {
                return;
            }
            #cache
            #body
        })
    }

    /// A body returning the single entry of a 1 x 1 output.
    pub(crate) fn scalar(&self, role: Role) -> mechanism_codegen::Result<TokenStream> {
        let (program, bindings) = self.routine(role)?;
        let body = emit_body(program, &bindings, &[OutputTarget::Return])?.tokens;
        let cache = self.cache_read(program);
        Ok(quote! {
            #cache
            #body
        })
    }

    /// The combined evaluation into the caller's `out`: one program for all outputs. Every
    /// entry is written: small outputs entry by entry (zeros included), outputs with many
    /// zeros by one `fill(0.0)` and their nonzero entries; in a large body (past
    /// [`LEAN_ABOVE`]), each matrix at once into its storage.
    fn evaluate_into(&self) -> mechanism_codegen::Result<TokenStream> {
        let (program, bindings) = self.routine(Role::Evaluation)?;
        let lean = program.instructions().len() > LEAN_ABOVE;
        let mut fills = TokenStream::new();
        let targets: Vec<OutputTarget> = EvaluationOutput::ORDER
            .iter()
            .zip(program.outputs())
            .map(|(o, output)| {
                let name = match o {
                    EvaluationOutput::Mass => quote!(out.mass),
                    EvaluationOutput::CoriolisForces => quote!(out.coriolis),
                    EvaluationOutput::Gravity => quote!(out.gravity),
                    EvaluationOutput::Forces => quote!(out.forces),
                    EvaluationOutput::Phi => quote!(out.phi),
                    EvaluationOutput::PhiQ => quote!(out.phi_q),
                    EvaluationOutput::PhiT => quote!(out.phi_t),
                    EvaluationOutput::Gamma => quote!(out.gamma),
                    EvaluationOutput::Kinetic => {
                        return OutputTarget::Vector {
                            name: quote!(kinetic),
                            zeroed: false,
                        };
                    }
                    EvaluationOutput::Potential => {
                        return OutputTarget::Vector {
                            name: quote!(potential),
                            zeroed: false,
                        };
                    }
                };
                if lean {
                    return OutputTarget::Columns {
                        name: quote!(#name.data.0),
                    };
                }
                let zeros = output
                    .entries
                    .iter()
                    .filter(|e| **e == Operand::Const(0.0))
                    .count();
                let zeroed = zeros > FILL_ZEROS_ABOVE;
                if zeroed {
                    fills.extend(quote!(#name.fill(0.0);));
                }
                OutputTarget::Matrix { name, zeroed }
            })
            .collect();
        let body = emit_body(program, &bindings, &targets)?.tokens;
        let cache = self.cache_read(program);
        Ok(quote! {
            #cache
            let mut kinetic = [0.0_f64; 1];
            let mut potential = [0.0_f64; 1];
            #fills
            #body
            out.kinetic = kinetic[0];
            out.potential = potential[0];
        })
    }

    /// The combined evaluation into the caller's `EvaluationSlices`: M and Phi_q at their
    /// structural pattern only (column-major), every entry of the vectors, after a check of
    /// the slices' lengths (false when one differs, so no index can panic).
    fn evaluate_sparse_into(&self) -> mechanism_codegen::Result<TokenStream> {
        let (program, bindings) = self.routine(Role::Evaluation)?;
        let targets: Vec<OutputTarget> = EvaluationOutput::ORDER
            .iter()
            .map(|o| {
                let vector = |name| OutputTarget::Vector {
                    name,
                    zeroed: false,
                };
                match o {
                    EvaluationOutput::Mass => OutputTarget::ColumnMajor {
                        name: quote!(out.mass),
                    },
                    EvaluationOutput::PhiQ => OutputTarget::ColumnMajor {
                        name: quote!(out.phi_q),
                    },
                    EvaluationOutput::CoriolisForces => vector(quote!(out.coriolis)),
                    EvaluationOutput::Gravity => vector(quote!(out.gravity)),
                    EvaluationOutput::Forces => vector(quote!(out.forces)),
                    EvaluationOutput::Phi => vector(quote!(out.phi)),
                    EvaluationOutput::PhiT => vector(quote!(out.phi_t)),
                    EvaluationOutput::Gamma => vector(quote!(out.gamma)),
                    EvaluationOutput::Kinetic => vector(quote!(kinetic)),
                    EvaluationOutput::Potential => vector(quote!(potential)),
                }
            })
            .collect();
        let body = emit_body(program, &bindings, &targets)?.tokens;
        let cache = self.cache_read(program);
        // Phi (m x 1) is the fifth output.
        let m = program.outputs().get(4).map_or(0, |o| o.rows);
        let n = self.model.coordinates.len();
        Ok(quote! {
            if !out.fits(#n, #m) {
                return false;
            }
            #cache
            let mut kinetic = [0.0_f64; 1];
            let mut potential = [0.0_f64; 1];
            #body
            *out.kinetic = kinetic[0];
            *out.potential = potential[0];
            true
        })
    }

    /// Phi_q into the column-major slice `phi_q` at its structural pattern and Phi_t into
    /// `phi_t`, from the programs of their two roles (each in its own block), after a check
    /// of the slices' lengths.
    fn constraint_jacobian_sparse_into(
        &self,
        n: usize,
        m: usize,
    ) -> mechanism_codegen::Result<TokenStream> {
        let (jacobian, bindings) = self.routine(Role::ConstraintJacobian)?;
        let targets = [OutputTarget::ColumnMajor {
            name: quote!(phi_q),
        }];
        let jacobian_body = emit_body(jacobian, &bindings, &targets)?.tokens;
        let jacobian_cache = self.cache_read(jacobian);
        let (time, bindings) = self.routine(Role::ConstraintTimeDerivative)?;
        let targets = [OutputTarget::Vector {
            name: quote!(phi_t),
            zeroed: false,
        }];
        let time_body = emit_body(time, &bindings, &targets)?.tokens;
        let time_cache = self.cache_read(time);
        let len = m * n;
        Ok(quote! {
            if phi_q.len() != #len || phi_t.len() != #m {
                return false;
            }
            {
                #jacobian_cache
                #jacobian_body
            }
            {
                #time_cache
                #time_body
            }
            true
        })
    }

    /// `Some((K, D))` with K = dF/dq and D = dF/dq' (n x n each, one program for both);
    /// q'' is read from `qdd`, the multipliers from `lambda`. `None` past
    /// [`TANGENT_INSTRUCTIONS_MAX`].
    fn tangent(&self, n: usize) -> mechanism_codegen::Result<TokenStream> {
        let (program, bindings) = self.routine(Role::Tangent)?;
        if program.instructions().len() > TANGENT_INSTRUCTIONS_MAX {
            return Ok(quote!(::core::option::Option::None));
        }
        let targets = [
            Self::place(program, quote!(stiffness)),
            Self::place(program, quote!(damping)),
        ];
        let body = emit_body(program, &bindings, &targets)?.tokens;
        let krate = self.krate;
        let cache = self.cache_read(program);
        Ok(quote! {
            #cache
            let mut stiffness = #krate::__private::SMatrix::<f64, #n, #n>::zeros();
            let mut damping = #krate::__private::SMatrix::<f64, #n, #n>::zeros();
            #body
            ::core::option::Option::Some((stiffness, damping))
        })
    }

    /// The body of `fn initial_values(p: &Parameters) -> ([f64; n], [f64; 2 k])`: the
    /// program of [`Role::InitialValues`], reading the parameters from `p` (never the
    /// cache, so a field changed without `refresh` is followed).
    pub(crate) fn initial_values(&self) -> mechanism_codegen::Result<TokenStream> {
        let role = Role::InitialValues;
        let program = self.routines.program(role)?;
        let rows = |k: usize| program.outputs().get(k).map_or(0, |o| o.rows);
        let (n, k2) = (rows(0), rows(1));
        let vector = |name| OutputTarget::Vector {
            name,
            zeroed: false,
        };
        let targets = [vector(quote!(guess)), vector(quote!(values))];
        let body = emit_body(program, &self.bindings_with(role, quote!(p)), &targets)?.tokens;
        Ok(quote! {
            let mut guess = [0.0_f64; #n];
            let mut values = [0.0_f64; #k2];
            #body
            (guess, values)
        })
    }

    /// The body of `fn parameter_cache(p: &Parameters) -> [f64; K]`.
    pub(crate) fn cache(&self) -> mechanism_codegen::Result<TokenStream> {
        let role = Role::ParameterCache;
        let program = self.routines.program(role)?;
        let k = self.routines.cache_len();
        let targets = [OutputTarget::Vector {
            name: quote!(out),
            zeroed: false,
        }];
        let body = emit_body(program, &self.bindings_with(role, quote!(p)), &targets)?.tokens;
        let mutable = if k == 0 { quote!() } else { quote!(mut) };
        Ok(quote! {
            let #mutable out = [0.0_f64; #k];
            #body
            out
        })
    }
}
