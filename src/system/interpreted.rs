//! The interpreter route: a mechanism read at run time (a `.mech` file that was not compiled
//! in), derived by `mechanism-codegen` and evaluated through its [`Tape`](mechanism_codegen::Tape).
//!
//! It computes exactly what the code emitted by `mechanism!` computes: its tapes run the
//! programs of the same [`Routines`] (`mechanism_codegen::compile`), one per role it serves,
//! with the parameter-only values computed by the routines' parameter cache once per
//! parameter set, as the emitted struct caches them. The runtime gets a [`System`] for
//! any declaration without a rebuild, and the tests get a second route to check the
//! emitted code against. Everything that can be wrong with the programs is checked when the
//! `Interpreted` is built; an evaluation then cannot fail, and like the emitted code it lets
//! a non-finite value through to the outputs it reaches.
//!
//! [`Routines`]: mechanism_codegen::Routines

mod rows;

use mechanism_codegen::error::ProgramError;
use mechanism_codegen::{
    Equations, Error, EvaluationOutput, Model, Role, Tangents, compile_interpreted,
    constraint_tangent, full_tangent, residual_tangent,
};
use nalgebra::{DMatrix, Matrix3, Vector3};

use crate::system::constraint_rows::ConstraintRows;
use crate::system::forward_routine::ForwardRoutine;
use crate::system::model_info::system_info;
use crate::system::parameters::Parameters;
use crate::system::robotics::Robotics;
use crate::system::routine::{Routine, Values};
use crate::system::scatter::EvaluationScatter;
use crate::system::sparsity::Sparsity;
use crate::system::{
    ConstraintTangent, Evaluation, Kinematic, ParameterError, System, SystemInfo, Tangent,
};

/// A mechanism interpreted from its declaration. For its constraint rows alone (assembly,
/// the mobility), [`crate::InterpretedConstraints`] compiles much less.
#[derive(Clone)]
pub struct Interpreted {
    info: SystemInfo,
    /// The parameters and their cache ([`Role::ParameterCache`]).
    parameters: Parameters,
    /// M, C q', g, tau, Phi, Phi_q, Phi_t, gamma, T, Pi ([`Role::Evaluation`]).
    full: Routine,
    /// The structural pattern of M and Phi_q ([`mechanism_codegen::Routines::sparsity`]).
    sparsity: Sparsity,
    /// Where `full`'s outputs go: M and Phi_q at their pattern only.
    scatter: EvaluationScatter,
    /// The same from `full`'s lane register file ([`Interpreted::evaluate_rows`]).
    lane_scatter: EvaluationScatter,
    /// Phi, Phi_q, Phi_t ([`Role::constraint_rows`]).
    rows: ConstraintRows,
    /// dF/dq, dF/dq' of the residual, exact Jacobians for implicit integrators
    /// ([`Role::Tangent`]); `None` when built without ([`Tangents::None`]).
    tangent: Option<Routine>,
    /// D, R_q, R_q' of the constraint rows, for a model with velocity constraints
    /// ([`Role::ConstraintTangent`]).
    constraint_tangent: Option<Routine>,
    /// dtau_id/dq and dtau_id/dq' of the inverse dynamics ([`Role::InverseDynamicsDerivatives`]),
    /// when built with [`Tangents::Derivatives`].
    inverse_dynamics_derivatives: Option<Routine>,
    /// dtau_id/dp ([`Role::ParameterDerivatives`]), when built with
    /// [`Tangents::Derivatives`].
    parameter_derivatives: Option<Routine>,
    /// The drawn points' positions (3 per point), when the declaration draws
    /// ([`Role::Draw`]).
    draw: Option<Routine>,
    /// The fingerprint of the routines the tapes run
    /// ([`mechanism_codegen::Routines::fingerprint`]).
    routines: u64,
    /// The inverse dynamics and the link frames' placements and Jacobians, with their own
    /// parameter cache, when asked for ([`Interpreted::from_model_with`]).
    robotics: Option<Box<Robotics>>,
    /// The generated forward dynamics and tau, with their own parameter cache, for a
    /// mechanism without constraint rows whose forward dynamics is within the budget
    /// ([`System::forward_dynamics`]).
    forward: Option<Box<ForwardRoutine>>,
}

