//! The interpreted constraint rows: the tapes of Phi, Phi_q and Phi_t
//! ([`Role::constraint_rows`]), shared by [`crate::Interpreted`] and
//! [`crate::InterpretedConstraints`].

use mechanism_codegen::error::ProgramError;
use mechanism_codegen::{Error, Role, Routines};
use nalgebra::DMatrix;

use crate::system::routine::{Routine, Values};
use crate::system::scatter::{matrix_scatter, write_matrix};

/// The tapes of Phi, Phi_q and Phi_t, with where Phi_q's structural nonzeros go.
#[derive(Clone, Debug)]
pub(crate) struct ConstraintRows {
    /// Phi ([`Role::Constraints`]).
    phi: Routine,
    /// Phi_q ([`Role::ConstraintJacobian`]).
    jacobian: Routine,
    /// (register slot, column-major index) of each structural nonzero of Phi_q.
    jacobian_scatter: Vec<(usize, usize)>,
    /// Phi_t ([`Role::ConstraintTimeDerivative`]).
    time_derivative: Routine,
}

impl ConstraintRows {
    /// The tapes of the constraint programs of `routines`, for m rows and n coordinates,
    /// with Phi_q written at `pattern` (row, column) only.
    ///
    /// # Errors
    /// As [`Routine::new`]; [`ProgramError::OutputCount`] when the Jacobian's program has no
    /// output entry for an entry of `pattern`.
    pub(crate) fn new(
        routines: &Routines,
        pattern: &[(usize, usize)],
        (m, n): (usize, usize),
    ) -> Result<Self, Error> {
        let routine = |role: Role, outputs: usize| -> Result<Routine, Error> {
            Routine::new(routines.program(role)?, routines.sources(), outputs)
        };
        let jacobian = routine(Role::ConstraintJacobian, m * n)?;
        let jacobian_scatter = matrix_scatter(&jacobian, 0, (m, n), pattern).ok_or(
            Error::Program(ProgramError::OutputCount {
                what: "constraint Jacobian outputs",
                given: m * n,
                outputs: 0,
            }),
        )?;
        Ok(Self {
            phi: routine(Role::Constraints, m)?,
            jacobian,
            jacobian_scatter,
            time_derivative: routine(Role::ConstraintTimeDerivative, m)?,
        })
    }

    /// Phi at `at` into `phi`.
    pub(crate) fn constraints(&self, at: &Values<'_>, phi: &mut [f64]) {
        self.phi.run(at, |v| phi.copy_from_slice(v));
    }

    /// Phi_q (at its structural nonzeros only; the others stay as they are, zero) and Phi_t
    /// at `at`.
    pub(crate) fn jacobian(&self, at: &Values<'_>, phi_q: &mut DMatrix<f64>, phi_t: &mut [f64]) {
        self.jacobian.execute(at, |registers| {
            write_matrix(&self.jacobian_scatter, registers, phi_q.as_mut_slice());
        });
        self.time_derivative.run(at, |v| phi_t.copy_from_slice(v));
    }
}
