//! A floating-base robot read at run time: the routines `mechanism!` emits for
//! [`super::FloatingBase`] (`mechanism_codegen::compile_floating`: M, g, the declared
//! efforts, T, Pi and the forward dynamics, each in v), run through codegen's tapes, with
//! q of `nq` entries (position, quaternion x y z w, joints) and v of `nv` (velocity and
//! angular velocity in the root's axes, joint rates) sized at run time. What
//! `mechanism simulate robot.mech` runs for a floating declaration, with
//! [`crate::simulate_interpreted_floating`].

use mechanism_codegen::{
    Equations, Error, Model, Role, compile_floating, compile_floating_with_derivatives,
};

use crate::system::free_flyer::rotation;
use crate::system::parameters::Parameters;
use crate::system::routine::{Routine, Values};
use crate::system::{ParameterError, ParameterRange};

/// A floating-base declaration interpreted from its text (module docs).
#[derive(Clone, Debug)]
pub struct InterpretedFloating {
    name: String,
    configuration: Vec<String>,
    velocities: Vec<String>,
    parameter_names: Vec<String>,
    ranges: Vec<ParameterRange>,
    parameters: Parameters,
    /// M (nv x nv, row-major).
    mass: Routine,
    /// g(q) (nv).
    gravity: Routine,
    /// The declared efforts tau(t, q, v) (nv).
    forces: Routine,
    /// b = C v + g - tau (nv).
    bias: Routine,
    /// M a + C v + g - tau (nv).
    inverse_dynamics: Routine,
    /// T and Pi.
    kinetic: Routine,
    potential: Routine,
    /// q'' (nv), the pivots of M = L^T D L (nv) and the diagonal entries they are
    /// compared with (nv).
    forward: Routine,
    /// dtau/dq and dtau/dv (nv x nv each, row-major, one after the other), compiled by
    /// [`InterpretedFloating::for_derivatives`] only.
    derivatives: Option<Routine>,
}

impl InterpretedFloating {
    /// Parses, checks, derives and compiles the declaration `text`, whose root link is
    /// `joint = floating(..)`.
    ///
    /// # Errors
    /// A declaration or derivation error (located in `text`), or
    /// [`mechanism_codegen::error::DerivationError::FloatingBase`] for a declaration without
    /// a floating root.
    pub fn from_text(text: &str) -> Result<Self, Error> {
        let model = mechanism_codegen::parse_model_str(text)?;
        Self::from_model(model)
    }

    /// [`InterpretedFloating::from_text`] of a parsed model.
    ///
    /// # Errors
    /// As [`InterpretedFloating::from_text`].
    pub fn from_model(mut model: Model) -> Result<Self, Error> {
        let eqs = mechanism_codegen::derive(&mut model)?;
        Self::from_equations(model, eqs)
    }

    /// [`InterpretedFloating::from_text`] of a derived model.
    ///
    /// # Errors
    /// As [`InterpretedFloating::from_text`].
    pub fn from_equations(model: Model, eqs: Equations) -> Result<Self, Error> {
        Self::compiled(model, eqs, false)
    }

    /// [`InterpretedFloating::from_model`] with the derivatives of the dynamics
    /// (`compile_floating_with_derivatives`): what
    /// [`InterpretedFloating::inverse_dynamics_derivatives`] and
    /// [`crate::FloatingDerivatives`] read. Deriving them costs about as much again as the
    /// rest, so the other constructors leave them out.
    ///
    /// # Errors
    /// As [`InterpretedFloating::from_text`].
    pub fn for_derivatives(mut model: Model) -> Result<Self, Error> {
        let eqs = mechanism_codegen::derive(&mut model)?;
        Self::compiled(model, eqs, true)
    }

    /// The routines of `model`, with the derivatives when `derivatives`.
    fn compiled(mut model: Model, eqs: Equations, derivatives: bool) -> Result<Self, Error> {
        let routines = match derivatives {
            true => compile_floating_with_derivatives(&mut model, &eqs)?,
            false => compile_floating(&mut model, &eqs)?,
        };
        let nv = model.coordinates.len();
        let routine = |role: Role, outputs: usize| {
            Routine::new(routines.program(role)?, routines.sources(), outputs)
        };
        let arena = &model.arena;
        let root = model.floating_root();
        let mut configuration: Vec<String> = (root.iter())
            .flat_map(|r| r.configuration)
            .filter_map(|c| arena.as_symbol(c))
            .map(|s| arena.symbol_info(s).name.clone())
            .collect();
        let joints = (model.coordinates.iter().enumerate())
            .filter(|(i, _)| model.configuration_index(*i).is_some())
            .map(|(_, c)| c.name.clone());
        configuration.extend(joints);
        Ok(Self {
            name: model.name.clone(),
            configuration,
            velocities: model.coordinates.iter().map(|c| c.name.clone()).collect(),
            parameter_names: model.parameters.iter().map(|p| p.name.clone()).collect(),
            ranges: (model.parameters.iter())
                .map(|p| crate::system::parameters::declared_range(p.range))
                .collect(),
            mass: routine(Role::Mass, nv * nv)?,
            gravity: routine(Role::Gravity, nv)?,
            forces: routine(Role::Forces, nv)?,
            bias: routine(Role::Bias, nv)?,
            inverse_dynamics: routine(Role::InverseDynamics, nv)?,
            kinetic: routine(Role::Kinetic, 1)?,
            potential: routine(Role::Potential, 1)?,
            forward: routine(Role::ForwardDynamics, 3 * nv)?,
            derivatives: match derivatives {
                true => Some(routine(Role::InverseDynamicsDerivatives, 2 * nv * nv)?),
                false => None,
            },
            parameters: Parameters::new(&model, &routines)?,
        })
    }

