//! Where each output matrix of an emitted body goes: an indexed matrix, a vector, a
//! column-major slice, a whole-matrix assignment, the body's tail expression, or nowhere.

use proc_macro2::TokenStream;

/// Where one output matrix of the program goes.
#[derive(Clone, Debug)]
pub enum OutputTarget {
    /// `name[(i, j)] = value;` for each entry (a nalgebra matrix). With `zeroed`, the
    /// caller guarantees the matrix starts at zero and entries that are 0 are not written.
    Matrix {
        /// The matrix place expression (`out_mass`, `m`).
        name: TokenStream,
        /// Skip entries equal to 0.
        zeroed: bool,
    },
    /// `name[k] = value;` for a row or column vector (a nalgebra vector, an array, a slice).
    /// Only for outputs with one row or one column: nalgebra's linear index of a matrix is
    /// column-major, so a general matrix must use [`OutputTarget::Matrix`].
    Vector {
        /// The vector place expression.
        name: TokenStream,
        /// Skip entries equal to 0.
        zeroed: bool,
    },
    /// `name[i + j * rows] = value;` for each entry of the structural pattern
    /// ([`crate::Sparsity`]) only: a column-major slice (the storage of a run-time matrix)
    /// that the caller keeps at zero on the structural zeros, which are never written.
    ColumnMajor {
        /// The slice place expression.
        name: TokenStream,
    },
    /// `name = [[column 0], [column 1], ..];` once, after the last instruction: every entry
    /// (zeros included), column by column, into a place of type `[[f64; rows]; cols]` (a
    /// nalgebra matrix's storage, `m.data.0`). One assignment instead of an indexed store per
    /// entry: what [`crate::LEAN_ABOVE`] bodies use, where rustc's cost per statement counts.
    Columns {
        /// The place expression (`out.data.0`).
        name: TokenStream,
    },
    /// The value of a 1 x 1 output is the body's tail expression (at most one per body).
    Return,
    /// Not emitted: instructions only this output needs are left out.
    Skip,
}
