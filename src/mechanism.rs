//! The two faces of a mechanism.
//!
//! - [`Mechanism`] is what `mechanism!` emits: static sizes (`N` coordinates, `M` constraint
//!   rows), specialised allocation-free code, one method per derived quantity.
//! - [`System`] is what the solvers consume: object-safe, sizes known at run time, results
//!   written into a caller-owned [`Evaluation`] so the step loop never allocates. A compiled
//!   mechanism becomes a `System` through [`Compiled`]; a `.mech` file read at run time is a
//!   `System` through the interpreter route.
//!
//! Equations (seed eq. 3, Van Khang 2011), with q the N redundant coordinates:
//!
//! ```text
//! M(q) q'' + C(q, q') q' + g(q) + Phi_q(q, t)^T lambda = tau(t, q, q'),   Phi(q, t) = 0
//! Phi_q q'' = gamma = -(dPhi_q/dq)(q' kron q') - 2 Phi_qt q' - Phi_tt
//! ```

use nalgebra::{DMatrix, DVector, SMatrix, SVector};

/// One coordinate the user sets directly (`independent { phi = 0.0; der(phi) = 2*pi; }`):
/// its index in q, its position and its rate at t = 0.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Independent {
    /// Index of the coordinate in q.
    pub coordinate: usize,
    /// Prescribed position q_k(0).
    pub position: f64,
    /// Prescribed rate q_k'(0) (0 when the declaration gives none).
    pub velocity: f64,
}

/// Everything the solver needs at one (t, q, q'), evaluated together so that sin, cos and
/// common subexpressions are computed once.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticEvaluation<const N: usize, const M: usize> {
    /// Mass matrix M(q) = d2T/dq'dq'.
    pub mass: SMatrix<f64, N, N>,
    /// Velocity-dependent forces C(q, q') q'.
    pub coriolis: SVector<f64, N>,
    /// Conservative forces g(q) = dPi/dq.
    pub gravity: SVector<f64, N>,
    /// Applied generalised forces tau(t, q, q').
    pub forces: SVector<f64, N>,
    /// Constraint residuals Phi(q, t).
    pub phi: SVector<f64, M>,
    /// Constraint Jacobian Phi_q (M x N).
    pub phi_q: SMatrix<f64, M, N>,
    /// Explicit time derivative Phi_t.
    pub phi_t: SVector<f64, M>,
    /// Acceleration right-hand side gamma, with Phi_q q'' = gamma.
    pub gamma: SVector<f64, M>,
    /// Kinetic energy T(q, q').
    pub kinetic: f64,
    /// Potential energy Pi(q).
    pub potential: f64,
}

