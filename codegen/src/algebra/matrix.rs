//! Symbolic matrices over the arena, and Van Khang's matrix calculus.
//!
//! Layout (Van Khang 2010): for A(x) of size m x p and x of size n, the
//! matrix derivative dA/dx has size m x (p n); entry a_ij is replaced by its row gradient
//! da_ij/dx^T, so (dA/dx)[i, j n + k] = d a_ij / d x_k.

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, Id, SymbolId, SymbolKind};
use crate::error::AlgebraError;
use crate::error::{Error, Result};

/// A dense symbolic matrix, row-major. Built through its constructors, it always has
/// rows x cols entries.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Matrix {
    /// Number of rows.
    pub(crate) rows: usize,
    /// Number of columns.
    pub(crate) cols: usize,
    /// Entries, row-major: entry (i, j) is `data[i * cols + j]`.
    pub(crate) data: Vec<Id>,
}

impl Matrix {
    /// The rows x cols matrix with the row-major entries `data`.
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::MalformedMatrix`] when `data` does not have rows x cols
    /// entries.
    pub fn new(rows: usize, cols: usize, data: Vec<Id>) -> Result<Self> {
        if rows.checked_mul(cols) != Some(data.len()) {
            return Err(Error::Algebra(AlgebraError::MalformedMatrix {
                rows,
                cols,
                len: data.len(),
            }));
        }
        Ok(Self { rows, cols, data })
    }

    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.cols
    }

    /// The entries, row-major: entry (i, j) is `data()[i * cols() + j]`.
    pub fn data(&self) -> &[Id] {
        &self.data
    }

    /// The rows x cols zero matrix.
    pub fn zeros(arena: &mut Arena, rows: usize, cols: usize) -> Self {
        let z = arena.int(0);
        Self {
            rows,
            cols,
            data: vec![z; rows * cols],
        }
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
        Self {
            rows: entries.len(),
            cols: 1,
            data: entries,
        }
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

impl Matrix {
    /// Checks that `data` has rows x cols entries and that every entry is a node of `arena`.
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::Shape`] for a wrong `data` length,
    /// [`crate::error::AlgebraError::InvalidId`] for a foreign id.
    pub fn validate(&self, arena: &Arena) -> Result<()> {
        if self.rows.checked_mul(self.cols) != Some(self.data.len()) {
            return Err(Error::Algebra(AlgebraError::Shape {
                operation: "validate",
                left_rows: self.rows,
                left_cols: self.cols,
                right_rows: self.data.len(),
                right_cols: 1,
            }));
        }
        match self.data.iter().find(|id| id.index() >= arena.len()) {
            Some(bad) => Err(Error::Algebra(AlgebraError::InvalidId {
                id: bad.0,
                len: arena.len(),
            })),
            None => Ok(()),
        }
    }

    fn shape_error(&self, other: &Matrix, operation: &'static str) -> Error {
        Error::Algebra(AlgebraError::Shape {
            operation,
            left_rows: self.rows,
            left_cols: self.cols,
            right_rows: other.rows,
            right_cols: other.cols,
        })
    }

    /// The n x n identity I_n.
    pub fn identity(arena: &mut Arena, n: usize) -> Self {
        let (zero, one) = (arena.int(0), arena.int(1));
        Self::from_fn(n, n, |i, j| if i == j { one } else { zero })
    }

    /// A^T.
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::Shape`] when `data` does not have rows x cols entries.
    pub fn transpose(&self) -> Result<Self> {
        if self.rows.checked_mul(self.cols) != Some(self.data.len()) {
            return Err(self.shape_error(self, "transpose"));
        }
        Ok(Self::from_fn(self.cols, self.rows, |i, j| self.get(j, i)))
    }

    fn entrywise(
        &self,
        arena: &mut Arena,
        other: &Matrix,
        operation: &'static str,
        f: impl Fn(&mut Arena, Id, Id) -> Id,
    ) -> Result<Self> {
        self.validate(arena)?;
        other.validate(arena)?;
        if self.rows != other.rows || self.cols != other.cols {
            return Err(self.shape_error(other, operation));
        }
        let data = self
            .data
            .iter()
            .zip(&other.data)
            .map(|(&a, &b)| f(arena, a, b))
            .collect();
        Ok(Self {
            rows: self.rows,
            cols: self.cols,
            data,
        })
    }

    /// A + B, entry by entry.
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::Shape`] when the sizes differ;
    /// [`crate::error::AlgebraError::InvalidId`] for a foreign id.
    pub fn add(&self, arena: &mut Arena, other: &Matrix) -> Result<Self> {
        self.entrywise(arena, other, "add", |a, x, y| a.add2(x, y))
    }

    /// A - B, entry by entry.
    ///
    /// # Errors
    /// As [`Matrix::add`].
    pub fn sub(&self, arena: &mut Arena, other: &Matrix) -> Result<Self> {
        self.entrywise(arena, other, "sub", |a, x, y| a.sub(x, y))
    }

    /// c A for a scalar expression c.
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::Shape`] or [`crate::error::AlgebraError::InvalidId`] for a
    /// malformed matrix or a foreign `c`.
    pub fn scale(&self, arena: &mut Arena, c: Id) -> Result<Self> {
        self.validate(arena)?;
        if c.index() >= arena.len() {
            return Err(Error::Algebra(AlgebraError::InvalidId {
                id: c.0,
                len: arena.len(),
            }));
        }
        let data = self.data.iter().map(|&a| arena.mul2(c, a)).collect();
        Ok(Self {
            rows: self.rows,
            cols: self.cols,
            data,
        })
    }

    /// True when this is a square identity matrix, entry by entry as constants.
    pub fn is_identity(&self, arena: &Arena) -> bool {
        self.rows == self.cols
            && self.data.iter().enumerate().all(|(k, &e)| {
                let want = if k / self.cols == k % self.cols {
                    1.0
                } else {
                    0.0
                };
                e.index() < arena.len() && arena.as_number(e).is_some_and(|n| n.to_f64() == want)
            })
    }

    /// True when every entry is the constant 0.
    pub fn is_zero(&self, arena: &Arena) -> bool {
        self.data
            .iter()
            .all(|&a| a.index() < arena.len() && arena.is_zero(a))
    }

    /// The product A B, (AB)_ij = sum_k a_ik b_kj, as one canonical sum per entry.
    ///
    /// Zero entries are skipped on both sides (the cost is the number of nonzero products,
    /// not rows x inner x cols), which keeps products with Kronecker factors such as
    /// (dM/dq)(I_n kron q') cheap.
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::Shape`] when A's columns differ from B's rows;
    /// [`crate::error::AlgebraError::InvalidId`].
    pub fn mul(&self, arena: &mut Arena, other: &Matrix) -> Result<Self> {
        self.validate(arena)?;
        other.validate(arena)?;
        if self.cols != other.rows {
            return Err(self.shape_error(other, "mul"));
        }
        let nonzero: Vec<Vec<(usize, Id)>> = (0..other.rows)
            .map(|k| {
                (0..other.cols)
                    .map(|j| (j, other.get(k, j)))
                    .filter(|&(_, b)| !arena.is_zero(b))
                    .collect()
            })
            .collect();
        let mut acc: Vec<Vec<Id>> = vec![Vec::new(); other.cols];
        let mut data = Vec::with_capacity(self.rows * other.cols);
        for i in 0..self.rows {
            for (k, row) in nonzero.iter().enumerate() {
                let a = self.get(i, k);
                if arena.is_zero(a) {
                    continue;
                }
                for &(j, b) in row {
                    acc[j].push(arena.mul2(a, b));
                }
            }
            for terms in acc.iter_mut() {
                data.push(arena.add(terms));
                terms.clear();
            }
        }
        Ok(Self {
            rows: self.rows,
            cols: other.cols,
            data,
        })
    }

    /// The Kronecker product A kron B: the block matrix [a_ij B], of size
    /// (rows_A rows_B) x (cols_A cols_B); entry (i rows_B + k, j cols_B + l) is a_ij b_kl.
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::Shape`] or [`crate::error::AlgebraError::InvalidId`] for a
    /// malformed operand.
    pub fn kron(&self, arena: &mut Arena, other: &Matrix) -> Result<Self> {
        self.validate(arena)?;
        other.validate(arena)?;
        let (rows, cols) = (self.rows * other.rows, self.cols * other.cols);
        let zero = arena.int(0);
        let mut data = vec![zero; rows * cols];
        for i in 0..self.rows {
            for j in 0..self.cols {
                let a = self.get(i, j);
                if arena.is_zero(a) {
                    continue;
                }
                for k in 0..other.rows {
                    for l in 0..other.cols {
                        let b = other.get(k, l);
                        if !arena.is_zero(b) {
                            data[(i * other.rows + k) * cols + j * other.cols + l] =
                                arena.mul2(a, b);
                        }
                    }
                }
            }
        }
        Ok(Self { rows, cols, data })
    }

    /// Van Khang's matrix derivative dA/dx (Van Khang 2010): for A of size
    /// m x p and x = (x_1, ..., x_n), the m x (p n) matrix in which each entry a_ij is replaced
    /// by its row gradient, (dA/dx)[i, j n + k] = d a_ij / d x_k.
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::Shape`], [`crate::error::AlgebraError::InvalidId`] or
    /// [`crate::error::AlgebraError::UnknownSymbolId`] for a malformed matrix or a symbol not
    /// in `arena`; differentiation errors (see [`Differentiator::diff`]).
    pub fn khang_derivative(
        &self,
        arena: &mut Arena,
        diff: &mut Differentiator,
        x: &[SymbolId],
    ) -> Result<Self> {
        self.validate(arena)?;
        let n = x.len();
        let mut data = Vec::with_capacity(self.data.len() * n);
        for &a in &self.data {
            for &s in x {
                data.push(diff.diff(arena, a, s)?);
            }
        }
        // Row-major m x (p n) with entry (i, j n + k) at i p n + j n + k: exactly the order above.
        Ok(Self {
            rows: self.rows,
            cols: self.cols * n,
            data,
        })
    }

    /// The total time derivative by Theorem 1 (Van Khang 2010):
    /// dA/dt = (dA/dx)(I_p kron x') + dA/dt|explicit, where x' are the `derivative` links of
    /// the symbols `x` and the explicit part differentiates with respect to every time symbol
    /// of the arena. Symbols of A outside `x` (and not time) are held constant: pass
    /// x = (q, q') to differentiate an A(q, q', t).
    ///
    /// # Errors
    /// [`crate::error::AlgebraError::NoTimeDerivative`] when a symbol of `x` has no derivative
    /// link; otherwise as [`Matrix::khang_derivative`].
    pub fn time_derivative(
        &self,
        arena: &mut Arena,
        diff: &mut Differentiator,
        x: &[SymbolId],
    ) -> Result<Self> {
        let rates: Vec<Id> = x
            .iter()
            .map(|&s| {
                let info = arena.symbols().get(s.0 as usize).ok_or_else(|| {
                    Error::Algebra(AlgebraError::UnknownSymbolId {
                        id: s.0,
                        symbols: arena.symbols().len(),
                    })
                })?;
                let d = info.derivative.ok_or_else(|| {
                    Error::Algebra(AlgebraError::NoTimeDerivative {
                        name: info.name.clone(),
                    })
                })?;
                Ok(arena.symbol_node(d))
            })
            .collect::<Result<_>>()?;
        let da = self.khang_derivative(arena, diff, x)?;
        let ip = Matrix::identity(arena, self.cols);
        let xd = Matrix::column(rates);
        let kron = ip.kron(arena, &xd)?;
        let mut out = da.mul(arena, &kron)?;
        let times: Vec<SymbolId> = (0..arena.symbols().len() as u32)
            .map(SymbolId)
            .filter(|&s| arena.symbol_info(s).kind == SymbolKind::Time && !x.contains(&s))
            .collect();
        for t in times {
            for e in out.data.iter_mut().zip(&self.data) {
                let dt = diff.diff(arena, *e.1, t)?;
                *e.0 = arena.add2(*e.0, dt);
            }
        }
        Ok(out)
    }
}