impl std::fmt::Debug for Interpreted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Interpreted")
            .field("info", &self.info)
            .finish_non_exhaustive()
    }
}

impl Interpreted {
    /// Parses, checks and derives the declaration `text` (the `.mech` grammar).
    ///
    /// # Errors
    /// The codegen error (parse errors carry line and column).
    pub fn from_source(text: &str) -> Result<Self, Error> {
        Self::from_source_with(text, mechanism_codegen::Budget::default())
    }

    /// [`Interpreted::from_source`] keeping the derivation to `budget` (its size, entries and
    /// work, and its progress report).
    ///
    /// # Errors
    /// As [`Interpreted::from_source`]; a derivation past its budget.
    pub fn from_source_with(text: &str, budget: mechanism_codegen::Budget) -> Result<Self, Error> {
        let model = mechanism_codegen::parse_model_str_with(text, budget)?;
        Self::from_model(model)
    }

    /// Derives the equations of `model` and compiles them for evaluation.
    ///
    /// # Errors
    /// A derivation or compilation error from codegen.
    pub fn from_model(mut model: Model) -> Result<Self, Error> {
        let eqs = mechanism_codegen::derive(&mut model)?;
        Self::from_equations(model, eqs)
    }

    /// Compiles already derived equations into [`mechanism_codegen::Routines`] and builds a
    /// tape for each role it serves (the evaluation; Phi; Phi_q; Phi_t; the residual's
    /// tangent; the drawing; the parameter cache), checking each once.
    ///
    /// # Errors
    /// A compilation error from codegen;
    /// [`mechanism_codegen::error::DerivationError::NotASymbol`] for a hand-built model whose
    /// parameter or coordinate entry is not a symbol,
    /// [`mechanism_codegen::error::EvalError::MissingValue`] for equations that read a symbol
    /// the model does not declare, [`mechanism_codegen::error::ProgramError::OutputCount`]
    /// for equations whose sizes are not n and m.
    pub fn from_equations(model: Model, eqs: Equations) -> Result<Self, Error> {
        Self::from_equations_with(model, eqs, Tangents::Residual)
    }

    /// [`Interpreted::from_equations`] with the tangents `tangents` asks for. Without the
    /// residual's tangent ([`Tangents::None`]: on a large mechanism, deriving and compiling
    /// it costs more than the rest of the routines together) [`System::tangent`] returns
    /// `None` and implicit integrators fall back to finite differences; with
    /// [`Tangents::WithConstraints`], as [`Interpreted::for_linearization`]; with
    /// [`Tangents::Derivatives`], as [`Interpreted::for_derivatives`].
    ///
    /// # Errors
    /// As [`Interpreted::from_equations`].
    pub fn from_equations_with(
        model: Model,
        eqs: Equations,
        tangents: Tangents,
    ) -> Result<Self, Error> {
        Self::build(model, eqs, tangents, false)
    }

    /// [`Interpreted::from_model`] with the constraint rows' tangents compiled for every
    /// constrained mechanism ([`System::constraint_tangent`], which
    /// [`crate::linearize_steady`] needs), not only for one with velocity constraints. Its
    /// routines then differ from the macro's by that one role.
    ///
    /// # Errors
    /// As [`Interpreted::from_model`].
    pub fn for_linearization(mut model: Model) -> Result<Self, Error> {
        let eqs = mechanism_codegen::derive(&mut model)?;
        Self::build(model, eqs, Tangents::WithConstraints, false)
    }

    /// [`Interpreted::from_model`] with every derivative compiled
    /// ([`Tangents::Derivatives`]): [`System::inverse_dynamics_derivatives`],
    /// [`System::parameter_derivatives`] and both tangents, which
    /// [`crate::DynamicsDerivatives`] reads for the forward and constrained dynamics'
    /// derivatives. Its routines are those `mechanism!` compiles from the same declaration,
    /// cut down to the roles it runs.
    ///
    /// # Errors
    /// As [`Interpreted::from_model`].
    pub fn for_derivatives(mut model: Model) -> Result<Self, Error> {
        let eqs = mechanism_codegen::derive(&mut model)?;
        Self::build(model, eqs, Tangents::Derivatives, false)
    }

