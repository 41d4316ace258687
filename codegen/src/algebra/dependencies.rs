//! Per-node sets of the symbols each node depends on, kept sparse.
//!
//! A node's set is the union of its children's (ids are topological, so the sets are built
//! in id order as the arena grows). Each set is a sorted run of symbol ids in one shared
//! pool; a node whose union equals one child's set (sin u, c u, u^2, a sum of terms in the
//! same symbols) shares that child's run instead of copying it. The memory is the total
//! size of the distinct sets, not nodes x symbols: a mechanism of 5,000 coordinates has
//! 15,000 symbols, and a dense bitset per node would cost 1.9 kB for each of its nodes.

use crate::algebra::expr::{Arena, Id, Node, SymbolId};

/// The sets, extended incrementally as the arena grows.
#[derive(Clone, Debug, Default)]
pub(crate) struct DependencySets {
    /// For each covered node, its run in `pool`: (start, length).
    runs: Vec<(u32, u32)>,
    /// Sorted, duplicate-free runs of symbol ids.
    pool: Vec<SymbolId>,
    /// Scratch for unions.
    scratch: Vec<SymbolId>,
}

impl DependencySets {
    /// Number of nodes covered.
    pub(crate) fn covered(&self) -> usize {
        self.runs.len()
    }

    /// Brings the sets up to date with `arena` (its new nodes).
    pub(crate) fn sync(&mut self, arena: &Arena) {
        for n in self.runs.len()..arena.len() {
            let run = match arena.node(Id(n as u32)) {
                Node::Num(_) | Node::Pi => (0, 0),
                Node::Sym(s) => {
                    let start = self.pool.len() as u32;
                    self.pool.push(*s);
                    (start, 1)
                }
                Node::Func(_, a) => self.runs[a.index()],
                Node::Pow(a, b) | Node::Atan2(a, b) => self.union(&[*a, *b]),
                Node::Add(v) | Node::Mul(v) => self.union(v),
            };
            self.runs.push(run);
        }
    }

    /// The run of the union of `children`'s sets: a child's own run when the union is it.
    fn union(&mut self, children: &[Id]) -> (u32, u32) {
        let mut widest = (0u32, 0u32);
        let mut distinct = 0;
        for c in children {
            let run = self.runs[c.index()];
            if run.1 == 0 || run == widest {
                continue;
            }
            distinct += 1;
            if run.1 > widest.1 {
                widest = run;
            }
        }
        if distinct <= 1 {
            return widest;
        }
        self.scratch.clear();
        for c in children {
            let (start, len) = self.runs[c.index()];
            self.scratch
                .extend_from_slice(&self.pool[start as usize..(start + len) as usize]);
        }
        self.scratch.sort_unstable();
        self.scratch.dedup();
        if self.scratch.len() == widest.1 as usize {
            return widest;
        }
        let start = self.pool.len() as u32;
        self.pool.extend_from_slice(&self.scratch);
        (start, self.scratch.len() as u32)
    }

    /// The symbols of node `id` (covered), in increasing order.
    pub(crate) fn set(&self, id: Id) -> &[SymbolId] {
        let (start, len) = self.runs[id.index()];
        &self.pool[start as usize..(start + len) as usize]
    }

    /// Whether node `id` depends on symbol `s`; true for a node not covered (conservative).
    pub(crate) fn contains(&self, id: Id, s: SymbolId) -> bool {
        if id.index() >= self.runs.len() {
            return true;
        }
        self.set(id).binary_search(&s).is_ok()
    }

    /// The symbols node `id` depends on, in increasing order (none for a node not covered).
    pub(crate) fn symbols(&self, id: Id) -> Vec<SymbolId> {
        if id.index() >= self.runs.len() {
            return Vec::new();
        }
        self.set(id).to_vec()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::expr::SymbolKind;

    /// The sets against a direct walk of each node's subtree, on an expression with shared
    /// subtrees, unions of distinct sets and runs reused from one child.
    #[test]
    fn sets_are_the_symbols_below_each_node() {
        let mut a = Arena::new();
        let xs: Vec<Id> = (0..6)
            .map(|k| a.symbol(&format!("x{k}"), SymbolKind::Free))
            .collect();
        let s0 = a.sin(xs[0]);
        let p = a.mul(&[s0, xs[1]]);
        let q = a.add(&[p, xs[2], s0]);
        let two = a.int(2);
        let r = a.pow(q, two).unwrap();
        let t = a.atan2(r, xs[5]);
        let u = a.add(&[t, xs[3]]);
        let mut sets = DependencySets::default();
        sets.sync(&a);
        for n in 0..a.len() {
            let id = Id(n as u32);
            let mut want = Vec::new();
            let mut stack = vec![id];
            while let Some(m) = stack.pop() {
                if let Node::Sym(s) = a.node(m) {
                    want.push(*s);
                }
                stack.extend(a.children(m));
            }
            want.sort_unstable();
            want.dedup();
            assert_eq!(sets.symbols(id), want, "node {n}: {:?}", a.node(id));
        }
        let x4 = a.lookup("x4").unwrap();
        assert!(!sets.contains(u, x4));
        assert!(sets.contains(u, a.lookup("x5").unwrap()));
    }
}