    /// The declaration's name.
    pub fn name(&self) -> &str {
        &self.name
    }
    /// NQ = 7 + joints.
    pub fn nq(&self) -> usize {
        self.configuration.len()
    }
    /// NV = 6 + joints.
    pub fn nv(&self) -> usize {
        self.velocities.len()
    }
    /// The names of q's entries (`base_x`, .., `base_qw`, the joints').
    pub fn configuration(&self) -> &[String] {
        &self.configuration
    }
    /// The names of v's entries (`base_vx`, .., `base_wz`, the joints').
    pub fn velocities(&self) -> &[String] {
        &self.velocities
    }
    /// The parameters' names, in declaration order.
    pub fn parameter_names(&self) -> &[String] {
        &self.parameter_names
    }
    /// The parameters' declared ranges, in declaration order.
    pub fn parameter_ranges(&self) -> &[ParameterRange] {
        &self.ranges
    }
    /// The parameters' current values.
    pub fn parameter_values(&self) -> &[f64] {
        self.parameters.values()
    }
    /// Sets parameter `index`.
    ///
    /// # Errors
    /// [`ParameterError::NoSuchParameter`] past the last, [`ParameterError::OutOfRange`]
    /// outside the declared range; the parameter keeps its value.
    pub fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError> {
        self.parameters.set(index, value)
    }

