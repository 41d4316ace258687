//! Derivation and code generation: the Lagrange equations with multipliers of the declared
//! model (`mechanism_codegen::derive`), then one CSE'd, straight-line, allocation-free body
//! per trait method (`Program::new` + `emit_body`).
//!
//! Each body starts from zeroed nalgebra matrices (stack values, no allocation), and the
//! emitted statements write the non-zero entries with constant indices. Symbols are read as
//! `self.<parameter>`, `q[i]`, `qd[i]` and `t`. The combined `evaluate` is one program over
//! all outputs, so sin/cos pairs and common subexpressions are computed once.

use mechanism_codegen::{
    EmitBindings, Equations, EvaluationOutput, Matrix, Model, OutputTarget, Program,
    ResidualTangent, emit_body, residual_tangent,
};
use proc_macro2::{Ident, Span, TokenStream};
use quote::quote;

use crate::ast::{self, Declaration};

/// The bodies of the trait methods and the equations text.
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
    /// `evaluate(&self, t, q, qd)`: everything, sharing subexpressions.
    pub evaluate: TokenStream,
    /// `residual_tangent(&self, t, q, qd, qdd, lambda)`: dF/dq and dF/dq' of the residual.
    pub residual_tangent: TokenStream,
    /// `draw_points(&self, t, q, out)`: the drawn points' world positions (empty without a
    /// drawing).
    pub draw_points: TokenStream,
    /// The derived equations as readable text (`mechanism_codegen::equations_text`).
    pub equations: String,
}

/// Derives the equations of `decl` and generates every body.
pub fn generate(decl: &mut Declaration) -> syn::Result<Generated> {
    let eqs = mechanism_codegen::derive(&mut decl.model).map_err(|e| codegen_error(decl, &e))?;
    let tangent = residual_tangent(&mut decl.model, &eqs).map_err(|e| codegen_error(decl, &e))?;
    let b = Bodies {
        model: &decl.model,
        krate: &decl.krate,
    };
    let result = (|| -> mechanism_codegen::Result<Generated> {
        let kinetic = Matrix::column(vec![eqs.kinetic]);
        let potential = Matrix::column(vec![eqs.potential]);
        Ok(Generated {
            mass_matrix: b.matrix(&eqs.mass)?,
            coriolis_matrix: b.matrix(&eqs.coriolis_matrix)?,
            coriolis_forces: b.matrix(&eqs.coriolis_forces)?,
            gravity: b.matrix(&eqs.gravity)?,
            generalized_forces: b.matrix(&eqs.forces)?,
            constraints: b.matrix(&eqs.phi)?,
            constraint_jacobian: b.matrix(&eqs.phi_q)?,
            constraint_time_derivative: b.matrix(&eqs.phi_t)?,
            constraint_gamma: b.matrix(&eqs.gamma)?,
            kinetic_energy: b.scalar(&kinetic)?,
            potential_energy: b.scalar(&potential)?,
            evaluate: b.evaluate(&eqs)?,
            residual_tangent: b.tangent(&tangent)?,
            draw_points: b.draw_points()?,
            equations: mechanism_codegen::equations_text(&decl.model, &eqs),
        })
    })();
    result.map_err(|e| codegen_error(decl, &e))
}

/// A codegen error as a compile error at the user's token (or the file literal).
fn codegen_error(decl: &Declaration, e: &mechanism_codegen::Error) -> syn::Error {
    decl.error_at(ast::location(e), &ast::message(e))
}

/// Emits bodies for one model.
struct Bodies<'a> {
    model: &'a Model,
    krate: &'a TokenStream,
}

