//! The copy of an arena cut down to what some roots reach (the graph Horner's rewrite and
//! the lowering work on).

use super::{Arena, Id, NO_ID, node_hash};
use crate::algebra::probe_table::ProbeTable;

impl Arena {
    /// A new arena holding the nodes reachable from `roots` and every symbol, in the same
    /// relative order (so sorted sums and products stay sorted), and the roots' ids there.
    /// The new arena is proportional to what `roots` reach; building it takes one pass of
    /// marks over this arena's nodes.
    pub(crate) fn reachable(&self, roots: &[Id]) -> (Arena, Vec<Id>) {
        let mut keep = vec![false; self.nodes.len()];
        let mut stack: Vec<Id> = roots.to_vec();
        while let Some(id) = stack.pop() {
            if !std::mem::replace(&mut keep[id.index()], true) {
                self.node(id).for_each_child(|c| stack.push(c));
            }
        }
        for &s in &self.symbol_nodes {
            keep[s.index()] = true;
        }
        let mut out = Arena {
            symbols: self.symbols.clone(),
            by_name: self.by_name.clone(),
            ..Arena::default()
        };
        // The kept nodes are distinct and their ids map one to one, so their copies are
        // distinct too: each is stored without a look-up, and the intern table is built
        // once at the end (in the order of its slots, not at random).
        let mut map = vec![NO_ID; self.nodes.len()];
        let mut hashes = Vec::new();
        for (k, node) in self.nodes.iter().enumerate() {
            if keep[k] {
                let copy = node.map_children(|c| map[c.index()]);
                map[k] = Id(out.nodes.len() as u32);
                hashes.push(node_hash(&copy));
                let mut children = 0;
                copy.for_each_child(|_| children += 1);
                out.size += 1 + children;
                out.nodes.push(copy);
            }
        }
        out.work = out.nodes.len() as u64;
        out.intern = ProbeTable::from_distinct(&hashes);
        out.symbol_nodes = self.symbol_nodes.iter().map(|s| map[s.index()]).collect();
        (out, roots.iter().map(|r| map[r.index()]).collect())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::algebra::expr::SymbolKind;

    /// The copy of what roots reach has an intern table built without look-ups: every
    /// node of the copy is found again by value (none is added), and the expression built
    /// again in the copy is the copied one (the products it builds on the way and does not
    /// keep are new there).
    #[test]
    fn the_reachable_copy_finds_every_node_by_value() {
        // sum_k k sin(q)^k q' for k = 1..199, in `a`.
        let series = |a: &mut Arena, q: Id, qd: Id| {
            let terms: Vec<Id> = (1..200)
                .map(|k| {
                    let c = a.int(k);
                    let s = a.sin(q);
                    let p = a.pow(s, c).unwrap();
                    a.mul(&[c, p, qd])
                })
                .collect();
            a.add(&terms)
        };
        let mut a = Arena::new();
        let [q, qd, _] = a.coordinate("q");
        let e = series(&mut a, q, qd);
        let (mut b, roots) = a.reachable(&[e]);
        let len = b.len();
        for k in 0..len {
            let node = b.node(Id(k as u32)).clone();
            assert_eq!(b.intern(node), Id(k as u32));
        }
        assert_eq!(b.len(), len);
        let [q, qd] = [q, qd].map(|s| {
            b.symbol(
                &a.symbol_info(a.as_symbol(s).unwrap()).name,
                SymbolKind::Free,
            )
        });
        assert_eq!(series(&mut b, q, qd), roots[0]);
    }
}
