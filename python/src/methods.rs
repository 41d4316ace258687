//! `Model`'s Python methods: its names, its equations, the per-state dynamics (one state
//! or a batch, see `batch.rs`) and the runs (`runs.rs`).

use std::collections::HashMap;

use mechanism::{Evaluation, Kinematic, System};
use nalgebra::{DMatrix, Matrix3, Vector3};
use numpy::PyArrayLikeDyn;
use pyo3::prelude::*;
use pyo3::types::PyTuple;

use crate::batch::{Arg, PyErrLater, batched_rows, later};
use crate::derivatives;
use crate::effort::WithEffort;
use crate::errors::declaration;
use crate::model::{Model, pairs, reduce};
use crate::rows::{forward_dynamics_rows, no_frames};
use crate::runs::{self, RunOptions};
use crate::scratch::with_scratch;

type Array<'py> = PyArrayLikeDyn<'py, f64, numpy::AllowTypeChange>;

impl Model {
    fn arg<'py>(&self, name: &'static str, array: Array<'py>) -> Arg<'py> {
        Arg {
            name,
            array,
            len: self.system.info().n(),
        }
    }
}

#[pymethods]
impl Model {
    /// The mechanism's name (the declared struct).
    #[getter]
    fn name(&self) -> String {
        self.system.info().name.clone()
    }

    /// The coordinate names, in the order of q.
    #[getter]
    fn coordinates(&self) -> Vec<String> {
        self.system.info().coordinates.clone()
    }

    /// The parameters and their values, in declaration order.
    #[getter]
    fn parameters(&self) -> Vec<(String, f64)> {
        let info = self.system.info();
        info.parameters
            .iter()
            .cloned()
            .zip(self.values.iter().copied())
            .collect()
    }

    /// The independent coordinates (whose positions, and rates, a run starts from).
    #[getter]
    fn independent(&self) -> Vec<String> {
        let info = self.system.info();
        info.independent
            .iter()
            .map(|i| info.coordinates[i.coordinate].clone())
            .collect()
    }

    /// The link frames (`link` sections, a URDF's links) in declaration order.
    #[getter]
    fn frames(&self) -> Vec<String> {
        self.system.info().frames.clone()
    }

    /// Coordinates n.
    #[getter]
    fn n(&self) -> usize {
        self.system.info().n()
    }

    /// Constraint rows m (position and velocity rows).
    #[getter]
    fn m(&self) -> usize {
        self.system.info().m()
    }

    /// The declaration text (for a URDF, the declaration it imports as).
    #[getter]
    fn source(&self) -> String {
        self.source.clone()
    }

    /// The derived equations as text, or as LaTeX when `latex`.
    #[pyo3(signature = (latex = false))]
    fn equations(&self, py: Python<'_>, latex: bool) -> PyResult<String> {
        py.detach(|| {
            let mut model = mechanism_codegen::parse_model_str(&self.source)
                .map_err(|e| declaration(&self.shown, &e))?;
            let eqs =
                mechanism_codegen::derive(&mut model).map_err(|e| declaration(&self.shown, &e))?;
            Ok(if latex {
                mechanism_codegen::equations_latex(&model, &eqs)
            } else {
                mechanism_codegen::equations_text(&model, &eqs)
            })
        })
    }

    /// M(q), n x n (a batch: rows x n x n).
    #[pyo3(signature = (q, t = 0.0))]
    fn mass_matrix(&self, py: Python<'_>, q: Array<'_>, t: f64) -> PyResult<Py<PyAny>> {
        let n = self.system.info().n();
        let write = |e: &Evaluation, out: &mut [f64]| {
            for i in 0..n {
                for j in 0..n {
                    out[i * n + j] = e.mass[(i, j)];
                }
            }
        };
        let one = |s: &[&[f64]], out: &mut [f64]| {
            with_scratch(self, |e, _| {
                self.system.evaluate(t, s[0], &vec![0.0; n], e);
                write(e, out);
            });
            Ok(())
        };
        let rows = |s: &[&[f64]], out: &mut [f64]| {
            let zeros = vec![0.0; s[0].len()];
            self.evaluate_rows(t, s[0], &zeros, n * n, out, |_, e, out| {
                write(e, out);
                Ok(())
            })
        };
        batched_rows(py, &[self.arg("q", q)], &[n, n], one, rows)
    }

