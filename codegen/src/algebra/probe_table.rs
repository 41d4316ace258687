//! A hash table of indices into a list its owner keeps: the arena's intern table (node ids
//! by node hash) and the instruction builder's value numbering (instruction positions by
//! instruction key).
//!
//! One slot is one `u64`, a 32-bit hash and the index side by side, in a single array probed
//! linearly; the owner decides whether the entry at an index is the one looked for. A
//! general-purpose map keeps its control bytes apart from its slots and stores the keys
//! themselves, so every look-up in a table larger than the cache misses twice and each
//! entry costs the key's size. On a large derivation these tables hold tens of millions of
//! entries, far beyond the cache, and every node made or instruction selected looks one up.

/// 32-bit hash to index, open addressing with linear probing; entries of one hash that
/// the owner tells apart (a 32-bit collision) each have a slot.
#[derive(Clone, Debug, Default)]
pub(crate) struct ProbeTable {
    /// `hash << 32 | (index + 1)`; 0 is an empty slot. The length is a power of two (or 0).
    slots: Vec<u64>,
    /// Occupied slots.
    len: usize,
}

/// The smallest table allocated.
const MIN_SLOTS: usize = 64;

/// [`ProbeTable::from_distinct`] sorts entries into 2^BUCKET_BITS runs of neighbouring
/// home slots (at most 256 kB of counters; a run of a table of 2^24 slots spans 2 kB).
const BUCKET_BITS: u32 = 15;

/// The table grows before it is more than `LOAD.0 / LOAD.1` full: linear probing then
/// inspects about 8.5 slots (one or two cache lines) for a hash that is absent, at worst.
const LOAD: (usize, usize) = (3, 4);

/// A slot: `index` is below `u32::MAX` (its owner's list is shorter).
fn pack(hash: u32, index: u32) -> u64 {
    (u64::from(hash) << 32) | (u64::from(index) + 1)
}

impl ProbeTable {
    /// An empty table with room for `entries` without growing.
    pub(crate) fn with_capacity(entries: usize) -> ProbeTable {
        let size = (entries * LOAD.1).div_ceil(LOAD.0) + 1;
        ProbeTable {
            slots: vec![0; size.next_power_of_two().max(MIN_SLOTS)],
            len: 0,
        }
    }

