//! A derived declaration's inverse dynamics and link frames, interpreted: the routines of
//! [`mechanism_codegen::Role::robotics`] with their own parameter cache
//! ([`mechanism_codegen::compile_robotics`]), which [`crate::Interpreted`] compiles when asked
//! ([`crate::Interpreted::from_model_with`]), as the macro emits `inverse_dynamics`,
//! `frame_placement` and `frame_jacobian` for every declaration.

use mechanism_codegen::{Equations, Error, Model, Role, compile_robotics};
use nalgebra::{DMatrix, Matrix3, Vector3};

use crate::ParameterError;
use crate::system::parameters::Parameters;
use crate::system::routine::{Routine, Values};

/// The robotics routines of one declaration and the parameter values they read.
#[derive(Clone, Debug)]
pub(crate) struct Robotics {
    /// The parameters and the cache of these routines' parameter-only values.
    parameters: Parameters,
    /// M q'' + C q' + g - tau (n outputs): Newton-Euler for a tree of links.
    inverse: Routine,
    /// Per link frame: R (3 x 3, row-major) then p (3).
    placements: Vec<Routine>,
    /// Per link frame: J (6 x n, row-major).
    jacobians: Vec<Routine>,
    /// n.
    n: usize,
}

impl Robotics {
    /// Compiles the robotics routines of the derived equations `eqs` of `model`.
    ///
    /// # Errors
    /// A compilation error from codegen (as [`crate::Interpreted::from_equations`]).
    pub(crate) fn new(model: &mut Model, eqs: &Equations) -> Result<Self, Error> {
        let routines = compile_robotics(model, eqs)?;
        let n = model.coordinates.len();
        let routine = |role: Role, outputs: usize| {
            Routine::new(routines.program(role)?, routines.sources(), outputs)
        };
        let frames = eqs.frames.len();
        Ok(Self {
            inverse: routine(Role::InverseDynamics, n)?,
            placements: (0..frames)
                .map(|k| routine(Role::FramePlacement(k), 12))
                .collect::<Result<_, _>>()?,
            jacobians: (0..frames)
                .map(|k| routine(Role::FrameJacobian(k), 6 * n))
                .collect::<Result<_, _>>()?,
            parameters: Parameters::new(model, &routines)?,
            n,
        })
    }

    /// Sets parameter `index` and recomputes the cache.
    ///
    /// # Errors
    /// As [`Parameters::set`]: an index out of range or a value outside its declared range.
    pub(crate) fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError> {
        self.parameters.set(index, value)
    }

    /// M q'' + C q' + g - tau at (t, q, q', q'') into `out` (n values).
    pub(crate) fn inverse_dynamics(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) {
        let values = Values {
            qd,
            qdd,
            ..self.parameters.at(t, q)
        };
        self.inverse.run(&values, |v| out.copy_from_slice(v));
    }

    /// R and p of frame `frame` at q; `None` past the last frame.
    pub(crate) fn placement(
        &self,
        frame: usize,
        q: &[f64],
        rotation: &mut Matrix3<f64>,
        position: &mut Vector3<f64>,
    ) -> Option<()> {
        let routine = self.placements.get(frame)?;
        routine.run(&self.parameters.at(0.0, q), |v| {
            for i in 0..3 {
                for j in 0..3 {
                    rotation[(i, j)] = v[3 * i + j];
                }
                position[i] = v[9 + i];
            }
        });
        Some(())
    }

    /// J (6 x n) of frame `frame` at q into `out`; `None` past the last frame.
    pub(crate) fn jacobian(&self, frame: usize, q: &[f64], out: &mut DMatrix<f64>) -> Option<()> {
        let routine = self.jacobians.get(frame)?;
        let n = self.n;
        routine.run(&self.parameters.at(0.0, q), |v| {
            for i in 0..6 {
                for j in 0..n {
                    out[(i, j)] = v[i * n + j];
                }
            }
        });
        Some(())
    }

    /// [`Robotics::inverse_dynamics`] at each row of the batch `q`, `qd`, `qdd` (n values
    /// per state, row-major) into the rows of `out`, side by side
    /// ([`Routine::run_rows`]).
    pub(crate) fn inverse_dynamics_rows(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) {
        let values = Values {
            qd,
            qdd,
            ..self.parameters.at(t, q)
        };
        self.inverse.run_rows(&values, self.n, out);
    }

    /// The outputs of frame `frame`'s placement (R row-major, then p: 12 values) at each
    /// row of the batch `q` into the rows of `out`; `None` past the last frame.
    pub(crate) fn placement_rows(&self, frame: usize, q: &[f64], out: &mut [f64]) -> Option<()> {
        let values = self.parameters.at(0.0, q);
        self.placements.get(frame)?.run_rows(&values, self.n, out);
        Some(())
    }

    /// J (6 x n, row-major) of frame `frame` at each row of the batch `q` into the rows of
    /// `out`; `None` past the last frame.
    pub(crate) fn jacobian_rows(&self, frame: usize, q: &[f64], out: &mut [f64]) -> Option<()> {
        let values = self.parameters.at(0.0, q);
        self.jacobians.get(frame)?.run_rows(&values, self.n, out);
        Some(())
    }
}