    /// The bias b = C(q, v) v + g(q) - tau(t, q, v): without constraints M q'' + b = u.
    #[pyo3(signature = (q, v, t = 0.0))]
    fn bias(&self, py: Python<'_>, q: Array<'_>, v: Array<'_>, t: f64) -> PyResult<Py<PyAny>> {
        let n = self.system.info().n();
        let write = |e: &Evaluation, out: &mut [f64]| {
            for (i, o) in out.iter_mut().enumerate() {
                *o = e.coriolis[i] + e.gravity[i] - e.forces[i];
            }
        };
        let one = |s: &[&[f64]], out: &mut [f64]| {
            with_scratch(self, |e, _| {
                self.system.evaluate(t, s[0], s[1], e);
                write(e, out);
            });
            Ok(())
        };
        let rows = |s: &[&[f64]], out: &mut [f64]| {
            self.evaluate_rows(t, s[0], s[1], n, out, |_, e, out| {
                write(e, out);
                Ok(())
            })
        };
        let args = [self.arg("q", q), self.arg("v", v)];
        batched_rows(py, &args, &[n], one, rows)
    }

    /// The effort u = M(q) a + C(q, v) v + g(q) - tau that gives the accelerations a when
    /// no constraint acts (Pinocchio's `rnea`; Newton-Euler for a tree of links).
    #[pyo3(signature = (q, v, a, t = 0.0))]
    fn inverse_dynamics(
        &self,
        py: Python<'_>,
        q: Array<'_>,
        v: Array<'_>,
        a: Array<'_>,
        t: f64,
    ) -> PyResult<Py<PyAny>> {
        let n = self.system.info().n();
        let args = [self.arg("q", q), self.arg("v", v), self.arg("a", a)];
        let one = |s: &[&[f64]], out: &mut [f64]| {
            if self
                .system
                .inverse_dynamics(t, s[0], s[1], s[2], out)
                .is_none()
            {
                with_scratch(self, |e, _| {
                    self.system.evaluate(t, s[0], s[1], e);
                    let u = &e.mass * nalgebra::DVector::from_column_slice(s[2]);
                    for (i, o) in out.iter_mut().enumerate() {
                        *o = u[i] + e.coriolis[i] + e.gravity[i] - e.forces[i];
                    }
                });
            }
            Ok(())
        };
        let rows = |s: &[&[f64]], out: &mut [f64]| {
            if self
                .system
                .inverse_dynamics_rows(t, s[0], s[1], s[2], out)
                .is_none()
            {
                // Without the robotics routines: each row as one state.
                for (i, o) in out.chunks_mut(n).enumerate() {
                    let r = i * n..(i + 1) * n;
                    let state = [&s[0][r.clone()], &s[1][r.clone()], &s[2][r]];
                    one(&state, o).map_err(|e| (i, e))?;
                }
            }
            Ok(())
        };
        batched_rows(py, &args, &[n], one, rows)
    }

    /// The accelerations q'' under the effort tau added to the declared forces, with the
    /// constraint rows acting (the augmented system; for an unconstrained robot
    /// M q'' = tau - b, Pinocchio's `aba`). The state should satisfy the constraints.
    #[pyo3(signature = (q, v, tau, t = 0.0))]
    fn forward_dynamics(
        &self,
        py: Python<'_>,
        q: Array<'_>,
        v: Array<'_>,
        tau: Array<'_>,
        t: f64,
    ) -> PyResult<Py<PyAny>> {
        let n = self.system.info().n();
        let args = [self.arg("q", q), self.arg("v", v), self.arg("tau", tau)];
        let one = |s: &[&[f64]], out: &mut [f64]| {
            with_scratch(self, |_, dynamics| {
                let system = WithEffort::new(self.system.as_ref(), s[2]);
                dynamics.solve(&system, t, s[0], s[1]).map_err(later)?;
                out.copy_from_slice(dynamics.accelerations());
                Ok::<(), PyErrLater>(())
            })
        };
        let rows = |s: &[&[f64]], out: &mut [f64]| forward_dynamics_rows(self, t, s, out);
        batched_rows(py, &args, &[n], one, rows)
    }

