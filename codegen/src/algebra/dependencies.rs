//! Per-node sets of the symbols each node depends on, kept sparse.
//!
//! A node's set is the union of its children's (ids are topological, so the sets are built
//! in id order as the arena grows). Each set is a sorted run of symbol ids in one shared
//! pool; a node whose union equals one child's set (sin u, c u, u^2, a sum of terms in the
//! same symbols) shares that child's run instead of copying it. The memory is the total
//! size of the distinct sets, not nodes x symbols: a mechanism of 5,000 coordinates has
//! 15,000 symbols, and a dense bitset per node would cost 1.9 kB for each of its nodes.

use crate::algebra::expr::{Arena, FxHashSet, Id, Node, SymbolId};
use crate::algebra::visit_marks::VisitMarks;

/// The sets, extended incrementally as the arena grows.
#[derive(Clone, Debug, Default)]
pub(crate) struct DependencySets {
    /// For each covered node, its run in `pool`: (start, length).
    runs: Vec<(u32, u32)>,
    /// Sorted, duplicate-free runs of symbol ids.
    pool: Vec<SymbolId>,
    /// Scratch for unions.
    scratch: Vec<SymbolId>,
    /// The symbols the current union has added to the scratch.
    added: VisitMarks,
    /// Pairs of runs (a, b) with a found inside b, for runs longer than [`SMALL_RUN`].
    inside: FxHashSet<((u32, u32), (u32, u32))>,
}

/// Runs up to this length are looked up symbol by symbol every time; longer ones are
/// remembered once found inside another.
const SMALL_RUN: u32 = 8;

impl DependencySets {
    /// Number of nodes covered.
    pub(crate) fn covered(&self) -> usize {
        self.runs.len()
    }

    /// Brings the sets up to date with `arena` (its new nodes).
    #[cfg(test)]
    pub(crate) fn sync(&mut self, arena: &Arena) {
        self.sync_to(arena, arena.len());
    }

    /// Brings the sets up to date with the first `end` nodes of `arena` (the nodes up to
    /// one a query reads: its children have smaller ids). A query about an early node of a
    /// large arena then costs the sets of the nodes before it only.
    pub(crate) fn sync_to(&mut self, arena: &Arena, end: usize) {
        for n in self.runs.len()..end.min(arena.len()) {
            let run = match arena.node(Id(n as u32)) {
                Node::Num(_) | Node::Pi => (0, 0),
                Node::Sym(s) => {
                    let start = self.pool.len() as u32;
                    self.pool.push(*s);
                    (start, 1)
                }
                Node::Func(_, a) | Node::Named(a) => self.runs[a.index()],
                Node::Pow(a, b) | Node::Atan2(a, b) => self.union(&[*a, *b]),
                Node::Add(v) | Node::Mul(v) => self.union(v),
            };
            self.runs.push(run);
        }
    }

    /// The run of the union of `children`'s sets: the widest child's own run when the union
    /// is it. The other runs are looked up in the widest by bisection, so the cost is their
    /// total size (times a logarithm), not the widest run's; a run found inside another once
    /// is remembered, so a sum over a chain's bars, whose sets nest, costs one look-up per
    /// term after the first. The symbols the widest lacks are marked as they are found, so
    /// each is sorted and merged once however many children hold it. Two short runs, the
    /// usual case, are merged directly instead ([`DependencySets::merge_two`]).
    fn union(&mut self, children: &[Id]) -> (u32, u32) {
        let mut widest = (0u32, 0u32);
        let mut distinct = 0;
        // The first two distinct non-empty runs, for the common case of two.
        let mut two = [(0u32, 0u32); 2];
        for c in children {
            let run = self.runs[c.index()];
            if run.1 == 0 || run == widest {
                continue;
            }
            if distinct < 2 {
                two[distinct] = run;
            }
            distinct += 1;
            if run.1 > widest.1 {
                widest = run;
            }
        }
        if distinct <= 1 {
            return widest;
        }
        let range = |(start, len): (u32, u32)| start as usize..(start + len) as usize;
        if distinct == 2 && two[0] != two[1] && two.iter().all(|r| r.1 <= SMALL_RUN) {
            return self.merge_two(range(two[0]), range(two[1]));
        }
        self.added.start();
        self.scratch.clear();
        for c in children {
            let r = self.runs[c.index()];
            if r == widest || r.1 == 0 {
                continue;
            }
            let remembered = r.1 > SMALL_RUN;
            if remembered && self.inside.contains(&(r, widest)) {
                continue;
            }
            let mut inside = true;
            let within = &self.pool[range(widest)];
            for &s in &self.pool[range(r)] {
                if within.binary_search(&s).is_err() {
                    inside = false;
                    // Each missing symbol enters the scratch once, however many children
                    // hold it.
                    if self.added.first_visit(s.index()) {
                        self.scratch.push(s);
                    }
                }
            }
            if remembered && inside {
                self.inside.insert((r, widest));
            }
        }
        if self.scratch.is_empty() {
            return widest;
        }
        self.scratch.sort_unstable();
        // Merge the widest run and the added symbols, both sorted, at the pool's end.
        let start = self.pool.len();
        let (mut a, mut b) = (range(widest), 0);
        while a.start < a.end || b < self.scratch.len() {
            let take_pool = b == self.scratch.len()
                || (a.start < a.end && self.pool[a.start] < self.scratch[b]);
            if take_pool {
                let s = self.pool[a.start];
                self.pool.push(s);
                a.start += 1;
            } else {
                self.pool.push(self.scratch[b]);
                b += 1;
            }
        }
        (start as u32, (self.pool.len() - start) as u32)
    }

