//! dM/dq where it is nonzero: for each entry M_ij, the coordinates q_k it depends on and
//! the derivative dM_ij/dq_k by each.
//!
//! Khang's C and the lean C q' both read these. They are formed once, in entry order, and
//! kept side by side in flat arrays, so each later read is the next element rather than a
//! look-up in the differentiator's memo (a random access into a table of tens of millions
//! of entries on a large mechanism).

use crate::algebra::diff::Differentiator;
use crate::algebra::expr::{Arena, Id, SymbolId};
use crate::algebra::matrix::Matrix;
use crate::error::{BudgetError, Error, Result};

/// The nonzero slopes dM_ij/dq_k of an n x n mass matrix.
pub(crate) struct MassSlopes {
    /// n.
    n: usize,
    /// Entry (i, j), row-major, holds `coordinates[starts[i n + j]..starts[i n + j + 1]]`.
    starts: Vec<u32>,
    /// The k of each slope, within an entry in the order of the coordinates' symbol ids
    /// (as the differentiator lists an expression's symbols).
    coordinates: Vec<u32>,
    /// dM_ij/dq_k, beside its k in `coordinates`.
    slopes: Vec<Id>,
}

impl MassSlopes {
    /// The slopes of `mass` by the coordinates `q`, differentiated entry by entry in
    /// row-major order.
    ///
    /// # Errors
    /// [`BudgetError::Entries`] when there are more slopes than the arena's
    /// [`crate::Budget::entries`] or 2^32 - 1 (counted before any is formed); what
    /// [`Differentiator::diff`] reports.
    pub(crate) fn new(
        arena: &mut Arena,
        d: &mut Differentiator,
        mass: &Matrix,
        q: &[SymbolId],
    ) -> Result<MassSlopes> {
        let n = q.len();
        let mut coordinate_of: Vec<Option<u32>> = vec![None; arena.symbols().len()];
        for (k, s) in q.iter().enumerate() {
            coordinate_of[s.index()] = Some(k as u32);
        }
        // The coordinates of each upper entry (row-major), mirrored below the diagonal.
        // They are counted over all n^2 entries as they are listed, and kept only while
        // the count is within the budget, so a dense dM/dq (n^3 entries) is reported with
        // its size instead of being listed; within the budget every offset fits in 32 bits.
        let limit = arena.budget().entries.min(u32::MAX as usize);
        let mut total = 0usize;
        let mut upper_starts: Vec<u32> = Vec::with_capacity(n * (n + 1) / 2 + 1);
        let mut upper = Vec::new();
        upper_starts.push(0);
        for i in 0..n {
            for j in i..n {
                let symbols = d.symbols_of(arena, mass.get(i, j))?;
                let ks = symbols
                    .iter()
                    .filter_map(|x| coordinate_of.get(x.index()).copied().flatten());
                let count = if total <= limit {
                    let before = upper.len();
                    upper.extend(ks);
                    upper.len() - before
                } else {
                    ks.count()
                };
                total += if i == j { count } else { 2 * count };
                upper_starts.push(upper.len() as u32);
            }
        }
        check_kronecker_size(n, total, limit)?;
        let mut starts = Vec::with_capacity(n * n + 1);
        let mut coordinates = Vec::with_capacity(total);
        starts.push(0);
        for i in 0..n {
            for j in 0..n {
                let (a, b) = (i.min(j), i.max(j));
                let entry = a * n - a * (a + 1) / 2 + b;
                let run = upper_starts[entry] as usize..upper_starts[entry + 1] as usize;
                coordinates.extend_from_slice(&upper[run]);
                starts.push(coordinates.len() as u32);
            }
        }
        let mut slopes = Vec::with_capacity(coordinates.len());
        for i in 0..n {
            for j in 0..n {
                let e = mass.get(i, j);
                let run = starts[i * n + j] as usize..starts[i * n + j + 1] as usize;
                for &k in &coordinates[run] {
                    slopes.push(d.diff(arena, e, q[k as usize])?);
                }
            }
        }
        Ok(MassSlopes {
            n,
            starts,
            coordinates,
            slopes,
        })
    }

    /// Whether M is free of every coordinate.
    pub(crate) fn is_empty(&self) -> bool {
        self.slopes.is_empty()
    }

    /// (k, dM_ij/dq_k) for each coordinate q_k that M_ij depends on.
    pub(crate) fn of(&self, i: usize, j: usize) -> impl Iterator<Item = (usize, Id)> + '_ {
        let run = self.starts[i * self.n + j] as usize..self.starts[i * self.n + j + 1] as usize;
        self.coordinates[run.clone()]
            .iter()
            .map(|&k| k as usize)
            .zip(self.slopes[run].iter().copied())
    }
}