    /// (dtau/dq, dtau/dv) of the inverse dynamics u = M(q) a + C(q, v) v + g(q) - tau, n x n
    /// each (Pinocchio's `computeRNEADerivatives`; du/da is `mass_matrix`).
    #[pyo3(signature = (q, v, a, t = 0.0))]
    fn inverse_dynamics_derivatives<'py>(
        &self,
        py: Python<'py>,
        q: Array<'py>,
        v: Array<'py>,
        a: Array<'py>,
        t: f64,
    ) -> PyResult<Bound<'py, PyTuple>> {
        derivatives::inverse_dynamics(self, py, (q, v, a), t)
    }

    /// du/dp of the inverse dynamics by the declared parameters, n x p (columns in the order
    /// of `parameters`).
    #[pyo3(signature = (q, v, a, t = 0.0))]
    fn inverse_dynamics_parameter_derivatives(
        &self,
        py: Python<'_>,
        q: Array<'_>,
        v: Array<'_>,
        a: Array<'_>,
        t: f64,
    ) -> PyResult<Py<PyAny>> {
        derivatives::parameters(self, py, (q, v, a), t)
    }

    /// (dq''/dq, dq''/dv, dq''/dtau) of `forward_dynamics`, n x n each (Pinocchio's
    /// `computeABADerivatives`: dq''/dtau = M^-1 without constraint rows).
    #[pyo3(signature = (q, v, tau, t = 0.0))]
    fn forward_dynamics_derivatives<'py>(
        &self,
        py: Python<'py>,
        q: Array<'py>,
        v: Array<'py>,
        tau: Array<'py>,
        t: f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        derivatives::forward_dynamics(self, py, (q, v, tau), t, false)
    }

    /// q'', the multipliers lambda and their derivatives by q, v and tau, as a dict (`qdd`,
    /// `lambda`, `dqdd_dq`, `dqdd_dv`, `dqdd_dtau`, `dlambda_dq`, `dlambda_dv`,
    /// `dlambda_dtau`), through the augmented system's derivative.
    #[pyo3(signature = (q, v, tau, t = 0.0))]
    fn constrained_dynamics_derivatives<'py>(
        &self,
        py: Python<'py>,
        q: Array<'py>,
        v: Array<'py>,
        tau: Array<'py>,
        t: f64,
    ) -> PyResult<Bound<'py, PyAny>> {
        derivatives::forward_dynamics(self, py, (q, v, tau), t, true)
    }

    /// The placement of link frame `frame` (a name or an index into `frames`) at q as a
    /// 4 x 4 homogeneous transform [[R, p], [0, 0, 0, 1]]: R the link axes in world axes,
    /// p the frame's origin in the world (a batch: rows x 4 x 4).
    fn frame_placement(
        &self,
        py: Python<'_>,
        frame: &Bound<'_, PyAny>,
        q: Array<'_>,
    ) -> PyResult<Py<PyAny>> {
        let k = self.frame(frame)?;
        // R row-major then p (12 values) as a homogeneous transform (16).
        let write = |rp: &[f64], out: &mut [f64]| {
            for i in 0..3 {
                out[4 * i..4 * i + 3].copy_from_slice(&rp[3 * i..3 * i + 3]);
                out[4 * i + 3] = rp[9 + i];
            }
            out[12..].copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
        };
        let one = |s: &[&[f64]], out: &mut [f64]| {
            let (mut r, mut p) = (Matrix3::zeros(), Vector3::zeros());
            self.system
                .frame_placement(k, s[0], &mut r, &mut p)
                .ok_or_else(no_frames)?;
            let rp: Vec<f64> = (0..9)
                .map(|e| r[(e / 3, e % 3)])
                .chain(p.iter().copied())
                .collect();
            write(&rp, out);
            Ok(())
        };
        let rows = |s: &[&[f64]], out: &mut [f64]| {
            let mut rp = vec![0.0; 12 * (out.len() / 16)];
            self.system
                .frame_placement_rows(k, s[0], &mut rp)
                .ok_or_else(|| (0, no_frames()))?;
            for (o, r) in out.chunks_mut(16).zip(rp.chunks(12)) {
                write(r, o);
            }
            Ok(())
        };
        batched_rows(py, &[self.arg("q", q)], &[4, 4], one, rows)
    }

    /// The Jacobian J (6 x n) of link frame `frame` at q: [v; w] = J q', the velocity of
    /// the frame's origin and its angular velocity in world axes (Pinocchio's
    /// `LOCAL_WORLD_ALIGNED`); a batch: rows x 6 x n.
    fn frame_jacobian(
        &self,
        py: Python<'_>,
        frame: &Bound<'_, PyAny>,
        q: Array<'_>,
    ) -> PyResult<Py<PyAny>> {
        let k = self.frame(frame)?;
        let n = self.system.info().n();
        let one = |s: &[&[f64]], out: &mut [f64]| {
            let mut jac = DMatrix::zeros(6, n);
            self.system
                .frame_jacobian(k, s[0], &mut jac)
                .ok_or_else(no_frames)?;
            for i in 0..6 {
                for j in 0..n {
                    out[i * n + j] = jac[(i, j)];
                }
            }
            Ok(())
        };
        let rows = |s: &[&[f64]], out: &mut [f64]| {
            self.system
                .frame_jacobian_rows(k, s[0], out)
                .ok_or_else(|| (0, no_frames()))
        };
        batched_rows(py, &[self.arg("q", q)], &[6, n], one, rows)
    }

    /// Simulates from the state assembled from the independent coordinates (`init`
    /// changes positions, `"der(x)"` rates), as `mechanism simulate` does.
    #[pyo3(signature = (*, t_end = 10.0, rtol = 1e-10, atol = 1e-10, integrator = "dop853",
        step = None, samples_per_second = 100.0, stabilization = "projection", set = None,
        init = None))]
    #[allow(clippy::too_many_arguments)]
    fn simulate(
        &self,
        py: Python<'_>,
        t_end: f64,
        rtol: f64,
        atol: f64,
        integrator: &str,
        step: Option<f64>,
        samples_per_second: f64,
        stabilization: &str,
        set: Option<HashMap<String, f64>>,
        init: Option<HashMap<String, f64>>,
    ) -> PyResult<Py<PyAny>> {
        let options = RunOptions {
            t_end,
            samples_per_second,
            integrator: integrator.to_string(),
            rtol,
            atol,
            step,
            stabilization: stabilization.to_string(),
        };
        runs::simulate(py, self, options, &pairs(set), &pairs(init))
    }

    /// The driving forces along the prescribed motions `drives` (`"phi = 2*pi*t"`), as
    /// `mechanism inverse` computes them.
    #[pyo3(signature = (drives, *, t_end = 1.0, samples_per_second = 100.0, set = None,
        init = None))]
    fn inverse(
        &self,
        py: Python<'_>,
        drives: Vec<String>,
        t_end: f64,
        samples_per_second: f64,
        set: Option<HashMap<String, f64>>,
        init: Option<HashMap<String, f64>>,
    ) -> PyResult<Py<PyAny>> {
        runs::inverse(
            py,
            self,
            drives,
            t_end,
            samples_per_second,
            &pairs(set),
            &pairs(init),
        )
    }

    /// The linearisation about the equilibrium or steady motion the independent
    /// coordinates give, in minimal variables, as `mechanism linearize` computes it.
    #[pyo3(signature = (*, set = None, init = None))]
    fn linearize(
        &self,
        py: Python<'_>,
        set: Option<HashMap<String, f64>>,
        init: Option<HashMap<String, f64>>,
    ) -> PyResult<Py<PyAny>> {
        runs::linearize(py, self, &pairs(set), &pairs(init))
    }

    fn __reduce__<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyTuple>> {
        reduce(self, py)
    }

    fn __repr__(&self) -> String {
        let info = self.system.info();
        format!(
            "<mechanism.Model {} from {}: {} coordinates, {} constraint rows>",
            info.name,
            self.shown,
            info.n(),
            info.m()
        )
    }
}