/// A mechanism with derived equations and static sizes: `N` coordinates, `M` constraint rows.
///
/// Implemented by the code `mechanism!` emits. Every method is allocation-free.
pub trait Mechanism<const N: usize, const M: usize>: Clone + Send + Sync + 'static {
    /// Name of the mechanism (the struct name).
    const NAME: &'static str;
    /// Coordinate names, in the order of q.
    const COORDINATES: [&'static str; N];
    /// Parameter names, in declaration order.
    const PARAMETERS: &'static [&'static str];
    /// Declared initial guesses for q (the start of the assembly Newton iteration).
    const INITIAL_GUESS: [f64; N];
    /// The independent coordinates and their initial values.
    const INDEPENDENT: &'static [Independent];
    /// The joint and the component of each constraint row, in row order (see
    /// [`ConstraintRow`]): `("revolute(B1, B2, z, z)", "y")`, `("constraint 2", "")`. Empty
    /// for hand-written impls ([`Compiled::new`] then names the rows `row 1`, `row 2`, ..).
    const CONSTRAINT_ROWS: &'static [(&'static str, &'static str)] = &[];

    /// Value of parameter `index` (declaration order), or `None` out of range.
    fn parameter(&self, index: usize) -> Option<f64>;
    /// Sets parameter `index`; returns false when out of range.
    fn set_parameter(&mut self, index: usize, value: f64) -> bool;
    /// M(q) = d2T/dq'dq'.
    fn mass_matrix(&self, q: &SVector<f64, N>) -> SMatrix<f64, N, N>;
    /// Khang's C(q, q') = (dM/dq)(I_n kron q') - 1/2 [(dM/dq)(q' kron I_n)]^T.
    fn coriolis_matrix(&self, q: &SVector<f64, N>, qd: &SVector<f64, N>) -> SMatrix<f64, N, N>;
    /// C(q, q') q'.
    fn coriolis_forces(&self, q: &SVector<f64, N>, qd: &SVector<f64, N>) -> SVector<f64, N>;
    /// g(q) = dPi/dq.
    fn gravity(&self, q: &SVector<f64, N>) -> SVector<f64, N>;
    /// tau(t, q, q').
    fn generalized_forces(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
    ) -> SVector<f64, N>;
    /// Phi(q, t).
    fn constraints(&self, t: f64, q: &SVector<f64, N>) -> SVector<f64, M>;
    /// Phi_q(q, t).
    fn constraint_jacobian(&self, t: f64, q: &SVector<f64, N>) -> SMatrix<f64, M, N>;
    /// Phi_t(q, t) = dPhi/dt at fixed q (zero for scleronomic constraints).
    fn constraint_time_derivative(&self, t: f64, q: &SVector<f64, N>) -> SVector<f64, M>;
    /// gamma(t, q, q') = -(dPhi_q/dq)(q' kron q') - 2 Phi_qt q' - Phi_tt.
    fn constraint_gamma(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
    ) -> SVector<f64, M>;
    /// T(q, q').
    fn kinetic_energy(&self, q: &SVector<f64, N>, qd: &SVector<f64, N>) -> f64;
    /// Pi(q).
    fn potential_energy(&self, q: &SVector<f64, N>) -> f64;
    /// All of the above at one (t, q, q'), sharing sin, cos and common subexpressions.
    fn evaluate(&self, t: f64, q: &SVector<f64, N>, qd: &SVector<f64, N>)
    -> StaticEvaluation<N, M>;
    /// The derived equations as readable text (what the snapshot tests pin).
    fn equations() -> &'static str;

    /// K = dF/dq and D = dF/dq' of the residual F = M q'' + C q' + g - tau + Phi_q^T lambda,
    /// derived symbolically (exact Jacobians for implicit integrators); `None` when the
    /// mechanism does not provide them.
    fn residual_tangent(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qd: &SVector<f64, N>,
        qdd: &SVector<f64, N>,
        lambda: &SVector<f64, M>,
    ) -> Option<(SMatrix<f64, N, N>, SMatrix<f64, N, N>)> {
        let _ = (t, q, qd, qdd, lambda);
        None
    }
}

/// Caller-owned buffers for one evaluation of a [`System`] (sizes n and m fixed at creation).
#[derive(Clone, Debug, PartialEq)]
pub struct Evaluation {
    /// Mass matrix M(q), n x n.
    pub mass: DMatrix<f64>,
    /// C(q, q') q'.
    pub coriolis: DVector<f64>,
    /// g(q) = dPi/dq.
    pub gravity: DVector<f64>,
    /// tau(t, q, q').
    pub forces: DVector<f64>,
    /// Phi(q, t), length m.
    pub phi: DVector<f64>,
    /// Phi_q, m x n.
    pub phi_q: DMatrix<f64>,
    /// Phi_t, length m.
    pub phi_t: DVector<f64>,
    /// gamma, length m.
    pub gamma: DVector<f64>,
    /// T(q, q').
    pub kinetic: f64,
    /// Pi(q).
    pub potential: f64,
}

impl Evaluation {
    /// Zeroed buffers for n coordinates and m constraint rows.
    pub fn zeros(n: usize, m: usize) -> Self {
        Self {
            mass: DMatrix::zeros(n, n),
            coriolis: DVector::zeros(n),
            gravity: DVector::zeros(n),
            forces: DVector::zeros(n),
            phi: DVector::zeros(m),
            phi_q: DMatrix::zeros(m, n),
            phi_t: DVector::zeros(m),
            gamma: DVector::zeros(m),
            kinetic: 0.0,
            potential: 0.0,
        }
    }
}

/// Where one scalar constraint row comes from: the statement that declared it and which of
/// its rows it is. Lets the runtime name a row (`revolute(B1, B2, z, z) y`) and the joints
/// that share a redundant part of the multipliers.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstraintRow {
    /// The statement, as the user reads it: the joint as written (`revolute(B1, B2, z, z)`,
    /// `spherical(C2, C)`, `P = Q`, `P.z = 0`) or `constraint k` for the k-th statement
    /// (1-based) of `constraints { .. }`; `row k` when the mechanism does not say.
    pub joint: String,
    /// Which row of the statement: `x`, `y`, `z` (point rows, vector equations), `axis 1`,
    /// `axis 2` (parallel axes of `revolute` and `prismatic`), `slide 1`, `slide 2`, `twist`
    /// (the other rows of `prismatic`), `1`, `2`, .. (longer vector equations); empty for a
    /// statement of one row.
    pub component: String,
}