    /// [`Interpreted::from_model`] with the tangents `tangents` asks for and, when
    /// `robotics`, the routines of [`System::inverse_dynamics`] (Newton-Euler for a tree of
    /// links), [`System::frame_placement`] and [`System::frame_jacobian`]
    /// ([`mechanism_codegen::compile_robotics`]): what the macro emits for every declaration
    /// and the interpreter otherwise leaves out. Those routines have their own parameter
    /// cache; [`System::set_parameter`] keeps both.
    ///
    /// # Errors
    /// As [`Interpreted::from_model`].
    ///
    /// # Example
    /// ```
    /// use mechanism::{Interpreted, Kinematic, System};
    /// use mechanism_codegen::{Tangents, parse_model_str};
    /// use nalgebra::{Matrix3, Vector3};
    ///
    /// // One link of length l turning about z: its tip frame sits at l (cos th, sin th, 0).
    /// let model = parse_model_str(
    ///     "pub struct Arm;
    ///      parameters { m = 1.0; l = 0.5; }
    ///      link upper {
    ///          joint = revolute(th, [0, 0, 1]);
    ///          mass = m; com = [l/2, 0, 0]; inertia = diag(0, m*l^2/12, m*l^2/12);
    ///      }
    ///      link tip { parent = upper; joint = fixed; xyz = [l, 0, 0]; }",
    /// )?;
    /// let arm = Interpreted::from_model_with(model, Tangents::None, true)?;
    /// let tip = arm.info().frame_index("tip").unwrap();
    /// let (mut r, mut p) = (Matrix3::zeros(), Vector3::zeros());
    /// arm.frame_placement(tip, &[0.3], &mut r, &mut p).unwrap();
    /// assert!((p - Vector3::new(0.5 * 0.3f64.cos(), 0.5 * 0.3f64.sin(), 0.0)).norm() < 1e-15);
    /// // The effort that turns it at 2 rad/s^2: (m l^2/3) th''.
    /// let mut u = [0.0];
    /// arm.inverse_dynamics(0.0, &[0.3], &[0.0], &[2.0], &mut u).unwrap();
    /// assert!((u[0] - 0.25 / 3.0 * 2.0).abs() < 1e-15);
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_model_with(
        mut model: Model,
        tangents: Tangents,
        robotics: bool,
    ) -> Result<Self, Error> {
        let eqs = mechanism_codegen::derive(&mut model)?;
        Self::build(model, eqs, tangents, robotics)
    }