impl Bodies<'_> {
    /// How the emitted code reads each symbol: parameters from `self`, coordinates and
    /// rates from `q` and `qd`, time from `t`. Real functions call the runtime crate's `math`
    /// module (`sin_cos` is the function the interpreter, `Tape`, uses; the others exist
    /// without std, where the f64 methods do not).
    fn bindings(&self) -> EmitBindings {
        let model = self.model;
        let arena = &model.arena;
        let krate = self.krate;
        let mut b = EmitBindings::new();
        b.set_prefix("v");
        b.set_math(quote!(#krate::math));
        for (i, c) in model.coordinates.iter().enumerate() {
            if let Some(s) = arena.as_symbol(c.q) {
                b.bind(s, quote!(q[#i]));
            }
            if let Some(s) = arena.as_symbol(c.qd) {
                b.bind(s, quote!(qd[#i]));
            }
        }
        for p in &model.parameters {
            let field = Ident::new(&p.name, Span::call_site());
            if let Some(s) = arena.as_symbol(p.symbol) {
                b.bind(s, quote!(self.#field));
            }
        }
        if let Some(s) = arena.as_symbol(model.time) {
            b.bind(s, quote!(t));
        }
        b
    }

    /// A body returning one nalgebra matrix (or vector) of the shape of `m`.
    fn matrix(&self, m: &Matrix) -> mechanism_codegen::Result<TokenStream> {
        let program = Program::new(&self.model.arena, &[m])?;
        let targets = [OutputTarget::Matrix {
            name: quote!(out),
            zeroed: true,
        }];
        let body = emit_body(&program, &self.bindings(), &targets)?.tokens;
        let (r, c, krate) = (m.rows(), m.cols(), self.krate);
        let mutable = if body.is_empty() {
            quote!()
        } else {
            quote!(mut)
        };
        Ok(quote! {
            let #mutable out = #krate::__private::SMatrix::<f64, #r, #c>::zeros();
            #body
            out
        })
    }

    /// The drawn points' x, y, z into the slice `out` (3 per point, in drawing order),
    /// after a length check so that the constant indices cannot panic.
    fn draw_points(&self) -> mechanism_codegen::Result<TokenStream> {
        let points = &self.model.drawing.points;
        if points.is_empty() {
            return Ok(quote!(let _ = (t, q, out);));
        }
        let column = Matrix::column(points.iter().flat_map(|p| p.position).collect());
        let program = Program::new(&self.model.arena, &[&column])?;
        let targets = [OutputTarget::Vector {
            name: quote!(out),
            zeroed: false,
        }];
        let body = emit_body(&program, &self.bindings(), &targets)?.tokens;
        let len = 3 * points.len();
        Ok(quote! {
            let _ = (t, q);
            if out.len() < #len {
                return;
            }
            #body
        })
    }

    /// A body returning the single entry of a 1 x 1 `m`.
    fn scalar(&self, m: &Matrix) -> mechanism_codegen::Result<TokenStream> {
        let program = Program::new(&self.model.arena, &[m])?;
        Ok(emit_body(&program, &self.bindings(), &[OutputTarget::Return])?.tokens)
    }

    /// The combined evaluation: one program for all outputs.
    fn evaluate(&self, e: &Equations) -> mechanism_codegen::Result<TokenStream> {
        let outputs = e.evaluation_outputs();
        let outputs: Vec<&Matrix> = outputs.iter().collect();
        let program = Program::new(&self.model.arena, &outputs)?;
        let place = |name: TokenStream| OutputTarget::Matrix { name, zeroed: true };
        let targets: Vec<OutputTarget> = EvaluationOutput::ORDER
            .iter()
            .map(|o| match o {
                EvaluationOutput::Mass => place(quote!(out.mass)),
                EvaluationOutput::CoriolisForces => place(quote!(out.coriolis)),
                EvaluationOutput::Gravity => place(quote!(out.gravity)),
                EvaluationOutput::Forces => place(quote!(out.forces)),
                EvaluationOutput::Phi => place(quote!(out.phi)),
                EvaluationOutput::PhiQ => place(quote!(out.phi_q)),
                EvaluationOutput::PhiT => place(quote!(out.phi_t)),
                EvaluationOutput::Gamma => place(quote!(out.gamma)),
                EvaluationOutput::Kinetic => OutputTarget::Vector {
                    name: quote!(kinetic),
                    zeroed: true,
                },
                EvaluationOutput::Potential => OutputTarget::Vector {
                    name: quote!(potential),
                    zeroed: true,
                },
            })
            .collect();
        let body = emit_body(&program, &self.bindings(), &targets)?.tokens;
        let (n, m, krate) = (e.n, e.m, self.krate);
        let sm = quote!(#krate::__private::SMatrix);
        Ok(quote! {
            let mut out = #krate::StaticEvaluation::<#n, #m> {
                mass: #sm::<f64, #n, #n>::zeros(),
                coriolis: #sm::<f64, #n, 1>::zeros(),
                gravity: #sm::<f64, #n, 1>::zeros(),
                forces: #sm::<f64, #n, 1>::zeros(),
                phi: #sm::<f64, #m, 1>::zeros(),
                phi_q: #sm::<f64, #m, #n>::zeros(),
                phi_t: #sm::<f64, #m, 1>::zeros(),
                gamma: #sm::<f64, #m, 1>::zeros(),
                kinetic: 0.0,
                potential: 0.0,
            };
            let mut kinetic = [0.0_f64; 1];
            let mut potential = [0.0_f64; 1];
            #body
            out.kinetic = kinetic[0];
            out.potential = potential[0];
            out
        })
    }

    /// `Some((K, D))` with K = dF/dq and D = dF/dq' (one program for both); q'' is read
    /// from `qdd`, the multipliers from `lambda`.
    fn tangent(&self, tangent: &ResidualTangent) -> mechanism_codegen::Result<TokenStream> {
        let arena = &self.model.arena;
        let mut bindings = self.bindings();
        for (i, c) in self.model.coordinates.iter().enumerate() {
            if let Some(s) = arena.as_symbol(c.qdd) {
                bindings.bind(s, quote!(qdd[#i]));
            }
        }
        for (k, &s) in tangent.lambda.iter().enumerate() {
            bindings.bind(s, quote!(lambda[#k]));
        }
        let program = Program::new(arena, &[&tangent.stiffness, &tangent.damping])?;
        let place = |name: TokenStream| OutputTarget::Matrix { name, zeroed: true };
        let targets = [place(quote!(stiffness)), place(quote!(damping))];
        let body = emit_body(&program, &bindings, &targets)?.tokens;
        let (n, krate) = (tangent.stiffness.rows(), self.krate);
        Ok(quote! {
            let mut stiffness = #krate::__private::SMatrix::<f64, #n, #n>::zeros();
            let mut damping = #krate::__private::SMatrix::<f64, #n, #n>::zeros();
            #body
            ::core::option::Option::Some((stiffness, damping))
        })
    }
}
