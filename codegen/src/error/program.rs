//! Errors of the back end's API (`program`, `compile`, `emit`): a request that does not fit
//! the program or routines it is made of. A caller that builds its requests from the
//! [`Routines`](crate::Routines) it was given never meets them.

/// A request that does not fit a program's outputs or the compiled routines.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
#[non_exhaustive]
pub enum ProgramError {
    /// A program output index past the last output.
    #[error("the program has {outputs} outputs, not {wanted}")]
    NoSuchOutput {
        /// Outputs of the program.
        outputs: usize,
        /// The 1-based count asked for.
        wanted: usize,
    },
    /// A role with no compiled routine (a frame past the last, the drawing of a model that
    /// draws nothing).
    #[error("no routine was compiled for the role {role}")]
    NoSuchRoutine {
        /// The role, as `Debug` prints it.
        role: String,
    },
    /// A list of output slots or targets whose length is not the program's output count.
    #[error("{given} {what} for {outputs} outputs")]
    OutputCount {
        /// "output slots" or "output targets for a program with".
        what: &'static str,
        /// Slots or targets given.
        given: usize,
        /// Outputs of the program.
        outputs: usize,
    },
    /// An emission prefix that is not a Rust identifier.
    #[error("register prefix `{prefix}` is not an identifier")]
    RegisterPrefix {
        /// The prefix.
        prefix: String,
    },
    /// More than one output targeted as the body's returned value.
    #[error("at most one output can be the returned value, and outputs {first} and {second} are")]
    SeveralReturns {
        /// The first output targeted as the returned value (0-based).
        first: usize,
        /// The second (0-based).
        second: usize,
    },
    /// A returned output that is not 1 x 1.
    #[error("the returned output {output} must be 1 x 1, not {rows} x {cols}")]
    ReturnNotScalar {
        /// The output (0-based).
        output: usize,
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
    },
    /// A matrix output targeted as a vector.
    #[error(
        "output {output} is {rows} x {cols} and cannot be written as a vector; use a matrix target"
    )]
    MatrixAsVector {
        /// The output (0-based).
        output: usize,
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
    },
}