/// Runs `simulate` once per parameter set of `sets` in parallel (all cores, or `threads`),
/// each as `model.simulate(set=..., **options)` would; the trajectories in the order of
/// `sets`. The first failure is raised, naming its set.
#[pyfunction]
#[pyo3(signature = (model, sets, *, t_end = 10.0, rtol = 1e-10, atol = 1e-10,
    integrator = "dop853", step = None, samples_per_second = 100.0,
    stabilization = "projection", init = None, threads = None))]
#[allow(clippy::too_many_arguments)]
pub fn sweep(
    py: Python<'_>,
    model: &Model,
    sets: Vec<HashMap<String, f64>>,
    t_end: f64,
    rtol: f64,
    atol: f64,
    integrator: &str,
    step: Option<f64>,
    samples_per_second: f64,
    stabilization: &str,
    init: Option<HashMap<String, f64>>,
    threads: Option<usize>,
) -> PyResult<Vec<Py<PyAny>>> {
    let options = RunOptions {
        t_end,
        samples_per_second,
        integrator: integrator.to_string(),
        rtol,
        atol,
        step,
        stabilization: stabilization.to_string(),
    };
    let sets: Vec<Vec<(String, f64)>> = sets.into_iter().map(|s| pairs(Some(s))).collect();
    runs::sweep(py, model, sets, options, &pairs(init), threads)
}
