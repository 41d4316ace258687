//! The constraint rows of a declaration alone, interpreted: Phi, Phi_q and Phi_t compiled
//! without the dynamics ([`mechanism_codegen::compile_constraints`]).
//!
//! Assembly and the [`crate::mobility()`] read only these. `mechanism equations` reports
//! the mobility of the equations it prints; compiling M, C q', g and the rest for that
//! (an [`Interpreted`](crate::Interpreted)) would be most of its work on a large mechanism.
//! The values are those of [`Interpreted`](crate::Interpreted), from programs of the same
//! expressions.

use mechanism_codegen::{Equations, Error, EvaluationOutput, Model, compile_constraints};
use nalgebra::DMatrix;

use crate::system::constraint_rows::ConstraintRows;
use crate::system::model_info::system_info;
use crate::system::parameters::Parameters;
use crate::system::{Kinematic, ParameterError, SystemInfo};

/// The [`Kinematic`] face of a derived declaration: its names and constraint rows, with the
/// parameters at their declared defaults until [`InterpretedConstraints::set_parameter`]
/// changes them.
#[derive(Clone, Debug)]
pub struct InterpretedConstraints {
    info: SystemInfo,
    /// The parameters and their cache (the constraint rows' parameter-only values).
    parameters: Parameters,
    /// Phi, Phi_q, Phi_t.
    rows: ConstraintRows,
}

impl InterpretedConstraints {
    /// Compiles the constraint rows of the derived equations `eqs` of `model`.
    ///
    /// # Errors
    /// A compilation error from codegen; as [`crate::Interpreted::from_equations`] for
    /// equations that read an undeclared symbol or whose sizes are not n and m.
    ///
    /// # Example
    /// ```
    /// use mechanism::{InterpretedConstraints, mobility};
    ///
    /// // A point on a circle of radius 1, x^2 + y^2 = 1: one degree of freedom.
    /// let mut model = mechanism_codegen::parse_model_str(
    ///     "pub struct Ring;
    ///      coordinates { x = 1.0; y = 0.0; }
    ///      independent { y = 0.0; }
    ///      kinetic = (der(x)^2 + der(y)^2)/2;
    ///      potential = 0;
    ///      constraints { x^2 + y^2 - 1; }",
    /// )?;
    /// let eqs = mechanism_codegen::derive(&mut model)?;
    /// let ring = InterpretedConstraints::from_equations(model, &eqs)?;
    /// let mob = mobility(&ring, 0.0, &[0.6, 0.8])?;
    /// assert_eq!((mob.rank, mob.degrees_of_freedom), (1, 1));
    /// # Ok::<(), Box<dyn std::error::Error>>(())
    /// ```
    pub fn from_equations(mut model: Model, eqs: &Equations) -> Result<Self, Error> {
        let routines = compile_constraints(&mut model, eqs)?;
        let (n, m) = (model.coordinates.len(), eqs.m);
        let pattern = routines.sparsity(EvaluationOutput::PhiQ)?.entries;
        let parameters = Parameters::new(&model, &routines)?;
        let mut info = system_info(&model, m);
        parameters.write_initial_values(&mut info);
        Ok(Self {
            rows: ConstraintRows::new(&routines, &pattern, (m, n))?,
            parameters,
            info,
        })
    }

    /// The current parameter values, in the declaration order of
    /// [`SystemInfo::parameters`].
    pub fn parameter_values(&self) -> &[f64] {
        self.parameters.values()
    }

    /// Sets parameter `index` (in [`SystemInfo::parameters`]) to `value`, as
    /// [`crate::System::set_parameter`] does for a whole system: the rows' parameter-only
    /// values and the initial values of [`Kinematic::info`] are recomputed.
    ///
    /// # Errors
    /// As [`crate::System::set_parameter`]: an index out of range, a value outside the
    /// declared range.
    pub fn set_parameter(&mut self, index: usize, value: f64) -> Result<(), ParameterError> {
        self.parameters.set(index, value)?;
        self.parameters.write_initial_values(&mut self.info);
        Ok(())
    }
}

impl Kinematic for InterpretedConstraints {
    fn info(&self) -> &SystemInfo {
        &self.info
    }

    fn constraints(&self, t: f64, q: &[f64], phi: &mut [f64]) {
        self.rows.constraints(&self.parameters.at(t, q), phi);
    }

    fn constraint_jacobian(&self, t: f64, q: &[f64], phi_q: &mut DMatrix<f64>, phi_t: &mut [f64]) {
        // Phi_q at its structural nonzeros only (the others stay zero).
        self.rows.jacobian(&self.parameters.at(t, q), phi_q, phi_t);
    }
}
