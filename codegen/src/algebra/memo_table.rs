//! The differentiator's memo: d(node)/d(symbol) by (node, symbol).
//!
//! One slot is 16 bytes, key and value side by side, in a single array probed linearly: a
//! look-up in a table larger than the cache misses once. A general-purpose map keeps its
//! control bytes apart from its slots and misses twice; the memo of a large derivation is
//! tens of millions of entries, looked up once per node visited.

use crate::algebra::expr::{Id, SymbolId};

/// (node, symbol) to derivative, open addressing with linear probing.
#[derive(Clone, Debug, Default)]
pub(crate) struct MemoTable {
    /// `[node + 1, symbol, derivative, 0]`; a slot whose first word is 0 is empty. The
    /// length is a power of two (or 0).
    slots: Vec<[u32; 4]>,
    /// Occupied slots.
    len: usize,
}

/// The smallest table allocated.
const MIN_SLOTS: usize = 64;

/// The table grows before it is more than `LOAD.0 / LOAD.1` full (about 8.5 slots, two or
/// three cache lines, inspected for an absent key at worst).
const LOAD: (usize, usize) = (3, 4);

impl MemoTable {
    /// The first slot to probe for (node, symbol) in a table of 2^`bits` slots.
    fn home(node: Id, sym: SymbolId, bits: u32) -> usize {
        let key = (u64::from(node.0) << 32) | u64::from(sym.0);
        (key.wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - bits)) as usize
    }

    /// The slot holding (node, symbol), or the empty slot where it would go.
    fn probe(&self, node: Id, sym: SymbolId) -> usize {
        let mask = self.slots.len() - 1;
        let mut k = Self::home(node, sym, self.slots.len().trailing_zeros());
        loop {
            let [n, s, _, _] = self.slots[k];
            if n == 0 || (n == node.0.wrapping_add(1) && s == sym.0) {
                return k;
            }
            k = (k + 1) & mask;
        }
    }

    /// The derivative of `node` by `sym`, if stored.
    pub(crate) fn get(&self, node: Id, sym: SymbolId) -> Option<Id> {
        if self.slots.is_empty() {
            return None;
        }
        match self.slots[self.probe(node, sym)] {
            [0, ..] => None,
            [_, _, d, _] => Some(Id(d)),
        }
    }

    /// Stores the derivative `d` of `node` by `sym` (`node` is never [`u32::MAX`]: no
    /// node has that id).
    pub(crate) fn insert(&mut self, node: Id, sym: SymbolId, d: Id) {
        if (self.len + 1) * LOAD.1 > self.slots.len() * LOAD.0 {
            self.grow();
        }
        let k = self.probe(node, sym);
        if self.slots[k][0] == 0 {
            self.len += 1;
        }
        self.slots[k] = [node.0.wrapping_add(1), sym.0, d.0, 0];
    }

    /// Forgets every entry.
    pub(crate) fn clear(&mut self) {
        *self = MemoTable::default();
    }

    /// Doubles the table (or allocates the first one) and places every entry again.
    fn grow(&mut self) {
        let size = (self.slots.len() * 2).max(MIN_SLOTS);
        let old = std::mem::replace(&mut self.slots, vec![[0; 4]; size]);
        for slot in old.into_iter().filter(|s| s[0] != 0) {
            let k = self.probe(Id(slot[0] - 1), SymbolId(slot[1]));
            self.slots[k] = slot;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Against a map, over keys that share nodes and symbols (so their home slots
    /// cluster) and enough of them to grow the table many times; storing a key again
    /// replaces its value.
    #[test]
    fn agrees_with_a_map() {
        let mut table = MemoTable::default();
        let mut truth: HashMap<(u32, u32), u32> = HashMap::new();
        assert_eq!(table.get(Id(0), SymbolId(0)), None);
        for k in 0..150_000u32 {
            let (node, sym) = (k % 9_000, k % 17);
            let d = k.wrapping_mul(2_654_435_761);
            table.insert(Id(node), SymbolId(sym), Id(d));
            truth.insert((node, sym), d);
        }
        assert_eq!(table.len, truth.len());
        for node in 0..9_100u32 {
            for sym in 0..18u32 {
                let want = truth.get(&(node, sym)).map(|&d| Id(d));
                assert_eq!(table.get(Id(node), SymbolId(sym)), want, "({node}, {sym})");
            }
        }
        table.clear();
        assert_eq!(table.get(Id(0), SymbolId(0)), None);
    }
}