/// [`crate::error::BudgetError::Entries`] when dM/dq of n coordinates has more nonzero entries
/// (`entries`, counted before any is formed) than `limit`: the arena's
/// [`crate::Budget::entries`], and never more than 2^32 - 1. dM/dq is formed sparsely, only
/// where M_ij depends on q_k: a closed chain in absolute angles has 2 n^2 such entries of
/// its n^3.
fn check_kronecker_size(n: usize, entries: usize, limit: usize) -> Result<()> {
    if entries > limit {
        return Err(Error::Budget(BudgetError::Entries {
            coordinates: n,
            entries,
            limit,
            links: None,
        }));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every listed slope is the derivative, and every slope not listed is zero: a
    /// 3 x 3 mass matrix whose entries depend on no coordinate, one, or two.
    #[test]
    fn lists_exactly_the_nonzero_slopes() {
        let mut a = Arena::new();
        let [q1, ..] = a.coordinate("q1");
        let [q2, ..] = a.coordinate("q2");
        let [q3, ..] = a.coordinate("q3");
        let m = a.symbol("m", crate::SymbolKind::Parameter);
        let q = ["q1", "q2", "q3"].map(|n| a.lookup(n).unwrap());
        let d12 = a.sub(q1, q2);
        let c12 = a.cos(d12);
        let s3 = a.sin(q3);
        let m3 = a.mul2(m, s3);
        let zero = a.int(0);
        #[rustfmt::skip]
        let data = vec![
            m,   c12,  zero,
            c12, m3,   s3,
            zero, s3,  m,
        ];
        let mass = Matrix::new(3, 3, data).unwrap();
        let mut d = Differentiator::new();
        let slopes = MassSlopes::new(&mut a, &mut d, &mass, &q).unwrap();
        let mut listed = 0;
        for i in 0..3 {
            for j in 0..3 {
                let of: Vec<(usize, Id)> = slopes.of(i, j).collect();
                listed += of.len();
                for (k, &qk) in q.iter().enumerate() {
                    let derivative = d.diff(&mut a, mass.get(i, j), qk).unwrap();
                    match of.iter().find(|(kk, _)| *kk == k) {
                        Some(&(_, e)) => assert_eq!(e, derivative, "dM{i}{j}/dq{k}"),
                        None => assert!(a.is_zero(derivative), "dM{i}{j}/dq{k} is not listed"),
                    }
                }
            }
        }
        // cos(q1 - q2) twice by two coordinates, m sin(q3) once, sin(q3) twice.
        assert_eq!(listed, 7);
    }

    /// More slopes than the budget's entries: the budget error, before any is formed.
    #[test]
    fn past_the_entry_budget_is_an_error() {
        let mut a = Arena::new();
        let [q1, ..] = a.coordinate("q1");
        let q = [a.lookup("q1").unwrap()];
        let s1 = a.sin(q1);
        let mass = Matrix::new(1, 1, vec![s1]).unwrap();
        let before = a.len();
        let err = slopes_within(&mut a, &mass, &q, 0);
        assert!(matches!(
            err,
            Some(Error::Budget(BudgetError::Entries {
                entries: 1,
                limit: 0,
                ..
            }))
        ));
        assert_eq!(a.len(), before, "no slope was formed");
    }

    /// Past the budget, the slopes are still counted to the end (the error names the size
    /// of dM/dq, not where the count stopped): every entry of a 2 x 2 M in both
    /// coordinates, 8 slopes, against a budget of 3.
    #[test]
    fn the_error_names_every_slope() {
        let mut a = Arena::new();
        let [q1, ..] = a.coordinate("q1");
        let [q2, ..] = a.coordinate("q2");
        let q = ["q1", "q2"].map(|n| a.lookup(n).unwrap());
        let sum = a.add2(q1, q2);
        let c = a.cos(sum);
        let mass = Matrix::new(2, 2, vec![c; 4]).unwrap();
        let err = slopes_within(&mut a, &mass, &q, 3);
        assert!(matches!(
            err,
            Some(Error::Budget(BudgetError::Entries {
                entries: 8,
                limit: 3,
                ..
            }))
        ));
    }

    /// The error of forming the slopes of `mass` with the entry budget set to `limit`.
    fn slopes_within(a: &mut Arena, mass: &Matrix, q: &[SymbolId], limit: usize) -> Option<Error> {
        let mut budget = *a.budget();
        budget.entries = limit;
        a.set_budget(budget);
        MassSlopes::new(a, &mut Differentiator::new(), mass, q).err()
    }
}
