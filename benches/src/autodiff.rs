//! Baseline (b): the runtime automatic-differentiation route, as a user without code
//! generation would write it.
//!
//! The user writes T(q, q'), Pi(q) and Phi(q) once, as generic Rust over num-dual's
//! [`DualNum`], and differentiates them numerically-exactly at every call:
//!
//! ```text
//! M_ij   = d2T/dq'_i dq'_j                    HyperDual, eps1 on q'_i, eps2 on q'_j (i <= j)
//! C q'   = (d/dq dT/dq') q' - dT/dq           HyperDual, eps1 on q'_i, eps2 along q' in q;
//!                                             Dual for dT/dq_i
//! g      = dPi/dq                             Dual, one pass per coordinate
//! Phi_q  = dPhi/dq                            Dual, one pass per column
//! gamma  = -(q'^T Hess(Phi_r) q')_r           HyperDual, eps1 = eps2 = q' (one pass)
//! ```
//!
//! (C q' = d/dt(dT/dq') - M q'' - dT/dq: the q''-free part of the Lagrange operator.)
//! That is N(N+1)/2 + 2N evaluations of T per call, each O(N) for the chain: the cost a
//! generic AD user pays. [`AutoDiff`] wraps such a model as a [`mechanism::System`], so the
//! same augmented solve and integrators run on it.

use mechanism::nalgebra::DMatrix;
use mechanism::{Evaluation, Kinematic, ParameterError, System, SystemInfo};
use num_dual::{Dual64, DualNum, HyperDual64};

/// A mechanism written by hand as generic functions of dual numbers: `N` coordinates, `M`
/// constraint rows, scleronomic constraints (Phi_t = 0).
pub trait AdModel<const N: usize, const M: usize>: Send + Sync {
    /// Builds the model from named parameter values (the compiled mechanism's defaults).
    fn from_parameters(names: &[String], values: &[f64]) -> Self
    where
        Self: Sized;
    /// Kinetic energy T(q, q').
    fn kinetic<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; N], qd: &[D; N]) -> D;
    /// Potential energy Pi(q).
    fn potential<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; N]) -> D;
    /// Constraints Phi(q).
    fn constraints<D: DualNum<Primitive = f64> + Copy>(&self, q: &[D; N]) -> [D; M];
    /// Applied generalised forces tau(t, q, q') (plain f64: no derivative needed).
    fn forces(&self, _t: f64, _q: &[f64; N], _qd: &[f64; N]) -> [f64; N] {
        [0.0; N]
    }
}

/// Looks up parameter `name` in (names, values); NaN when absent (caught by the solvers).
pub fn parameter(names: &[String], values: &[f64], name: &str) -> f64 {
    names
        .iter()
        .position(|n| n == name)
        .map_or(f64::NAN, |i| values[i])
}

fn lift<D: DualNum<Primitive = f64> + Copy, const N: usize>(
    x: &[f64],
    f: impl Fn(f64) -> D,
) -> [D; N] {
    std::array::from_fn(|i| f(x[i]))
}

fn hd(re: f64) -> HyperDual64 {
    HyperDual64::from_re(re)
}

/// The AD route as a [`System`]: every quantity recomputed by dual numbers at each call.
pub struct AutoDiff<A, const N: usize, const M: usize> {
    model: A,
    info: SystemInfo,
    values: Vec<f64>,
}

impl<A: AdModel<N, M>, const N: usize, const M: usize> AutoDiff<A, N, M> {
    /// The AD route with the names, guesses, independents and parameter values of
    /// `reference` (the compiled mechanism it mirrors).
    pub fn like(reference: &dyn System) -> Self {
        let info = reference.info().clone();
        let mut values = vec![0.0; info.parameters.len()];
        reference.parameter_values(&mut values);
        assert_eq!(
            (info.n(), info.m()),
            (N, M),
            "AD model size differs from {}",
            info.name
        );
        Self {
            model: A::from_parameters(&info.parameters, &values),
            info,
            values,
        }
    }

    /// M(q) = d2T/dq'dq' by hyper-dual numbers, one pass per entry of the upper triangle.
    pub fn mass(&self, q: &[f64; N], qd: &[f64; N], out: &mut DMatrix<f64>) {
        let qh: [HyperDual64; N] = lift(q, hd);
        for i in 0..N {
            for j in i..N {
                let mut v: [HyperDual64; N] = lift(qd, hd);
                v[i].eps1 = 1.0;
                v[j].eps2 = 1.0;
                let m = self.model.kinetic(&qh, &v).eps1eps2;
                out[(i, j)] = m;
                out[(j, i)] = m;
            }
        }
    }

