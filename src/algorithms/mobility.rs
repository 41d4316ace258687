//! Mobility of a mechanism at a configuration: how many degrees of freedom it really has,
//! and which constraint rows repeat others.
//!
//! With n coordinates and m constraint rows, Grübler's count (Kutzbach's criterion in the
//! coordinates declared) is n - m: it assumes every row independent. The true number of
//! degrees of freedom is n - rank(Phi_q). They differ for overconstrained mechanisms: a
//! planar four-bar declared with spatial revolute joints (18 coordinates, 20 rows, rank 17:
//! Grübler -2, mobility 1), Bricard's linkage (30, 30, rank 29: Grübler 0, mobility 1).
//! The rank and the redundant rows come from the independence test of
//! [`RowBasis`] (a row is redundant when its distance to the span of the rows before it is
//! below 1e-6 of its norm). The multipliers of the rows on which the null space of Phi_q^T
//! is nonzero are not unique: only their combination Phi_q^T lambda (the constraint forces
//! on the coordinates) is. With velocity rows A q' + a = 0 (the last rows of Phi_q), the
//! degrees of freedom in positions, n - rank of the position rows, exceed those in
//! velocities (the Whipple bicycle: 7 and 3).

use nalgebra::DMatrix;

use crate::algorithms::finite::check_jacobian;
use crate::error::Error;
use crate::linalg::RowBasis;
use crate::system::Kinematic;

/// The mobility of a mechanism at one configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct Mobility {
    /// Number of coordinates n.
    pub n: usize,
    /// Number of constraint rows m.
    pub m: usize,
    /// Rank of Phi_q at the configuration.
    pub rank: usize,
    /// Degrees of freedom n - rank (in velocities: the velocity rows count).
    pub degrees_of_freedom: usize,
    /// Degrees of freedom in positions, n - rank of the position rows (the velocity rows
    /// A q' + a = 0 restrict the rates only); equal to `degrees_of_freedom` without them.
    pub position_degrees_of_freedom: usize,
    /// Grübler's count n - m (every row taken as independent).
    pub grubler: i64,
    /// Rows that repeat rows before them (in row order), m - rank of them.
    pub redundant_rows: Vec<usize>,
    /// Rows whose multipliers are not unique (the support of the null space of Phi_q^T).
    pub indeterminate_rows: Vec<usize>,
}

impl Mobility {
    /// True when every constraint row is independent (the multipliers are unique).
    pub fn full_rank(&self) -> bool {
        self.rank == self.m
    }
}

/// The [`Mobility`] of `system` at (q, t).
pub fn mobility(system: &dyn Kinematic, t: f64, q: &[f64]) -> Result<Mobility, Error> {
    let info = system.info();
    let (n, m) = (info.n(), info.m());
    if q.len() != n {
        return Err(Error::WrongLength {
            what: "q",
            expected: n,
            got: q.len(),
        });
    }
    let mut phi_q = DMatrix::zeros(m, n);
    let mut phi_t = vec![0.0; m];
    system.constraint_jacobian(t, q, &mut phi_q, &mut phi_t);
    check_jacobian(&phi_q, info, t, q)?;
    let mut basis = RowBasis::new(m, n);
    let rank = basis.factor(&phi_q);
    let p = info.position_rows();
    let position_rank = if p == m {
        rank
    } else {
        RowBasis::new(p, n).factor(&phi_q.rows(0, p).into_owned())
    };
    Ok(Mobility {
        n,
        m,
        rank,
        degrees_of_freedom: n - rank,
        position_degrees_of_freedom: n - position_rank,
        grubler: n as i64 - m as i64,
        redundant_rows: (0..m).filter(|&r| basis.is_redundant(r)).collect(),
        indeterminate_rows: basis.indeterminate_rows(),
    })
}
