//! A floating-base robot from Python: `load(.., floating=True)` of a URDF, or `load` /
//! `from_source` of a declaration whose root link is `joint = floating(..)`, gives a
//! `FloatingModel` over the crate's `InterpretedFloating` (the routines the macro emits
//! for `FloatingBase`, run on codegen's tapes), in Pinocchio's free-flyer layout:
//! q = [position (3), quaternion x, y, z, w, joints] (nq = 7 + joints),
//! v = [velocity, angular velocity (root axes), joint rates] (nv = 6 + joints).

use std::sync::OnceLock;

use mechanism::{FloatingDerivatives, InterpretedFloating, simulate_interpreted_floating};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{SingularError, declaration, did_you_mean, input, solver};

/// A floating-base robot (module docs). Immutable; `set=` at load time sets parameters.
#[pyclass(module = "mechanism", frozen)]
pub struct FloatingModel {
    robot: InterpretedFloating,
    shown: String,
    /// The declaration text, for the derivatives.
    source: String,
    /// The same robot with the derivatives of the dynamics, derived on first use.
    derivatives: OnceLock<InterpretedFloating>,
}

/// The floating model of `source` (shown as `shown`), with the parameters `set`.
pub(crate) fn build(source: &str, shown: &str, set: &[(String, f64)]) -> PyResult<FloatingModel> {
    let mut robot = InterpretedFloating::from_text(source).map_err(|e| declaration(shown, &e))?;
    for (name, value) in set {
        let names = robot.parameter_names();
        let Some(k) = names.iter().position(|n| n == name) else {
            return Err(input(format!(
                "set: unknown parameter `{name}`{}; parameters: {}",
                did_you_mean(name, names),
                names.join(", ")
            )));
        };
        if !value.is_finite() {
            return Err(input(format!(
                "set {name}: the value must be finite, got {value}"
            )));
        }
        robot
            .set_parameter(k, *value)
            .map_err(|e| input(format!("set {name}={value}: {e}")))?;
    }
    Ok(FloatingModel {
        robot,
        shown: shown.to_string(),
        source: source.to_string(),
        derivatives: OnceLock::new(),
    })
}

/// Whether the declaration `source` has a floating root (false when it does not parse:
/// the ordinary route then reports the error).
pub(crate) fn is_floating(source: &str) -> bool {
    mechanism_codegen::parse_model_str(source).is_ok_and(|m| m.floating_root().is_some())
}

impl FloatingModel {
    /// `x` as a vector of `len` finite entries, or an `InputError` naming `what`.
    fn vector(&self, what: &str, x: Vec<f64>, len: usize) -> PyResult<Vec<f64>> {
        if x.len() != len {
            return Err(input(format!(
                "{}: {what} has {} entries, not {len}",
                self.shown,
                x.len()
            )));
        }
        if let Some(bad) = x.iter().find(|v| !v.is_finite()) {
            return Err(input(format!(
                "{}: {what} holds {bad}: the values must be finite",
                self.shown
            )));
        }
        Ok(x)
    }
    fn q(&self, q: Vec<f64>) -> PyResult<Vec<f64>> {
        self.vector("q", q, self.robot.nq())
    }
    fn v(&self, what: &str, v: Vec<f64>) -> PyResult<Vec<f64>> {
        self.vector(what, v, self.robot.nv())
    }
    /// The robot with its derivatives, at this model's parameter values.
    fn with_derivatives(&self) -> PyResult<&InterpretedFloating> {
        if let Some(r) = self.derivatives.get() {
            return Ok(r);
        }
        let model = mechanism_codegen::parse_model_str(&self.source)
            .map_err(|e| declaration(&self.shown, &e))?;
        let mut robot =
            InterpretedFloating::for_derivatives(model).map_err(|e| declaration(&self.shown, &e))?;
        for (k, value) in self.robot.parameter_values().iter().enumerate() {
            // The model's own values, accepted when it was built.
            robot.set_parameter(k, *value).map_err(|e| input(e.to_string()))?;
        }
        Ok(self.derivatives.get_or_init(|| robot))
    }
}

fn vector<'py>(py: Python<'py>, x: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    x.into_pyarray(py)
}

fn matrix<'py>(py: Python<'py>, x: Vec<f64>, rows: usize) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let cols = x.len() / rows.max(1);
    x.into_pyarray(py).reshape([rows, cols])
}