impl ConstraintRow {
    /// The row at 0-based index `row` when nobody named it: joint `row k` with k = `row` + 1,
    /// no component.
    pub fn unnamed(row: usize) -> Self {
        Self {
            joint: format!("row {}", row + 1),
            component: String::new(),
        }
    }

    /// The joint, then a space and the component when there is one.
    pub fn label(&self) -> String {
        if self.component.is_empty() {
            self.joint.clone()
        } else {
            format!("{} {}", self.joint, self.component)
        }
    }
}

/// Names and declared data of a system, fixed for its lifetime.
#[derive(Clone, Debug, PartialEq)]
pub struct SystemInfo {
    /// Mechanism name.
    pub name: String,
    /// Coordinate names, in the order of q.
    pub coordinates: Vec<String>,
    /// Parameter names, in declaration order.
    pub parameters: Vec<String>,
    /// Declared initial guesses for q.
    pub initial_guess: Vec<f64>,
    /// Independent coordinates and their initial values.
    pub independent: Vec<Independent>,
    /// Number of constraint rows m.
    pub constraints: usize,
    /// Where each constraint row comes from, in row order (m entries).
    pub constraint_rows: Vec<ConstraintRow>,
}

impl SystemInfo {
    /// Number of coordinates n.
    pub fn n(&self) -> usize {
        self.coordinates.len()
    }
    /// Number of constraint rows m.
    pub fn m(&self) -> usize {
        self.constraints
    }
    /// Index of the coordinate called `name`.
    pub fn coordinate_index(&self, name: &str) -> Option<usize> {
        self.coordinates.iter().position(|c| c == name)
    }
    /// Index of the parameter called `name`.
    pub fn parameter_index(&self, name: &str) -> Option<usize> {
        self.parameters.iter().position(|c| c == name)
    }
    /// The label of constraint row `row` (0-based): the joint, then a space and the
    /// component if there is one (`revolute(B1, B2, z, z) y`, `constraint 2`); `row k`
    /// (1-based) when `row` has no entry in [`SystemInfo::constraint_rows`].
    pub fn constraint_label(&self, row: usize) -> String {
        self.constraint_rows
            .get(row)
            .map_or_else(|| ConstraintRow::unnamed(row).label(), ConstraintRow::label)
    }
    /// The distinct joints of constraint rows `rows` (0-based), in order of first appearance
    /// (rows without an entry count as `row k`).
    pub fn joints_of(&self, rows: &[usize]) -> Vec<String> {
        let mut joints: Vec<String> = Vec::new();
        for &row in rows {
            let joint = self
                .constraint_rows
                .get(row)
                .map_or_else(|| ConstraintRow::unnamed(row).joint, |r| r.joint.clone());
            if !joints.contains(&joint) {
                joints.push(joint);
            }
        }
        joints
    }
}

/// The object-safe, run-time-sized view of a mechanism that the solvers use.
///
/// Every method writes into caller-owned buffers and allocates nothing.
pub trait System: Send + Sync {
    /// Names, sizes and declared data.
    fn info(&self) -> &SystemInfo;
    /// Current parameter values, in declaration order (written into `out`).
    fn parameter_values(&self, out: &mut [f64]);
    /// Sets parameter `index`; returns false when out of range.
    fn set_parameter(&mut self, index: usize, value: f64) -> bool;
    /// Everything at (t, q, q'): see [`Evaluation`].
    fn evaluate(&self, t: f64, q: &[f64], qd: &[f64], out: &mut Evaluation);
    /// Phi(q, t) into `phi` (length m).
    fn constraints(&self, t: f64, q: &[f64], phi: &mut [f64]);
    /// Phi_q (m x n) and Phi_t (m) at (q, t).
    fn constraint_jacobian(&self, t: f64, q: &[f64], phi_q: &mut DMatrix<f64>, phi_t: &mut [f64]);
    /// Exact tangent matrices of the dynamic residual
    /// F = M(q) q'' + C(q, q') q' + g(q) - tau(t, q, q') + Phi_q(q, t)^T lambda:
    /// `out.stiffness` = dF/dq and `out.damping` = dF/dq' (n x n), for the Newton iteration of
    /// implicit integrators (HHT). Returns `None` when not provided (the default); the
    /// solver then uses finite differences. `mechanism!` and [`crate::Interpreted`] provide
    /// them, derived symbolically by codegen (`residual_tangent`).
    fn tangent(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        lambda: &[f64],
        out: &mut Tangent,
    ) -> Option<()> {
        let _ = (t, q, qd, qdd, lambda, out);
        None
    }
}