    /// The first slot to probe for `hash`: its Fibonacci mix, so that hashes that differ
    /// only in their high bits start apart (`bits` is log2 of the table's length).
    fn home(hash: u32, bits: u32) -> usize {
        (u64::from(hash).wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - bits)) as usize
    }

    /// The index stored under `hash` for which `same` holds; when none does, `index` is
    /// stored under `hash` and `None` returned (one probe sequence for both).
    pub(crate) fn find_or_insert(
        &mut self,
        hash: u32,
        index: u32,
        mut same: impl FnMut(u32) -> bool,
    ) -> Option<u32> {
        if (self.len + 1) * LOAD.1 > self.slots.len() * LOAD.0 {
            self.grow();
        }
        let mask = self.slots.len() - 1;
        let mut k = Self::home(hash, self.slots.len().trailing_zeros());
        loop {
            let slot = self.slots[k];
            if slot == 0 {
                self.slots[k] = pack(hash, index);
                self.len += 1;
                return None;
            }
            if (slot >> 32) as u32 == hash && same(slot as u32 - 1) {
                return Some(slot as u32 - 1);
            }
            k = (k + 1) & mask;
        }
    }

    /// A table of the entries `0..hashes.len()`, entry `i` under `hashes[i]`, all distinct
    /// to the owner (a copy of a list it has already told apart, so nothing is compared).
    ///
    /// The entries are placed in the order of their home slots (a counting sort by the
    /// home's top [`BUCKET_BITS`] bits), so the writes sweep the table once from start to
    /// end. Placed in list order, each would land at a random slot: one cache miss per
    /// entry in a table of millions.
    pub(crate) fn from_distinct(hashes: &[u32]) -> ProbeTable {
        let mut table = ProbeTable::with_capacity(hashes.len());
        let bits = table.slots.len().trailing_zeros();
        let shift = bits.saturating_sub(BUCKET_BITS);
        let bucket = |h: u32| Self::home(h, bits) >> shift;
        // start[b]: where bucket b's entries begin in `sorted`.
        let mut start = vec![0usize; (1 << (bits - shift)) + 1];
        for &h in hashes {
            start[bucket(h) + 1] += 1;
        }
        for b in 1..start.len() {
            start[b] += start[b - 1];
        }
        // The slots, bucket by bucket (each carries its hash: no look-up back in `hashes`).
        let mut sorted = vec![0u64; hashes.len()];
        for (i, &h) in hashes.iter().enumerate() {
            let next = &mut start[bucket(h)];
            sorted[*next] = pack(h, i as u32);
            *next += 1;
        }
        for slot in sorted {
            Self::place(&mut table.slots, bits, slot);
        }
        table.len = hashes.len();
        table
    }

    /// Doubles the table (or allocates the first one) and places every slot again.
    fn grow(&mut self) {
        let size = (self.slots.len() * 2).max(MIN_SLOTS);
        let old = std::mem::replace(&mut self.slots, vec![0; size]);
        let bits = size.trailing_zeros();
        for slot in old.into_iter().filter(|&s| s != 0) {
            Self::place(&mut self.slots, bits, slot);
        }
    }

    /// Writes the filled `slot` into the first empty slot from its hash's home on, in
    /// `slots` of length 2^`bits` (an entry known to be absent: nothing is compared).
    fn place(slots: &mut [u64], bits: u32, slot: u64) {
        let mask = slots.len() - 1;
        let mut k = Self::home((slot >> 32) as u32, bits);
        while slots[k] != 0 {
            k = (k + 1) & mask;
        }
        slots[k] = slot;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// Keys in a list, hashed so that many share a hash (the key modulo 1,000): each key
    /// is found at the position it was first stored at, whatever shares its hash, over
    /// enough keys to grow the table many times.
    #[test]
    fn finds_each_key_among_colliding_hashes() {
        let mut table = ProbeTable::default();
        let mut list: Vec<u64> = Vec::new();
        let mut first: HashMap<u64, u32> = HashMap::new();
        let mut x: u64 = 12345;
        for _ in 0..100_000 {
            x = x.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            let key = (x >> 33) % 30_000;
            let hash = (key % 1_000) as u32;
            let index = list.len() as u32;
            let found = table.find_or_insert(hash, index, |i| list[i as usize] == key);
            assert_eq!(found, first.get(&key).copied(), "key {key}");
            if found.is_none() {
                list.push(key);
                first.insert(key, index);
            }
        }
        assert_eq!(table.len, first.len());
        assert!(table.len * LOAD.1 <= table.slots.len() * LOAD.0);
    }

    /// Hash 0 and index 0 are a real entry, not an empty slot.
    #[test]
    fn hash_and_index_zero_are_stored() {
        let mut table = ProbeTable::default();
        assert_eq!(table.find_or_insert(0, 0, |_| true), None);
        assert_eq!(table.find_or_insert(0, 7, |i| i == 0), Some(0));
    }

    /// A table built from distinct entries at once finds each of them, whatever shares its
    /// hash, as one filled entry by entry does; its load is within the limit, and entries
    /// added afterwards are found too.
    #[test]
    fn a_table_built_from_distinct_entries_finds_each() {
        for n in [0u32, 1, 47, 48, 49, 5_000, 100_000] {
            // Hashes that collide 7-fold, and a run of equal homes at the table's end.
            let hashes: Vec<u32> = (0..n)
                .map(|i| {
                    if i % 50 == 0 {
                        u32::MAX
                    } else {
                        (i / 7).wrapping_mul(0x9E37_79B9)
                    }
                })
                .collect();
            let mut table = ProbeTable::from_distinct(&hashes);
            assert_eq!(table.len, n as usize);
            assert!(table.len * LOAD.1 <= table.slots.len() * LOAD.0);
            for (i, &h) in hashes.iter().enumerate() {
                assert_eq!(
                    table.find_or_insert(h, n, |k| k == i as u32),
                    Some(i as u32)
                );
            }
            assert_eq!(table.find_or_insert(u32::MAX, n, |_| false), None);
            assert_eq!(table.find_or_insert(u32::MAX, n + 1, |k| k == n), Some(n));
        }
    }

    /// A table made for n entries takes them without growing.
    #[test]
    fn a_table_with_capacity_does_not_grow() {
        let mut table = ProbeTable::with_capacity(1_000);
        let slots = table.slots.len();
        for k in 0..1_000u32 {
            assert_eq!(
                table.find_or_insert(k.wrapping_mul(0x9E37_79B9), k, |_| true),
                None
            );
        }
        assert_eq!(table.slots.len(), slots);
    }
}
