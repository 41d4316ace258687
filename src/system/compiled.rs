//! A compiled [`Mechanism`] (static sizes) seen as a run-time [`System`].

use nalgebra::{DMatrix, Matrix3, SVector, Vector3};

use super::drawing::Drawing;
use super::dynamic::{ConstraintTangent, Evaluation, Kinematic, SolverKey, System, Tangent};
use super::info::{BodyOrientation, ConstraintRow, SystemInfo};
use super::mechanism::{Mechanism, StaticEvaluation};
use super::parameter_range::ParameterError;
use super::sparsity::Sparsity;
use crate::linalg::{FixedNullSpace, NullSpaceSolve};

/// Adapts a compiled [`Mechanism`] to the run-time [`System`] interface.
#[derive(Clone, Debug)]
pub struct Compiled<T, const N: usize, const M: usize> {
    /// The compiled mechanism (its fields are the parameters). Private: a parameter is set
    /// through [`System::set_parameter`], which keeps `info`'s initial values with it.
    mechanism: T,
    info: SystemInfo,
    /// The run-time copy of `T::SPARSITY`.
    sparsity: Option<Sparsity>,
}

impl<T: Mechanism<N, M>, const N: usize, const M: usize> Compiled<T, N, M> {
    /// Wraps `mechanism` (its cached parameter values refreshed: [`Mechanism::refresh`]),
    /// recording its names and declared data.
    pub fn new(mut mechanism: T) -> Self {
        mechanism.refresh();
        let info = SystemInfo {
            name: T::NAME.to_string(),
            coordinates: T::COORDINATES.iter().map(|s| s.to_string()).collect(),
            parameters: T::PARAMETERS.iter().map(|s| s.to_string()).collect(),
            parameter_ranges: (0..T::PARAMETERS.len())
                .map(|k| T::PARAMETER_RANGES.get(k).copied().unwrap_or_default())
                .collect(),
            initial_guess: mechanism.initial_guess().to_vec(),
            independent: (0..T::INDEPENDENT.len())
                .filter_map(|k| mechanism.independent(k))
                .collect(),
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
            velocity_rows: T::VELOCITY_ROWS,
            // `mechanism!` refuses a T or Pi with t in it (the trait's `mass_matrix(q)`,
            // `gravity(q)`, `kinetic_energy(q, q')` take no time).
            energy_depends_on_time: false,
            drawing: Drawing::from_static(T::DRAW_POINTS, T::DRAW_LINES, T::DRAW_TRACES),
            orientations: (T::ORIENTATIONS.iter())
                .map(|&(body, factors)| BodyOrientation {
                    body: body.to_string(),
                    factors: factors.to_vec(),
                })
                .collect(),
            joint_limits: T::JOINT_LIMITS.to_vec(),
            frames: T::FRAMES.iter().map(|s| s.to_string()).collect(),
        };
        let sparsity = T::SPARSITY.map(|s| Sparsity::from_static(N, M, &s));
        Self {
            mechanism,
            info,
            sparsity,
        }
    }

    /// The compiled mechanism, with the parameters as set.
    pub fn mechanism(&self) -> &T {
        &self.mechanism
    }

    /// The compiled mechanism, given back.
    pub fn into_inner(self) -> T {
        self.mechanism
    }
}

/// Entries of M and Phi_q together above which [`Compiled`] evaluates through
/// [`Mechanism::evaluate_sparse_into`] (no zeroing or copying of the dense matrices) rather
/// than `evaluate_into` and a copy: a 20 x 20 system's copy is already larger than its
/// evaluation's nonzeros.
const SPARSE_ABOVE: usize = 400;

fn to_static<const N: usize>(x: &[f64]) -> SVector<f64, N> {
    SVector::<f64, N>::from_fn(|i, _| x[i])
}

impl<T: Mechanism<N, M>, const N: usize, const M: usize> Kinematic for Compiled<T, N, M> {
    fn info(&self) -> &SystemInfo {
        &self.info
    }
    fn constraints(&self, t: f64, q: &[f64], phi: &mut [f64]) {
        let p = self.mechanism.constraints(t, &to_static(q));
        phi.copy_from_slice(p.as_slice());
    }
    fn constraint_jacobian(&self, t: f64, q: &[f64], phi_q: &mut DMatrix<f64>, phi_t: &mut [f64]) {
        let qs = to_static(q);
        if N * M > SPARSE_ABOVE
            && self.sparsity.is_some()
            && self
                .mechanism
                .constraint_jacobian_sparse_into(t, &qs, phi_q.as_mut_slice(), phi_t)
        {
            return;
        }
        phi_q.copy_from(&self.mechanism.constraint_jacobian(t, &qs));
        phi_t.copy_from_slice(self.mechanism.constraint_time_derivative(t, &qs).as_slice());
    }
}