    /// The union of two short runs (both non-empty and different) by one merge of the two:
    /// the run that holds the other when one does, else a new run at the pool's end. For
    /// the two-operand nodes that most of an arena is, this is cheaper than looking each
    /// symbol up in the wider run and sorting what it lacks.
    fn merge_two(&mut self, a: std::ops::Range<usize>, b: std::ops::Range<usize>) -> (u32, u32) {
        let start = self.pool.len();
        let (mut i, mut j) = (a.start, b.start);
        let (mut a_only, mut b_only) = (false, false);
        while i < a.end || j < b.end {
            let s = if j == b.end || (i < a.end && self.pool[i] < self.pool[j]) {
                a_only = true;
                i += 1;
                self.pool[i - 1]
            } else if i == a.end || self.pool[j] < self.pool[i] {
                b_only = true;
                j += 1;
                self.pool[j - 1]
            } else {
                i += 1;
                j += 1;
                self.pool[i - 1]
            };
            self.pool.push(s);
        }
        let whole = |r: std::ops::Range<usize>| (r.start as u32, (r.end - r.start) as u32);
        match (a_only, b_only) {
            (_, false) => {
                self.pool.truncate(start);
                whole(a)
            }
            (false, true) => {
                self.pool.truncate(start);
                whole(b)
            }
            (true, true) => (start as u32, (self.pool.len() - start) as u32),
        }
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
        // Nested sets (a chain's bar velocities, each the previous one plus a bar) and
        // sums over them, whose union is the widest; products that add one symbol at the
        // front, the back and the middle of a run.
        let mut prefix = Vec::new();
        let mut bars = Vec::new();
        for &x in &xs {
            prefix.push(a.sin(x));
            bars.push(a.add(&prefix));
        }
        a.add(&bars);
        a.mul(&[bars[2], xs[5]]);
        a.mul(&[bars[1], bars[4], xs[0]]);
        let sparse = a.add(&[xs[0], xs[4]]);
        a.mul(&[sparse, xs[2], bars[0]]);
        // Runs longer than SMALL_RUN: nested (remembered as inside the widest, then reused
        // by a second sum over the same bars) and overlapping ones that add symbols.
        let ys: Vec<Id> = (0..24)
            .map(|k| a.symbol(&format!("y{k}"), SymbolKind::Free))
            .collect();
        let mut long = Vec::new();
        let mut acc = Vec::new();
        for &y in &ys {
            acc.push(a.cos(y));
            long.push(a.add(&acc));
        }
        a.add(&long[10..]);
        let twice = a.add(&long[12..]);
        a.mul(&[twice, xs[1]]);
        let low = a.add(&ys[..16]);
        let high = a.add(&ys[8..]);
        a.mul(&[low, high, long[3]]);
        // Two children that share symbols the widest lacks (ys[8..16]): each enters the
        // union once.
        let zs: Vec<Id> = (0..30)
            .map(|k| a.symbol(&format!("z{k}"), SymbolKind::Free))
            .collect();
        let wide = a.add(&zs);
        a.mul(&[wide, low, high]);
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
