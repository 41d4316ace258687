//! The derivative methods of the emitted `impl Mechanism`: the inverse dynamics'
//! derivatives by the motion (`inverse_dynamics_derivatives`) and by the parameters
//! (`inverse_dynamics_parameter_derivatives`), and the constraint rows' tangent
//! (`constraint_tangent`), and the forward dynamics' derivatives
//! (`forward_dynamics_derivatives`, one program with q'' and M's factorisation inside), each
//! from its role's program. The trait's defaults build the constrained dynamics'
//! derivatives on them.

use mechanism_codegen::{OutputTarget, Role, emit_body};
use proc_macro2::TokenStream;
use quote::quote;

use crate::dispatch::Method;
use crate::generate::{Bodies, DerivativeBodies, TANGENT_INSTRUCTIONS_MAX};

impl Bodies<'_> {
    /// `(dtau/dq, dtau/dq')`, n x n each, one program; q'' read from `qdd`.
    pub(crate) fn inverse_dynamics_derivatives(
        &self,
        n: usize,
    ) -> mechanism_codegen::Result<Option<TokenStream>> {
        if self.too_large(Role::InverseDynamicsDerivatives)? {
            return Ok(None);
        }
        self.tuple(
            Role::InverseDynamicsDerivatives,
            &[(quote!(position), n, n), (quote!(velocity), n, n)],
        )
        .map(Some)
    }

    /// `Some((dq''/dq, dq''/dq', M^-1))` from one program (q'' and the factorisation of M
    /// over its pattern inside it) when every pivot of M = L^T D L is finite and above
    /// 1e-14 of its diagonal entry (as `forward_dynamics`) and every entry is finite, else
    /// `None`; no body (the trait's default, a dense factorisation at run time) for a
    /// mechanism without the routine or past [`TANGENT_INSTRUCTIONS_MAX`].
    pub(crate) fn forward_dynamics_derivatives(
        &self,
        n: usize,
    ) -> mechanism_codegen::Result<Option<TokenStream>> {
        let role = Role::ForwardDynamicsDerivatives;
        if self.routines.get(role).is_none() || self.too_large(role)? {
            return Ok(None);
        }
        let program = self.routines.program(role)?;
        let names = [
            quote!(dq),
            quote!(dqd),
            quote!(inverse),
            quote!(pivots),
            quote!(diagonal),
        ];
        let body = self.named_outputs(role, program, &names)?;
        let (krate, cache) = (self.krate, self.cache_read(program));
        let m = quote!(#krate::__private::SMatrix::<f64, #n, #n>);
        let v = quote!(#krate::__private::SVector::<f64, #n>);
        let definite = Self::definite_pivots(quote!(1e-14));
        Ok(Some(quote! {
            let _ = t;
            #cache
            let mut dq = #m::zeros();
            let mut dqd = #m::zeros();
            let mut inverse = #m::zeros();
            let mut pivots = #v::zeros();
            let mut diagonal = #v::zeros();
            #body
            #definite
            let finite = [&dq, &dqd, &inverse]
                .iter()
                .all(|x| x.iter().fold(true, |ok, v| ok & v.is_finite()));
            (definite && finite).then_some((dq, dqd, inverse))
        }))
    }

    /// Whether the program of `role` is past [`TANGENT_INSTRUCTIONS_MAX`].
    fn too_large(&self, role: Role) -> mechanism_codegen::Result<bool> {
        let program = self.routines.program(role)?;
        Ok(program.instructions().len() > TANGENT_INSTRUCTIONS_MAX)
    }

    /// `(D, R_q, R_q')`, m x n each, one program.
    pub(crate) fn constraint_tangent(
        &self,
        n: usize,
        m: usize,
    ) -> mechanism_codegen::Result<Option<TokenStream>> {
        if self.too_large(Role::ConstraintTangent)? {
            return Ok(None);
        }
        let body = self.tuple(
            Role::ConstraintTangent,
            &[
                (quote!(velocity), m, n),
                (quote!(stiffness), m, n),
                (quote!(damping), m, n),
            ],
        )?;
        Ok(Some(quote!(::core::option::Option::Some({ #body }))))
    }

    /// dtau/dp into the column-major slice `out` (n x p, p the parameters), after a check of
    /// its length (false, nothing written, when it differs) and zeroing it.
    pub(crate) fn parameter_derivatives(&self) -> mechanism_codegen::Result<Option<TokenStream>> {
        if self.too_large(Role::ParameterDerivatives)? {
            return Ok(None);
        }
        let (program, bindings) = self.routine(Role::ParameterDerivatives)?;
        let targets = [OutputTarget::ColumnMajor { name: quote!(out) }];
        let body = emit_body(program, &bindings, &targets)?.tokens;
        let output = &program.outputs()[0];
        let len = output.rows * output.cols;
        let cache = self.cache_read(program);
        Ok(Some(quote! {
            let _ = (t, q, qd, qdd);
            if out.len() != #len {
                return false;
            }
            for x in out.iter_mut() {
                *x = 0.0;
            }
            #cache
            #body
            true
        }))
    }
}

/// `inverse_dynamics_derivatives`, `inverse_dynamics_parameter_derivatives` and
/// `constraint_tangent`, each compiled for the CPU's instruction set like the others
/// ([`crate::dispatch`]).
pub fn methods(krate: &TokenStream, n: usize, m: usize, d: &DerivativeBodies) -> Vec<Method> {
    let sv = quote!(&#krate::__private::SVector<f64, #n>);
    let sm = |r: usize| quote!(#krate::__private::SMatrix<f64, #r, #n>);
    let (smn, smm) = (sm(n), sm(m));
    let motion = [
        ("t", quote!(f64)),
        ("q", sv.clone()),
        ("qd", sv.clone()),
        ("qdd", sv.clone()),
    ];
    let mut with_out = motion.to_vec();
    with_out.push(("out", quote!(&mut [f64])));
    let mut methods = Vec::new();
    if let Some(body) = &d.inverse_dynamics {
        methods.push(Method::new(
            "inverse_dynamics_derivatives",
            &motion,
            quote!(-> (#smn, #smn)),
            body.clone(),
        ));
    }
    if let Some(body) = &d.forward_dynamics {
        let effort = [
            ("t", quote!(f64)),
            ("q", sv.clone()),
            ("qd", sv.clone()),
            ("effort", sv.clone()),
        ];
        methods.push(Method::new(
            "forward_dynamics_derivatives",
            &effort,
            quote!(-> ::core::option::Option<(#smn, #smn, #smn)>),
            body.clone(),
        ));
    }
    if let Some(body) = &d.parameters {
        methods.push(Method::new(
            "inverse_dynamics_parameter_derivatives",
            &with_out,
            quote!(-> bool),
            body.clone(),
        ));
    }
    if let Some(body) = &d.constraint_tangent {
        methods.push(Method::new(
            "constraint_tangent",
            &motion,
            quote!(-> ::core::option::Option<(#smm, #smm, #smm)>),
            body.clone(),
        ));
    }
    methods
}

/// The body of `residual_tangent`: `tangent` (its own program), or a call of the body of
/// `inverse_dynamics_derivatives` (same instruction set) where the two programs are one.
pub fn residual_tangent_body(tangent: &TokenStream, d: &DerivativeBodies) -> TokenStream {
    if d.tangent_is_inverse_dynamics && d.inverse_dynamics.is_some() {
        quote! {
            let _ = lambda;
            ::core::option::Option::Some(self.__inverse_dynamics_derivatives(isa, t, q, qd, qdd))
        }
    } else {
        tangent.clone()
    }
}