#[pymethods]
impl FloatingModel {
    /// The robot's name (the declared struct).
    #[getter]
    fn name(&self) -> String {
        self.robot.name().to_string()
    }
    /// The size of q: 7 for the root (position, quaternion x, y, z, w) plus the joints.
    #[getter]
    fn nq(&self) -> usize {
        self.robot.nq()
    }
    /// The size of v: 6 for the root (velocity, angular velocity, root axes) plus the joints.
    #[getter]
    fn nv(&self) -> usize {
        self.robot.nv()
    }
    /// The names of q's entries (`root_joint_x`, .., `root_joint_qw`, then the joints').
    #[getter]
    fn configuration(&self) -> Vec<String> {
        self.robot.configuration().to_vec()
    }
    /// The names of v's entries (`root_joint_vx`, .., `root_joint_wz`, then the joints').
    #[getter]
    fn velocities(&self) -> Vec<String> {
        self.robot.velocities().to_vec()
    }
    /// The parameters and their values, in declaration order.
    #[getter]
    fn parameters(&self) -> Vec<(String, f64)> {
        (self.robot.parameter_names().iter().cloned())
            .zip(self.robot.parameter_values().iter().copied())
            .collect()
    }
    /// The neutral configuration: the root at the origin, quaternion (0, 0, 0, 1), each
    /// joint at its declared guess.
    fn neutral<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        vector(py, self.robot.neutral())
    }
    /// M(q), nv x nv (Pinocchio's `crba`, both triangles).
    fn mass_matrix<'py>(&self, py: Python<'py>, q: Vec<f64>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let q = self.q(q)?;
        let n = self.robot.nv();
        let mut out = vec![0.0; n * n];
        self.robot.mass_matrix(&q, &mut out);
        matrix(py, out, n)
    }
    /// b = C(q, v) v + g(q) - tau(t, q, v) (Pinocchio's `nonLinearEffects` without declared
    /// forces).
    #[pyo3(signature = (q, v, t = 0.0))]
    fn bias<'py>(&self, py: Python<'py>, q: Vec<f64>, v: Vec<f64>, t: f64) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (q, v) = (self.q(q)?, self.v("v", v)?);
        let mut out = vec![0.0; self.robot.nv()];
        self.robot.bias(t, &q, &v, &mut out);
        Ok(vector(py, out))
    }
    /// g(q), the generalised gravity (Pinocchio's `computeGeneralizedGravity`).
    fn gravity<'py>(&self, py: Python<'py>, q: Vec<f64>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let q = self.q(q)?;
        let mut out = vec![0.0; self.robot.nv()];
        self.robot.gravity(&q, &mut out);
        Ok(vector(py, out))
    }
    /// M a + C v + g - tau: the effort that gives the acceleration a (Pinocchio's `rnea`).
    #[pyo3(signature = (q, v, a, t = 0.0))]
    fn inverse_dynamics<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        v: Vec<f64>,
        a: Vec<f64>,
        t: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (q, v, a) = (self.q(q)?, self.v("v", v)?, self.v("a", a)?);
        let mut out = vec![0.0; self.robot.nv()];
        self.robot.inverse_dynamics(t, &q, &v, &a, &mut out);
        Ok(vector(py, out))
    }
    /// a = M^-1 (tau - b) (Pinocchio's `aba`); `tau` defaults to zero. `SingularError` where
    /// M is not positive definite (or a is not finite).
    #[pyo3(signature = (q, v, tau = None, t = 0.0))]
    fn forward_dynamics<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        v: Vec<f64>,
        tau: Option<Vec<f64>>,
        t: f64,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let n = self.robot.nv();
        let (q, v) = (self.q(q)?, self.v("v", v)?);
        let tau = self.v("tau", tau.unwrap_or_else(|| vec![0.0; n]))?;
        let mut a = vec![0.0; n];
        if !self.robot.forward_dynamics(t, &q, &v, &tau, &mut a) {
            return Err(SingularError::new_err(format!(
                "{}: the forward dynamics at t = {t} s: M is not positive definite (or a is \
                 not finite)",
                self.shown
            )));
        }
        Ok(vector(py, a))
    }
    /// q (+) v dt on the configuration manifold (Pinocchio's `integrate(q, v dt)`): the
    /// root by the exponential map of SE(3), the joints by addition.
    fn integrate<'py>(&self, py: Python<'py>, q: Vec<f64>, v: Vec<f64>, dt: f64) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let (q, v) = (self.q(q)?, self.v("v", v)?);
        let mut out = q.clone();
        self.robot.integrate(&q, &v, dt, &mut out);
        Ok(vector(py, out))
    }
    /// (dtau/dq, dtau/dv), nv x nv each, of `inverse_dynamics` (Pinocchio's
    /// `computeRNEADerivatives`): by q along the tangent of the configuration manifold,
    /// column k the rate along `integrate(q, e_k, e)`. Derived on the first call and kept.
    #[pyo3(signature = (q, v, a, t = 0.0))]
    #[allow(clippy::type_complexity)]
    fn inverse_dynamics_derivatives<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        v: Vec<f64>,
        a: Vec<f64>,
        t: f64,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<f64>>)> {
        let n = self.robot.nv();
        let (q, v, a) = (self.q(q)?, self.v("v", v)?, self.v("a", a)?);
        let robot = py.detach(|| self.with_derivatives())?;
        let (mut dq, mut dv) = (vec![0.0; n * n], vec![0.0; n * n]);
        robot.inverse_dynamics_derivatives(t, &q, &v, &a, (&mut dq, &mut dv));
        Ok((matrix(py, dq, n)?, matrix(py, dv, n)?))
    }
    /// (da/dq, da/dv, M^-1), nv x nv each, of `forward_dynamics` (Pinocchio's
    /// `computeABADerivatives`), q's direction as `inverse_dynamics_derivatives`'.
    /// `SingularError` where M is not positive definite.
    #[pyo3(signature = (q, v, tau = None, t = 0.0))]
    #[allow(clippy::type_complexity)]
    fn forward_dynamics_derivatives<'py>(
        &self,
        py: Python<'py>,
        q: Vec<f64>,
        v: Vec<f64>,
        tau: Option<Vec<f64>>,
        t: f64,
    ) -> PyResult<(
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<f64>>,
    )> {
        let n = self.robot.nv();
        let (q, v) = (self.q(q)?, self.v("v", v)?);
        let tau = self.v("tau", tau.unwrap_or_else(|| vec![0.0; n]))?;
        let robot = py.detach(|| self.with_derivatives())?;
        let mut d = FloatingDerivatives::new(robot);
        d.compute(robot, t, &q, &v, &tau).map_err(solver)?;
        Ok((
            matrix(py, d.da_dq().to_vec(), n)?,
            matrix(py, d.da_dv().to_vec(), n)?,
            matrix(py, d.m_inverse().to_vec(), n)?,
        ))
    }
    /// T = 1/2 v^T M(q) v (J).
    fn kinetic_energy(&self, q: Vec<f64>, v: Vec<f64>) -> PyResult<f64> {
        Ok(self.robot.kinetic_energy(&self.q(q)?, &self.v("v", v)?))
    }
    /// Pi(q) of the links' gravity (J).
    fn potential_energy(&self, q: Vec<f64>) -> PyResult<f64> {
        Ok(self.robot.potential_energy(&self.q(q)?))
    }
    /// Simulates from (q0, v0) (default: the neutral configuration at rest) for `t_end` s
    /// under gravity and the declared efforts, fixed RK4 steps of `step` with the
    /// quaternion projected back onto unit norm (as `mechanism simulate`), a sample every
    /// `every` steps. Returns a dict: `t` (k), `q` (k x nq), `v` (k x nv), `configuration`
    /// and `velocities` (the column names). `InputError` for a quaternion not unit within
    /// 1e-9 or a bad option; `IntegrationError` where the run leaves the finite numbers.
    #[pyo3(signature = (t_end, *, q0 = None, v0 = None, step = 1e-3, every = 10))]
    fn simulate<'py>(
        &self,
        py: Python<'py>,
        t_end: f64,
        q0: Option<Vec<f64>>,
        v0: Option<Vec<f64>>,
        step: f64,
        every: usize,
    ) -> PyResult<Bound<'py, PyDict>> {
        let (nq, nv) = (self.robot.nq(), self.robot.nv());
        let q0 = self.q(q0.unwrap_or_else(|| self.robot.neutral()))?;
        let v0 = self.v("v0", v0.unwrap_or_else(|| vec![0.0; nv]))?;
        let (mut t, mut q, mut v) = (Vec::new(), Vec::new(), Vec::new());
        py.detach(|| {
            simulate_interpreted_floating(&self.robot, (&q0, &v0), (t_end, step, every), |ti, qi, vi| {
                t.push(ti);
                q.extend_from_slice(qi);
                v.extend_from_slice(vi);
            })
        })
        .map_err(solver)?;
        let k = t.len();
        let out = PyDict::new(py);
        out.set_item("t", vector(py, t))?;
        out.set_item("q", matrix(py, q, k)?)?;
        out.set_item("v", matrix(py, v, k)?)?;
        out.set_item("configuration", self.robot.configuration().to_vec())?;
        out.set_item("velocities", self.robot.velocities().to_vec())?;
        let _ = nq;
        Ok(out)
    }
    fn __repr__(&self) -> String {
        format!(
            "<mechanism.FloatingModel {} (nq = {}, nv = {})>",
            self.robot.name(),
            self.robot.nq(),
            self.robot.nv()
        )
    }
}