    /// Compiles the routines of `tangents` (and, after them, the robotics routines when
    /// `robotics`) and builds their tapes.
    fn build(
        mut model: Model,
        eqs: Equations,
        tangents: Tangents,
        robotics: bool,
    ) -> Result<Self, Error> {
        let tangent = match tangents {
            Tangents::Derivatives => Some(full_tangent(&mut model, &eqs)?),
            Tangents::None => None,
            Tangents::Residual => Some(residual_tangent(&mut model, &eqs)?),
            Tangents::WithConstraints => {
                let mut tangent = residual_tangent(&mut model, &eqs)?;
                if eqs.m > 0 && tangent.constraints.is_none() {
                    tangent.constraints = Some(constraint_tangent(&mut model, &eqs)?);
                }
                Some(tangent)
            }
        };
        let routines = compile_interpreted(&mut model, &eqs, tangent.as_ref())?;
        // After the interpreted routines, so that theirs equal the macro's (symbol ids).
        let robotics = match robotics {
            true => Some(Box::new(Robotics::new(&mut model, &eqs)?)),
            false => None,
        };
        let forward = ForwardRoutine::new(&mut model, &eqs)?.map(Box::new);
        let (n, m) = (model.coordinates.len(), eqs.m);
        let full_len = EvaluationOutput::ORDER
            .iter()
            .map(|o| o.shape(n, m))
            .map(|(rows, cols)| rows * cols)
            .sum();
        let routine = |role: Role, outputs: usize| -> Result<Routine, Error> {
            Routine::new(routines.program(role)?, routines.sources(), outputs)
        };
        let draw = match routines.get(Role::Draw) {
            Some(_) => Some(routine(Role::Draw, 3 * model.drawing.points.len())?),
            None => None,
        };
        let sparsity = Sparsity::new(
            n,
            m,
            routines.sparsity(EvaluationOutput::Mass)?.entries,
            routines.sparsity(EvaluationOutput::PhiQ)?.entries,
        );
        let full = routine(Role::Evaluation, full_len)?;
        // `full` has full_len outputs (checked above), all that the scatter reads.
        let scatter = EvaluationScatter::new(&full, &sparsity).ok_or(Error::Program(
            ProgramError::OutputCount {
                what: "evaluation outputs",
                given: full_len,
                outputs: 0,
            },
        ))?;
        let lane_scatter =
            scatter
                .for_lanes(&full)
                .ok_or(Error::Program(ProgramError::OutputCount {
                    what: "evaluation outputs in lanes",
                    given: full_len,
                    outputs: 0,
                }))?;
        let constraint_tangent = match routines.get(Role::ConstraintTangent) {
            Some(_) => Some(routine(Role::ConstraintTangent, 3 * m * n)?),
            None => None,
        };
        let (inverse_dynamics_derivatives, parameter_derivatives) =
            match routines.get(Role::InverseDynamicsDerivatives) {
                Some(_) => (
                    Some(routine(Role::InverseDynamicsDerivatives, 2 * n * n)?),
                    Some(routine(
                        Role::ParameterDerivatives,
                        n * model.parameters.len(),
                    )?),
                ),
                None => (None, None),
            };
        Ok(Self {
            draw,
            constraint_tangent,
            inverse_dynamics_derivatives,
            parameter_derivatives,
            rows: ConstraintRows::new(&routines, &sparsity.jacobian, (m, n))?,
            full,
            sparsity,
            scatter,
            lane_scatter,
            tangent: match routines.get(Role::Tangent) {
                Some(_) => Some(routine(Role::Tangent, 2 * n * n)?),
                None => None,
            },
            parameters: Parameters::new(&model, &routines)?,
            routines: routines.fingerprint(),
            info: system_info(&model, m),
            robotics,
            forward,
        }
        .with_initial_values())
    }

    /// This system with [`SystemInfo`]'s initial values computed by the routines'
    /// [`Role::InitialValues`] program, the one that evaluates them after each change.
    fn with_initial_values(mut self) -> Self {
        self.parameters.write_initial_values(&mut self.info);
        self
    }

    /// [`mechanism_codegen::Routines::fingerprint`] of the routines this system's tapes run:
    /// the routines `mechanism!` compiles from the same declaration (whose fingerprint it
    /// emits as `__ROUTINES`) cut down by `Routines::restricted` to `Role::interpreted` with
    /// this system's tangents.
    #[doc(hidden)]
    pub fn routines_fingerprint(&self) -> u64 {
        self.routines
    }

    /// The values of an evaluation at (t, q) with the current parameters.
    fn at<'a>(&'a self, t: f64, q: &'a [f64]) -> Values<'a> {
        self.parameters.at(t, q)
    }
}

/// The two n x n blocks of a tangent program's output `v` (row-major: d/dq, then d/dq')
/// into `out`'s stiffness and damping; `None` where an entry is not finite, on which the
/// caller falls back to finite differences (the residual's tangent) or says it has none.
fn copy_tangent(v: &[f64], n: usize, out: &mut Tangent) -> Option<()> {
    if !v.iter().all(|x| x.is_finite()) {
        return None;
    }
    copy_block(v, n, n, &mut out.stiffness);
    copy_block(&v[n * n..], n, n, &mut out.damping);
    Some(())
}

/// Copies a row-major block of `rows x cols` values into `dst`.
fn copy_block(src: &[f64], rows: usize, cols: usize, dst: &mut DMatrix<f64>) {
    for i in 0..rows {
        for j in 0..cols {
            dst[(i, j)] = src[i * cols + j];
        }
    }
}

impl Kinematic for Interpreted {
    fn info(&self) -> &SystemInfo {
        &self.info
    }

    fn constraints(&self, t: f64, q: &[f64], phi: &mut [f64]) {
        self.rows.constraints(&self.at(t, q), phi);
    }

    fn constraint_jacobian(&self, t: f64, q: &[f64], phi_q: &mut DMatrix<f64>, phi_t: &mut [f64]) {
        // Phi_q at its structural nonzeros only (the others stay zero; see System::sparsity).
        self.rows.jacobian(&self.at(t, q), phi_q, phi_t);
    }
}

