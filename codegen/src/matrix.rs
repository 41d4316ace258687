//! Symbolic matrices over the arena, and Van Khang's matrix calculus.
//!
//! Layout (Van Khang 2010, ERRATA item 5): for A(x) of size m x p and x of size n, the
//! matrix derivative dA/dx has size m x (p n); entry a_ij is replaced by its row gradient
//! da_ij/dx^T, so (dA/dx)[i, j n + k] = d a_ij / d x_k.

use crate::expr::{Arena, Id};

/// A dense symbolic matrix, row-major.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Matrix {
    /// Number of rows.
    pub rows: usize,
    /// Number of columns.
    pub cols: usize,
    /// Entries, row-major: entry (i, j) is `data[i * cols + j]`.
    pub data: Vec<Id>,
}

impl Matrix {
    /// The rows x cols zero matrix.
    pub fn zeros(arena: &mut Arena, rows: usize, cols: usize) -> Self {
        let z = arena.int(0);
        Self { rows, cols, data: vec![z; rows * cols] }
    }

    /// A matrix from a function of (i, j).
    pub fn from_fn(rows: usize, cols: usize, mut f: impl FnMut(usize, usize) -> Id) -> Self {
        let mut data = Vec::with_capacity(rows * cols);
        for i in 0..rows {
            for j in 0..cols {
                data.push(f(i, j));
            }
        }
        Self { rows, cols, data }
    }

    /// A column vector.
    pub fn column(entries: Vec<Id>) -> Self {
        Self { rows: entries.len(), cols: 1, data: entries }
    }

    /// Entry (i, j).
    pub fn get(&self, i: usize, j: usize) -> Id {
        self.data[i * self.cols + j]
    }

    /// Sets entry (i, j).
    pub fn set(&mut self, i: usize, j: usize, v: Id) {
        self.data[i * self.cols + j] = v;
    }
}
