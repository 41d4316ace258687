//! The children of a wide sum or product that depend on a symbol, found through an index.
//!
//! Differentiating a sum of k terms by a symbol looks at every term's dependency set: k
//! look-ups per derivative. A wide sum differentiated by many symbols pays that every time:
//! in a closed chain of n bars the bar velocities are sums of up to n terms, differentiated
//! by each of the n rates, n^3 / 6 look-ups in all. The second time a node of at least
//! [`WIDE`] children is asked about, its children are indexed by symbol (one entry per
//! (child, symbol of the child's set)), and later questions cost a look-up of the index.

use crate::algebra::dependencies::DependencySets;
use crate::algebra::expr::{FxHashMap, Id, SymbolId};

/// Nodes with at least this many children are indexed.
const WIDE: usize = 32;

/// The most index entries kept in all (4 bytes each, and a run per distinct symbol): past
/// it, wide nodes are filtered term by term as narrow ones are, so the index never
/// outweighs the derivation.
const MAX_ENTRIES: usize = 1 << 24;

/// One wide node's children by symbol: the positions of the children depending on each
/// symbol, in increasing order, one run per symbol in `positions`. A hash look-up per
/// question: bisecting one sorted array of (symbol, position) pairs missed the cache at
/// every step once the index of a long sum outgrew it (1.3 million pairs for the 800-bar
/// chain's kinetic energy).
#[derive(Clone, Debug, Default)]
struct Indexed {
    runs: FxHashMap<SymbolId, (u32, u32)>,
    positions: Box<[u32]>,
}

/// The index of the wide nodes asked about twice or more.
#[derive(Clone, Debug, Default)]
pub(crate) struct WideChildren {
    /// Per indexed node, its children by symbol.
    index: FxHashMap<Id, Indexed>,
    /// How often each wide node not indexed yet was asked about.
    asked: FxHashMap<Id, u32>,
    /// Entries of all indexes.
    entries: usize,
}

impl WideChildren {
    /// Forgets every index (the differentiator's arena changed).
    pub(crate) fn clear(&mut self) {
        *self = Self::default();
    }

    /// The positions of the children of `node` (whose children are `children`, all covered
    /// by `deps`) that depend on `sym`, in increasing order, into `out`.
    pub(crate) fn positions(
        &mut self,
        deps: &DependencySets,
        node: Id,
        children: &[Id],
        sym: SymbolId,
        out: &mut Vec<u32>,
    ) {
        out.clear();
        if children.len() >= WIDE && self.indexed(deps, node, children) {
            let indexed = &self.index[&node];
            if let Some(&(from, to)) = indexed.runs.get(&sym) {
                out.extend_from_slice(&indexed.positions[from as usize..to as usize]);
            }
            return;
        }
        out.extend(
            children
                .iter()
                .enumerate()
                .filter(|(_, c)| deps.contains(**c, sym))
                .map(|(k, _)| k as u32),
        );
    }

    /// Whether `node` has an index, building it on the second question within the cap.
    fn indexed(&mut self, deps: &DependencySets, node: Id, children: &[Id]) -> bool {
        if self.index.contains_key(&node) {
            return true;
        }
        let asked = self.asked.entry(node).or_insert(0);
        *asked += 1;
        if *asked < 2 {
            return false;
        }
        let size: usize = children.iter().map(|&c| deps.set(c).len()).sum();
        if self.entries + size > MAX_ENTRIES {
            return false;
        }
        let mut entries = Vec::with_capacity(size);
        for (k, &c) in children.iter().enumerate() {
            entries.extend(deps.set(c).iter().map(|&s| (s, k as u32)));
        }
        entries.sort_unstable();
        self.entries += entries.len();
        self.asked.remove(&node);
        let mut runs: FxHashMap<SymbolId, (u32, u32)> = FxHashMap::default();
        let mut from = 0;
        for k in 1..=entries.len() {
            if k == entries.len() || entries[k].0 != entries[from].0 {
                runs.insert(entries[from].0, (from as u32, k as u32));
                from = k;
            }
        }
        let positions = entries.iter().map(|e| e.1).collect();
        self.index.insert(node, Indexed { runs, positions });
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::expr::{Arena, SymbolKind};

    /// The indexed positions are the filtered ones, for every symbol, before and after the
    /// index is built, on a sum of nested and disjoint terms.
    #[test]
    fn indexed_positions_are_the_filtered_ones() {
        let mut a = Arena::new();
        let xs: Vec<Id> = (0..40)
            .map(|k| a.symbol(&format!("x{k}"), SymbolKind::Free))
            .collect();
        let mut terms = Vec::new();
        for k in 0..40 {
            let s = a.sin(xs[k]);
            let c = a.cos(xs[(k * 7) % 40]);
            terms.push(a.mul(&[s, c]));
        }
        let wide = a.add(&terms);
        let children: Vec<Id> = a.children(wide);
        assert!(children.len() >= WIDE);
        let mut deps = DependencySets::default();
        deps.sync(&a);
        let mut index = WideChildren::default();
        let mut got = Vec::new();
        for round in 0..3 {
            for &x in &xs {
                let sym = a.as_symbol(x).unwrap();
                index.positions(&deps, wide, &children, sym, &mut got);
                let want: Vec<u32> = (0..children.len() as u32)
                    .filter(|&k| deps.contains(children[k as usize], sym))
                    .collect();
                assert_eq!(got, want, "round {round}");
                assert!(!got.is_empty());
            }
        }
        assert!(index.index.contains_key(&wide));
    }
}