impl System for Interpreted {
    fn parameter_values(&self, out: &mut [f64]) {
        for (o, v) in out.iter_mut().zip(self.parameters.values()) {
            *o = *v;
        }
    }

    fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError> {
        self.parameters.set(index, value)?;
        self.parameters.write_initial_values(&mut self.info);
        if let Some(robotics) = &mut self.robotics {
            // The same value the check above accepted, for the routines' own cache.
            robotics.set_parameter(index, value)?;
        }
        if let Some(forward) = &mut self.forward {
            forward.set_parameter(index, value)?;
        }
        Ok(())
    }

    fn evaluate(&self, t: f64, q: &[f64], qd: &[f64], out: &mut Evaluation) {
        let values = Values {
            qd,
            ..self.at(t, q)
        };
        self.full
            .execute(&values, |registers| self.scatter.write(registers, out));
    }

    fn sparsity(&self) -> Option<&Sparsity> {
        Some(&self.sparsity)
    }

    fn draw_points(&self, t: f64, q: &[f64], out: &mut [f64]) {
        if let Some(draw) = &self.draw {
            draw.run(&self.at(t, q), |v| {
                if let Some(dst) = out.get_mut(..v.len()) {
                    dst.copy_from_slice(v);
                }
            });
        }
    }

    fn inverse_dynamics(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut [f64],
    ) -> Option<()> {
        self.robotics.as_ref()?.inverse_dynamics(t, q, qd, qdd, out);
        Some(())
    }

    fn forward_dynamics(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        effort: &[f64],
        qdd: &mut [f64],
        forces: &mut [f64],
    ) -> Option<bool> {
        let forward = self.forward.as_ref()?;
        Some(forward.solve(t, q, qd, effort, qdd, forces))
    }

    fn frame_placement(
        &self,
        frame: usize,
        q: &[f64],
        rotation: &mut Matrix3<f64>,
        position: &mut Vector3<f64>,
    ) -> Option<()> {
        self.robotics
            .as_ref()?
            .placement(frame, q, rotation, position)
    }

    fn frame_jacobian(&self, frame: usize, q: &[f64], out: &mut DMatrix<f64>) -> Option<()> {
        self.robotics.as_ref()?.jacobian(frame, q, out)
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
        let n = self.info.n();
        let values = Values {
            qd,
            qdd,
            lambda,
            ..self.at(t, q)
        };
        self.tangent
            .as_ref()?
            .run(&values, |v| copy_tangent(v, n, out))
    }

    fn constraint_tangent(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut ConstraintTangent,
    ) -> Option<()> {
        let (n, m) = (self.info.n(), self.info.m());
        let values = Values {
            qd,
            qdd,
            ..self.at(t, q)
        };
        self.constraint_tangent.as_ref()?.run(&values, |v| {
            if !v.iter().all(|x| x.is_finite()) {
                return None;
            }
            copy_block(v, m, n, &mut out.velocity);
            copy_block(&v[m * n..], m, n, &mut out.stiffness);
            copy_block(&v[2 * m * n..], m, n, &mut out.damping);
            Some(())
        })
    }

    fn inverse_dynamics_derivatives(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut Tangent,
    ) -> Option<()> {
        let n = self.info.n();
        let values = Values {
            qd,
            qdd,
            ..self.at(t, q)
        };
        self.inverse_dynamics_derivatives
            .as_ref()?
            .run(&values, |v| copy_tangent(v, n, out))
    }

    fn parameter_derivatives(
        &self,
        t: f64,
        q: &[f64],
        qd: &[f64],
        qdd: &[f64],
        out: &mut DMatrix<f64>,
    ) -> Option<()> {
        let (n, p) = (self.info.n(), self.parameters.values().len());
        if out.shape() != (n, p) {
            return None;
        }
        let values = Values {
            qd,
            qdd,
            ..self.at(t, q)
        };
        self.parameter_derivatives.as_ref()?.run(&values, |v| {
            if !v.iter().all(|x| x.is_finite()) {
                return None;
            }
            copy_block(v, n, p, out);
            Some(())
        })
    }
}