/// dF/dq and dF/dq' of the dynamic residual F = M q'' + C q' + g - tau + Phi_q^T lambda
/// (see [`System::tangent`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Tangent {
    /// dF/dq, n x n ("stiffness").
    pub stiffness: DMatrix<f64>,
    /// dF/dq', n x n ("damping").
    pub damping: DMatrix<f64>,
}

impl Tangent {
    /// Zero matrices for n coordinates.
    pub fn zeros(n: usize) -> Self {
        Self {
            stiffness: DMatrix::zeros(n, n),
            damping: DMatrix::zeros(n, n),
        }
    }
}

/// Adapts a compiled [`Mechanism`] to the run-time [`System`] interface.
#[derive(Clone, Debug)]
pub struct Compiled<T, const N: usize, const M: usize> {
    /// The compiled mechanism (its fields are the parameters).
    pub mechanism: T,
    info: SystemInfo,
}

impl<T: Mechanism<N, M>, const N: usize, const M: usize> Compiled<T, N, M> {
    /// Wraps `mechanism`, recording its names and declared data.
    pub fn new(mechanism: T) -> Self {
        let info = SystemInfo {
            name: T::NAME.to_string(),
            coordinates: T::COORDINATES.iter().map(|s| s.to_string()).collect(),
            parameters: T::PARAMETERS.iter().map(|s| s.to_string()).collect(),
            initial_guess: T::INITIAL_GUESS.to_vec(),
            independent: T::INDEPENDENT.to_vec(),
            constraints: M,
            constraint_rows: (0..M)
                .map(|k| match T::CONSTRAINT_ROWS.get(k) {
                    Some(&(joint, component)) => ConstraintRow {
                        joint: joint.to_string(),
                        component: component.to_string(),
                    },
                    None => ConstraintRow::unnamed(k),
                })
                .collect(),
        };
        Self { mechanism, info }
    }
}

fn to_static<const N: usize>(x: &[f64]) -> SVector<f64, N> {
    SVector::<f64, N>::from_fn(|i, _| x[i])
}

impl<T: Mechanism<N, M>, const N: usize, const M: usize> System for Compiled<T, N, M> {
    fn info(&self) -> &SystemInfo {
        &self.info
    }
    fn parameter_values(&self, out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.mechanism.parameter(i).unwrap_or(f64::NAN);
        }
    }
    fn set_parameter(&mut self, index: usize, value: f64) -> bool {
        self.mechanism.set_parameter(index, value)
    }
    fn evaluate(&self, t: f64, q: &[f64], qd: &[f64], out: &mut Evaluation) {
        let e = self.mechanism.evaluate(t, &to_static(q), &to_static(qd));
        out.mass.copy_from(&e.mass);
        out.coriolis.copy_from(&e.coriolis);
        out.gravity.copy_from(&e.gravity);
        out.forces.copy_from(&e.forces);
        out.phi.copy_from(&e.phi);
        out.phi_q.copy_from(&e.phi_q);
        out.phi_t.copy_from(&e.phi_t);
        out.gamma.copy_from(&e.gamma);
        out.kinetic = e.kinetic;
        out.potential = e.potential;
    }
    fn constraints(&self, t: f64, q: &[f64], phi: &mut [f64]) {
        let p = self.mechanism.constraints(t, &to_static(q));
        phi.copy_from_slice(p.as_slice());
    }
    fn constraint_jacobian(&self, t: f64, q: &[f64], phi_q: &mut DMatrix<f64>, phi_t: &mut [f64]) {
        let qs = to_static(q);
        phi_q.copy_from(&self.mechanism.constraint_jacobian(t, &qs));
        phi_t.copy_from_slice(self.mechanism.constraint_time_derivative(t, &qs).as_slice());
    }
    fn tangent(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        lambda: &[f64],
        out: &mut Tangent,
    ) -> Option<()> {
        let (k, d) = self.mechanism.residual_tangent(
            t,
            &to_static(q),
            &to_static(qd),
            &to_static(qdd),
            &to_static(lambda),
        )?;
        out.stiffness.copy_from(&k);
        out.damping.copy_from(&d);
        Some(())
    }
}