impl<T: Mechanism<N, M>, const N: usize, const M: usize> System for Compiled<T, N, M> {
    fn parameter_values(&self, out: &mut [f64]) {
        for (i, o) in out.iter_mut().enumerate() {
            *o = self.mechanism.parameter(i).unwrap_or(f64::NAN);
        }
    }
    fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError> {
        self.mechanism.set_parameter(index, value)?;
        self.info.initial_guess = self.mechanism.initial_guess().to_vec();
        for (k, entry) in self.info.independent.iter_mut().enumerate() {
            if let Some(now) = self.mechanism.independent(k) {
                *entry = now;
            }
        }
        Ok(())
    }
    fn evaluate(&self, t: f64, q: &[f64], qd: &[f64], out: &mut Evaluation) {
        // With a pattern, M and Phi_q of a large mechanism are written in place at their
        // nonzeros only; a small one takes `evaluate_into` (its AVX2 copy) and the copy.
        if N * (N + M) > SPARSE_ABOVE
            && self.sparsity.is_some()
            && self.mechanism.evaluate_sparse_into(
                t,
                &to_static(q),
                &to_static(qd),
                &mut out.slices(),
            )
        {
            return;
        }
        let mut e = StaticEvaluation::<N, M>::zeros();
        self.mechanism
            .evaluate_into(t, &to_static(q), &to_static(qd), &mut e);
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
    fn sparsity(&self) -> Option<&Sparsity> {
        self.sparsity.as_ref()
    }
    fn null_space_solver(&self, _: SolverKey) -> Option<Box<dyn NullSpaceSolve>> {
        Some(Box::new(FixedNullSpace::<N, M>::default()))
    }
    fn draw_points(&self, t: f64, q: &[f64], out: &mut [f64]) {
        self.mechanism.draw_points(t, &to_static(q), out);
    }
    fn inverse_dynamics(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) -> Option<()> {
        let u = self
            .mechanism
            .inverse_dynamics(t, &to_static(q), &to_static(qd), &to_static(qdd));
        out.copy_from_slice(u.as_slice());
        Some(())
    }
    fn frame_placement(
        &self,
        frame: usize,
        q: &[f64],
        rotation: &mut Matrix3<f64>,
        position: &mut Vector3<f64>,
    ) -> Option<()> {
        let (r, p) = self.mechanism.frame_placement(frame, &to_static(q))?;
        *rotation = r;
        *position = p;
        Some(())
    }
    fn frame_jacobian(&self, frame: usize, q: &[f64], out: &mut DMatrix<f64>) -> Option<()> {
        out.copy_from(&self.mechanism.frame_jacobian(frame, &to_static(q))?);
        Some(())
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
    fn constraint_tangent(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut ConstraintTangent,
    ) -> Option<()> {
        let (velocity, stiffness, damping) =
            self.mechanism
                .constraint_tangent(t, &to_static(q), &to_static(qd), &to_static(qdd))?;
        out.velocity.copy_from(&velocity);
        out.stiffness.copy_from(&stiffness);
        out.damping.copy_from(&damping);
        Some(())
    }
    fn inverse_dynamics_derivatives(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut Tangent,
    ) -> Option<()> {
        let (dq, dqd) = self.mechanism.inverse_dynamics_derivatives(
            t,
            &to_static(q),
            &to_static(qd),
            &to_static(qdd),
        );
        out.stiffness.copy_from(&dq);
        out.damping.copy_from(&dqd);
        Some(())
    }
    fn parameter_derivatives(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut DMatrix<f64>,
    ) -> Option<()> {
        // A DMatrix stores its entries column-major, the layout the method writes.
        self.mechanism
            .inverse_dynamics_parameter_derivatives(
                t,
                &to_static(q),
                &to_static(qd),
                &to_static(qdd),
                out.as_mut_slice(),
            )
            .then_some(())
    }
}