    /// C(q, q') q' = (d2T/dq'dq) q' - dT/dq.
    pub fn coriolis(&self, q: &[f64; N], qd: &[f64; N], out: &mut [f64]) {
        let qh: [HyperDual64; N] = std::array::from_fn(|k| HyperDual64::new(q[k], 0.0, qd[k], 0.0));
        for (i, o) in out.iter_mut().enumerate() {
            let mut v: [HyperDual64; N] = lift(qd, hd);
            v[i].eps1 = 1.0;
            *o = self.model.kinetic(&qh, &v).eps1eps2;
        }
        let vd: [Dual64; N] = lift(qd, Dual64::from_re);
        for (i, o) in out.iter_mut().enumerate() {
            let mut x: [Dual64; N] = lift(q, Dual64::from_re);
            x[i].eps = 1.0;
            *o -= self.model.kinetic(&x, &vd).eps;
        }
    }

    /// g(q) = dPi/dq.
    pub fn gravity(&self, q: &[f64; N], out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            let mut x: [Dual64; N] = lift(q, Dual64::from_re);
            x[i].eps = 1.0;
            *o = self.model.potential(&x).eps;
        }
    }

    /// Phi_q by one dual pass per column.
    pub fn jacobian(&self, q: &[f64; N], out: &mut DMatrix<f64>) {
        for j in 0..N {
            let mut x: [Dual64; N] = lift(q, Dual64::from_re);
            x[j].eps = 1.0;
            for (r, v) in self.model.constraints(&x).iter().enumerate() {
                out[(r, j)] = v.eps;
            }
        }
    }

    /// gamma = -(dPhi_q/dq)(q' kron q'), i.e. minus the second directional derivative of Phi
    /// along q'.
    pub fn gamma(&self, q: &[f64; N], qd: &[f64; N], out: &mut [f64]) {
        let x: [HyperDual64; N] =
            std::array::from_fn(|k| HyperDual64::new(q[k], qd[k], qd[k], 0.0));
        for (o, v) in out.iter_mut().zip(self.model.constraints(&x)) {
            *o = -v.eps1eps2;
        }
    }
}

fn fixed<const N: usize>(x: &[f64]) -> [f64; N] {
    std::array::from_fn(|i| x[i])
}

impl<A: AdModel<N, M>, const N: usize, const M: usize> Kinematic for AutoDiff<A, N, M> {
    fn info(&self) -> &SystemInfo {
        &self.info
    }
    fn constraints(&self, _t: f64, q: &[f64], phi: &mut [f64]) {
        phi.copy_from_slice(&self.model.constraints(&fixed::<N>(q)));
    }
    fn constraint_jacobian(&self, _t: f64, q: &[f64], phi_q: &mut DMatrix<f64>, phi_t: &mut [f64]) {
        self.jacobian(&fixed::<N>(q), phi_q);
        phi_t.fill(0.0);
    }
}

impl<A: AdModel<N, M>, const N: usize, const M: usize> System for AutoDiff<A, N, M> {
    fn parameter_values(&self, out: &mut [f64]) {
        out.copy_from_slice(&self.values);
    }
    fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError> {
        let count = self.values.len();
        if index >= count {
            return Err(ParameterError::NoSuchParameter { index, count });
        }
        self.values[index] = value;
        self.model = A::from_parameters(&self.info.parameters, &self.values);
        Ok(())
    }
    fn evaluate(&self, t: f64, q: &[f64], qd: &[f64], out: &mut Evaluation) {
        let (q, qd) = (fixed::<N>(q), fixed::<N>(qd));
        self.mass(&q, &qd, &mut out.mass);
        self.coriolis(&q, &qd, out.coriolis.as_mut_slice());
        self.gravity(&q, out.gravity.as_mut_slice());
        out.forces
            .as_mut_slice()
            .copy_from_slice(&self.model.forces(t, &q, &qd));
        out.phi
            .as_mut_slice()
            .copy_from_slice(&self.model.constraints(&q));
        self.jacobian(&q, &mut out.phi_q);
        out.phi_t.fill(0.0);
        self.gamma(&q, &qd, out.gamma.as_mut_slice());
        out.kinetic = self.model.kinetic(&q, &qd);
        out.potential = self.model.potential(&q);
    }
}
