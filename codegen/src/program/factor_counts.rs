//! How many monomials of a sum contain each factor, kept up to date as the Horner scheme
//! (`factor.rs`) takes monomials out, with the most frequent factor found in O(log) time.
//!
//! The scheme takes out a factor, then chooses again among the monomials left. Counting
//! afresh for every choice hashes every factor of every monomial left, each time; a sum
//! whose factors are each shared by two monomials (a row of C q' in a chain: the rates
//! q_j' pair the terms) is taken apart two monomials at a time, so that counting is
//! O(k^2 d) for k monomials of d factors. Here the counts are made once per sum and
//! decremented as monomials leave, and the largest is read from a heap whose stale entries
//! (a count that has since dropped) are discarded when they surface: the choices cost
//! O(F log F) for F factor occurrences, and they are the choices of counting afresh. (The
//! scheme still splits the monomials left into those with and without the factor at each
//! choice, one comparison per monomial; the expansion limit of `factor.rs` bounds
//! k.)

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use crate::algebra::expr::{FxHashMap, Id};

/// Which count a factor of a monomial enters: the varying factors are preferred; a
/// parameter-only factor counts only in monomials that also vary (see `factor.rs`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Tier {
    /// A factor that depends on a coordinate, rate or time.
    Varying,
    /// A parameter-only factor of a monomial that also has a varying one.
    Invariant,
}

/// The counts of one sum's factors, by tier.
#[derive(Debug, Default)]
pub(crate) struct FactorCounts {
    counts: [FxHashMap<Id, usize>; 2],
    /// (count, Reverse(factor)) per tier: the top is the most frequent factor, the
    /// smallest id among equals; entries whose count has dropped since are stale.
    heaps: [BinaryHeap<(usize, Reverse<Id>)>; 2],
}

fn tier_index(t: Tier) -> usize {
    match t {
        Tier::Varying => 0,
        Tier::Invariant => 1,
    }
}

impl FactorCounts {
    /// The counts over `monomials`, each given by its distinct counted factors.
    pub(crate) fn new<'a>(monomials: impl IntoIterator<Item = &'a [(Id, Tier)]>) -> Self {
        let mut out = Self::default();
        for m in monomials {
            for &(f, t) in m {
                *out.counts[tier_index(t)].entry(f).or_default() += 1;
            }
        }
        for t in 0..2 {
            let heap = out.counts[t]
                .iter()
                .filter(|&(_, &n)| n >= 2)
                .map(|(&f, &n)| (n, Reverse(f)))
                .collect();
            out.heaps[t] = heap;
        }
        out
    }

    /// Takes one monomial (its distinct counted factors) out of the counts.
    pub(crate) fn remove(&mut self, monomial: &[(Id, Tier)]) {
        for &(f, t) in monomial {
            let t = tier_index(t);
            if let Some(n) = self.counts[t].get_mut(&f) {
                *n -= 1;
                if *n >= 2 {
                    self.heaps[t].push((*n, Reverse(f)));
                }
            }
        }
    }

    /// The factor contained in the most monomials left, if two or more contain it: a
    /// varying one if any qualifies, else a parameter-only one; among equal counts the
    /// smallest id.
    pub(crate) fn best(&mut self) -> Option<Id> {
        for t in 0..2 {
            while let Some(&(n, Reverse(f))) = self.heaps[t].peek() {
                if self.counts[t].get(&f) == Some(&n) {
                    return Some(f);
                }
                self.heaps[t].pop();
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The factor counting afresh picks: the largest count >= 2, varying first, ties to
    /// the smallest id.
    fn fresh(monomials: &[Vec<(Id, Tier)>]) -> Option<Id> {
        let pick = |tier: Tier| {
            let mut count: FxHashMap<Id, usize> = FxHashMap::default();
            for m in monomials {
                for &(f, t) in m {
                    if t == tier {
                        *count.entry(f).or_default() += 1;
                    }
                }
            }
            count
                .into_iter()
                .filter(|&(_, n)| n >= 2)
                .max_by_key(|&(f, n)| (n, Reverse(f)))
                .map(|(f, _)| f)
        };
        pick(Tier::Varying).or_else(|| pick(Tier::Invariant))
    }

    /// Taking monomials out as the Horner scheme does (those that contain the chosen
    /// factor), the kept counts choose what counting afresh chooses, at every step, over
    /// pseudo-random sums of both tiers.
    #[test]
    fn kept_counts_choose_what_fresh_counts_choose() {
        let mut seed = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = |m: u64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed % m
        };
        for _ in 0..200 {
            let k = 1 + next(40) as usize;
            let mut monomials: Vec<Vec<(Id, Tier)>> = (0..k)
                .map(|_| {
                    let mut m: Vec<(Id, Tier)> = Vec::new();
                    for _ in 0..1 + next(4) {
                        let f = Id::new(next(12) as u32);
                        let t = if f.0 < 4 {
                            Tier::Invariant
                        } else {
                            Tier::Varying
                        };
                        if !m.iter().any(|e| e.0 == f) {
                            m.push((f, t));
                        }
                    }
                    m
                })
                .collect();
            let mut kept = FactorCounts::new(monomials.iter().map(Vec::as_slice));
            loop {
                let want = fresh(&monomials);
                assert_eq!(kept.best(), want);
                let Some(f) = want else { break };
                let (with, without): (Vec<_>, Vec<_>) = monomials
                    .into_iter()
                    .partition(|m| m.iter().any(|e| e.0 == f));
                for m in &with {
                    kept.remove(m);
                }
                monomials = without;
            }
        }
    }
}
