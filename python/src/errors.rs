//! The exceptions: one class per kind of failure, each carrying the one-line message the
//! command-line tool prints for it.
//!
//! ```text
//! MechanismError                 every failure of this package
//! ├── DeclarationError           a declaration or URDF that cannot be read or derived
//! ├── InputError                 an argument: unknown name, bad value, wrong shape
//! └── SolverError                a computation that cannot go on (the library's Error)
//!     ├── AssemblyError          the constraints cannot be closed from the given state
//!     ├── SingularError          the motion or a drive is not determined there
//!     └── IntegrationError       a run that stops midway (step size, NaN, divergence)
//! ```

use mechanism::Error;
use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    mechanism,
    MechanismError,
    PyException,
    "Every failure of the mechanism package; its message is the command-line tool's one line."
);
create_exception!(
    mechanism,
    DeclarationError,
    MechanismError,
    "A declaration (.mech) or URDF that cannot be read, parsed, checked or derived; the \
     message names `file:line:column` where it has one."
);
create_exception!(
    mechanism,
    InputError,
    MechanismError,
    "An argument that cannot be used: an unknown parameter, coordinate, frame or mechanism \
     name (with the likely one it mistypes), a value that is not finite or out of range, an \
     array of the wrong shape."
);
create_exception!(
    mechanism,
    SolverError,
    MechanismError,
    "A computation that cannot go on at the state it reached (the library's typed errors)."
);
create_exception!(
    mechanism,
    AssemblyError,
    SolverError,
    "The constraints cannot be closed: Newton does not converge from the guesses, the \
     independent coordinates do not determine the others, or the initial state contradicts \
     a velocity row."
);
create_exception!(
    mechanism,
    SingularError,
    SolverError,
    "The motion is not determined: a singular configuration, a mass matrix singular on an \
     allowed motion, drives that conflict or leave the mechanism's reach, no steady state to \
     linearise about."
);
create_exception!(
    mechanism,
    IntegrationError,
    SolverError,
    "A run that stops midway: the step size collapses, a value becomes NaN or infinite, the \
     state diverges, or the span needs more steps than allowed."
);

/// The exception for the library's error `e`, with its message.
pub fn solver(e: Error) -> PyErr {
    kind(&e)(e.to_string())
}

/// The constructor of the exception class for the library's error `e`.
pub fn kind(e: &Error) -> fn(String) -> PyErr {
    match e {
        Error::NewtonDidNotConverge { .. }
        | Error::ConstraintsUnsatisfiable { .. }
        | Error::IndependentSetDoesNotDetermine { .. }
        | Error::OverSpecified { .. }
        | Error::VelocityRowRedundant { .. }
        | Error::VelocityRowContradicts { .. }
        | Error::InconsistentInitialState { .. } => AssemblyError::new_err,
        Error::SingularConfiguration { .. }
        | Error::UndeterminedMotion { .. }
        | Error::ConflictingDrives { .. }
        | Error::DriveOutOfReach { .. }
        | Error::DriveKink { .. }
        | Error::NotSteady { .. }
        | Error::Linearization { .. } => SingularError::new_err,
        Error::StepSizeUnderflow { .. }
        | Error::TooManySteps { .. }
        | Error::StepSizeCollapse { .. }
        | Error::StuckAtSingularPosition { .. }
        | Error::FixedStepTooSmall { .. }
        | Error::StepTooLarge { .. }
        | Error::SpanTooLong { .. }
        | Error::Diverged { .. }
        | Error::NonFinite { .. }
        | Error::NonFiniteTerm { .. } => IntegrationError::new_err,
        Error::UnknownCoordinate { .. }
        | Error::UnknownParameter { .. }
        | Error::UnknownDriver { .. }
        | Error::RepeatedCoordinate { .. }
        | Error::TooFewDrives { .. }
        | Error::InvalidOption { .. }
        | Error::WrongLength { .. }
        | Error::TooMuchOutput { .. }
        | Error::TooManySamples { .. } => InputError::new_err,
        #[allow(unreachable_patterns)]
        _ => SolverError::new_err,
    }
}

/// [`DeclarationError`] for the codegen error `e` of the declaration shown as `shown`:
/// `shown:line:column: message` where the error has a place, as the command-line tool
/// prints it.
pub fn declaration(shown: &str, e: &mechanism_codegen::Error) -> PyErr {
    DeclarationError::new_err(located(shown, e))
}

/// `shown:line:column: message` for a codegen error with a place, else `shown: message`.
pub fn located(shown: &str, e: &mechanism_codegen::Error) -> String {
    match e.location() {
        Some(l) => format!("{shown}:{}:{}: {}", l.line, l.column, e.message()),
        None => format!("{shown}: {e}"),
    }
}

/// [`InputError`] with `message`.
pub fn input(message: impl Into<String>) -> PyErr {
    InputError::new_err(message.into())
}

/// `" (did you mean `l2`?)"` when one of `names` is a likely typo of `name`, else nothing
/// (the command-line tool's suggestion).
pub fn did_you_mean(name: &str, names: &[String]) -> String {
    match mechanism_codegen::closest(name, names.iter().map(String::as_str)) {
        Some(c) => format!(" (did you mean `{c}`?)"),
        None => String::new(),
    }
}

/// Registers the exception classes in `module`.
pub fn register(module: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = module.py();
    module.add("MechanismError", py.get_type::<MechanismError>())?;
    module.add("DeclarationError", py.get_type::<DeclarationError>())?;
    module.add("InputError", py.get_type::<InputError>())?;
    module.add("SolverError", py.get_type::<SolverError>())?;
    module.add("AssemblyError", py.get_type::<AssemblyError>())?;
    module.add("SingularError", py.get_type::<SingularError>())?;
    module.add("IntegrationError", py.get_type::<IntegrationError>())?;
    Ok(())
}