    /// The neutral configuration: the root at the origin with the identity quaternion
    /// (0, 0, 0, 1), each joint at its declared guess at the current parameters.
    pub fn neutral(&self) -> Vec<f64> {
        let guesses = self.parameters.initial_guess(self.nv());
        let mut q = vec![0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        q.extend(guesses.iter().skip(6));
        q
    }

    fn at<'a>(&'a self, t: f64, q: &'a [f64], v: &'a [f64]) -> Values<'a> {
        Values {
            qd: v,
            ..self.parameters.at(t, q)
        }
    }

    /// M(q) (nv x nv, row-major) into `out`.
    pub fn mass_matrix(&self, q: &[f64], out: &mut [f64]) {
        self.mass
            .run(&self.at(0.0, q, &[]), |m| out.copy_from_slice(m));
    }

    /// g(q), the generalised gravity, into `out` (nv).
    pub fn gravity(&self, q: &[f64], out: &mut [f64]) {
        self.gravity
            .run(&self.at(0.0, q, &[]), |g| out.copy_from_slice(g));
    }

    /// The robot's weight F = m g in world axes (N): g(q)'s first three entries are the
    /// force the root must exert against gravity, in its axes, so F = -R g(q)[0..3].
    /// Constant in q for uniform gravity.
    pub fn weight(&self, q: &[f64]) -> [f64; 3] {
        let r = rotation(&[q[3], q[4], q[5], q[6]]);
        self.gravity.run(&self.at(0.0, q, &[]), |g| {
            [0, 1, 2].map(|i| -(r[i][0] * g[0] + r[i][1] * g[1] + r[i][2] * g[2]))
        })
    }

    /// The declared efforts tau(t, q, v) into `out` (nv).
    pub fn generalized_forces(&self, t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        self.forces
            .run(&self.at(t, q, v), |f| out.copy_from_slice(f));
    }

    /// The bias b = C(q, v) v + g(q) - tau(t, q, v) into `out` (nv), one Newton-Euler pass
    /// (Pinocchio's `nonLinearEffects` when no force is declared).
    pub fn bias(&self, t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        self.bias.run(&self.at(t, q, v), |b| out.copy_from_slice(b));
    }

    /// The inverse dynamics M a + C v + g - tau into `out` (nv): the effort that gives the
    /// acceleration `a` (Pinocchio's `rnea` when no force is declared).
    pub fn inverse_dynamics(&self, t: f64, q: &[f64], v: &[f64], a: &[f64], out: &mut [f64]) {
        let values = Values {
            qdd: a,
            ..self.at(t, q, v)
        };
        self.inverse_dynamics
            .run(&values, |x| out.copy_from_slice(x));
    }

    /// dtau/dq and dtau/dv (nv x nv each, row-major) of the inverse dynamics at (t, q, v, a)
    /// into `dq` and `dv`, by the tangent of the configuration manifold (as
    /// [`super::FloatingBase::inverse_dynamics_derivatives`]); false, nothing written, when
    /// the robot was built without them ([`InterpretedFloating::for_derivatives`]) or a
    /// slice is not nv x nv.
    pub fn inverse_dynamics_derivatives(
        &self,
        t: f64,
        q: &[f64],
        v: &[f64],
        a: &[f64],
        (dq, dv): (&mut [f64], &mut [f64]),
    ) -> bool {
        let n = self.nv();
        let Some(routine) = &self.derivatives else {
            return false;
        };
        if dq.len() != n * n || dv.len() != n * n {
            return false;
        }
        let values = Values {
            qdd: a,
            ..self.at(t, q, v)
        };
        routine.run(&values, |out| {
            dq.copy_from_slice(&out[..n * n]);
            dv.copy_from_slice(&out[n * n..]);
        });
        true
    }

    /// Whether [`InterpretedFloating::inverse_dynamics_derivatives`] answers.
    pub fn has_derivatives(&self) -> bool {
        self.derivatives.is_some()
    }

    /// q (+) v dt into `out` (nq), on the configuration manifold
    /// ([`crate::integrate_floating`]'s exponential map); `out` is left alone when q, v or
    /// `out` is not of this robot's sizes.
    pub fn integrate(&self, q: &[f64], v: &[f64], dt: f64, out: &mut [f64]) {
        if q.len() == self.nq() && v.len() == self.nv() && out.len() == self.nq() {
            crate::system::free_flyer::integrate_slices(q, v, dt, out);
        }
    }

    /// T = 1/2 v^T M(q) v.
    pub fn kinetic_energy(&self, q: &[f64], v: &[f64]) -> f64 {
        self.kinetic.run(&self.at(0.0, q, v), |x| x[0])
    }

    /// Pi(q) of the links' gravity.
    pub fn potential_energy(&self, q: &[f64]) -> f64 {
        self.potential.run(&self.at(0.0, q, &[]), |x| x[0])
    }

    /// a = M^-1 (effort - b) into `a` (nv), b = C v + g - tau, as
    /// [`super::FloatingBase::forward_dynamics`]; false (and `a` not to be read) when a
    /// pivot of M = L^T D L is not above 1e-14 of its diagonal entry or a is not finite.
    pub fn forward_dynamics(
        &self,
        t: f64,
        q: &[f64],
        v: &[f64],
        effort: &[f64],
        a: &mut [f64],
    ) -> bool {
        let n = self.nv();
        let values = Values {
            effort,
            ..self.at(t, q, v)
        };
        self.forward.run(&values, |out| {
            let (qdd, rest) = out.split_at(n);
            let (pivots, diagonal) = rest.split_at(n);
            a.copy_from_slice(qdd);
            let definite =
                (pivots.iter().zip(diagonal)).all(|(d, m)| d.is_finite() && *d > 1e-14 * *m);
            definite && qdd.iter().all(|x| x.is_finite())
        })
    }

    /// The momentum of the whole robot in world axes: the linear momentum p, the angular
    /// momentum L_c about the centre of mass, and the centre of mass c, from M's root rows
    /// (the momentum in the root's axes about its origin, h = M[0..6, :] v): p = R h_lin,
    /// L_c = R h_ang - (c - x) x p, c = x + R s / m with m = M[0, 0] and s the first
    /// moment read off M's root block `[[m 1, -[s]x], [[s]x, I]]` (as
    /// [`super::FloatingBase::centroidal_momentum_matrix`]). `mass` is scratch of nv x nv.
    pub fn momentum(&self, q: &[f64], v: &[f64], mass: &mut [f64]) -> Momentum {
        let n = self.nv();
        self.mass_matrix(q, mass);
        let row = |i: usize| (0..n).map(|j| mass[i * n + j] * v[j]).sum::<f64>();
        let h = [row(0), row(1), row(2), row(3), row(4), row(5)];
        let r = rotation(&[q[3], q[4], q[5], q[6]]);
        let rot = |x: [f64; 3]| [0, 1, 2].map(|i| r[i][0] * x[0] + r[i][1] * x[1] + r[i][2] * x[2]);
        let m = mass[0];
        let s = [mass[n + 5], mass[2 * n + 3], mass[4]];
        let rs = rot(s);
        let d = rs.map(|x| x / m);
        let p = rot([h[0], h[1], h[2]]);
        let lo = rot([h[3], h[4], h[5]]);
        let cross = [
            d[1] * p[2] - d[2] * p[1],
            d[2] * p[0] - d[0] * p[2],
            d[0] * p[1] - d[1] * p[0],
        ];
        Momentum {
            linear: p,
            angular: [0, 1, 2].map(|i| lo[i] - cross[i]),
            center_of_mass: [0, 1, 2].map(|i| q[i] + d[i]),
            mass: m,
        }
    }
}

/// The momentum of a floating robot ([`InterpretedFloating::momentum`]), world axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Momentum {
    /// p (kg m/s).
    pub linear: [f64; 3],
    /// L about the centre of mass (kg m^2/s).
    pub angular: [f64; 3],
    /// The centre of mass (m).
    pub center_of_mass: [f64; 3],
    /// The total mass (kg).
    pub mass: f64,
}
