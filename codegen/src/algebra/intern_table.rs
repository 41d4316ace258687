//! The arena's intern table: for each 32-bit node hash, the first node that has it.
//!
//! One slot is one `u64`, the hash and the id side by side, in a single array probed
//! linearly. A general-purpose map keeps its control bytes apart from its slots, so every
//! look-up in a table larger than the cache misses twice (control byte, then key); here the
//! hash is compared in the slot itself and a look-up misses once. On a large derivation
//! the table is hundreds of megabytes, and interning is a fifth of the derivation's time.
//!
//! The table never holds two slots of one hash: a second node with a hash already present
//! is the arena's business (its table of collisions, by value).

/// Hash to first id, open addressing with linear probing.
#[derive(Clone, Debug, Default)]
pub(crate) struct InternTable {
    /// `hash << 32 | (id + 1)`; 0 is an empty slot. The length is a power of two (or 0).
    slots: Vec<u64>,
    /// Occupied slots.
    len: usize,
}

/// The smallest table allocated.
const MIN_SLOTS: usize = 64;

/// The table grows before it is more than `LOAD.0 / LOAD.1` full: linear probing then
/// inspects about 8.5 slots (one or two cache lines) for a hash that is absent, at worst.
const LOAD: (usize, usize) = (3, 4);

/// A node's id as the table holds it: the arena's index, below `u32::MAX` (no node has
/// that id). The table knows nothing else of nodes, so the arena is its only importer.
pub(crate) type NodeIndex = u32;

fn pack(hash: u32, id: NodeIndex) -> u64 {
    (u64::from(hash) << 32) | (u64::from(id) + 1)
}

impl InternTable {
    /// The first slot to probe for `hash`: its Fibonacci mix, so that hashes that differ
    /// only in their high bits start apart (`bits` is log2 of the table's length).
    fn home(hash: u32, bits: u32) -> usize {
        (u64::from(hash).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - bits)) as usize
    }

    /// The slot holding `hash`, or the empty slot where it would go (the table has one:
    /// it is never full).
    fn probe(&self, hash: u32) -> usize {
        let mask = self.slots.len() - 1;
        let mut k = Self::home(hash, self.slots.len().trailing_zeros());
        while self.slots[k] != 0 && (self.slots[k] >> 32) as u32 != hash {
            k = (k + 1) & mask;
        }
        k
    }

    /// The id stored under `hash`; when there is none, `id` is stored under it and `None`
    /// returned (one probe sequence for both).
    pub(crate) fn find_or_claim(&mut self, hash: u32, id: NodeIndex) -> Option<NodeIndex> {
        if (self.len + 1) * LOAD.1 > self.slots.len() * LOAD.0 {
            self.grow();
        }
        let k = self.probe(hash);
        match self.slots[k] {
            0 => {
                self.slots[k] = pack(hash, id);
                self.len += 1;
                None
            }
            slot => Some((slot as u32) - 1),
        }
    }

    /// Stores `id` under `hash`, replacing what was there (tests plant collisions so).
    #[cfg(test)]
    pub(crate) fn insert(&mut self, hash: u32, id: NodeIndex) {
        if self.find_or_claim(hash, id).is_some() {
            let k = self.probe(hash);
            self.slots[k] = pack(hash, id);
        }
    }

    /// Doubles the table (or allocates the first one) and places every slot again.
    fn grow(&mut self) {
        let size = (self.slots.len() * 2).max(MIN_SLOTS);
        let old = std::mem::replace(&mut self.slots, vec![0; size]);
        let (mask, bits) = (size - 1, size.trailing_zeros());
        for slot in old.into_iter().filter(|&s| s != 0) {
            let mut k = Self::home((slot >> 32) as u32, bits);
            while self.slots[k] != 0 {
                k = (k + 1) & mask;
            }
            self.slots[k] = slot;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Against a map, over enough hashes to grow the table many times and with hashes
    /// chosen to share home slots (they differ in the low bits only, and repeat): every
    /// hash finds the id first stored under it, and an absent one is claimed.
    #[test]
    fn finds_the_first_id_of_each_hash() {
        let mut table = InternTable::default();
        let mut truth: HashMap<u32, u32> = HashMap::new();
        let mut x: u32 = 12345;
        for k in 0..200_000u32 {
            // A linear congruential walk, folded so that hashes repeat and cluster.
            x = x.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let hash = if k % 3 == 0 { x >> 20 } else { x };
            let id = k;
            let found = table.find_or_claim(hash, id);
            match truth.get(&hash) {
                Some(&first) => assert_eq!(found, Some(first), "hash {hash:#x}"),
                None => {
                    assert_eq!(found, None, "hash {hash:#x} is new");
                    truth.insert(hash, id);
                }
            }
        }
        assert_eq!(table.len, truth.len());
        assert!(table.len * LOAD.1 <= table.slots.len() * LOAD.0);
        for (&hash, &first) in &truth {
            assert_eq!(table.find_or_claim(hash, u32::MAX - 1), Some(first));
        }
    }

    /// Hash 0 and id 0 are a real entry, not an empty slot.
    #[test]
    fn hash_and_id_zero_are_stored() {
        let mut table = InternTable::default();
        assert_eq!(table.find_or_claim(0, 0), None);
        assert_eq!(table.find_or_claim(0, 7), Some(0));
    }
}
