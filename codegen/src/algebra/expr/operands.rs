//! The operands of a sum or a product node: two or three ids inside the node itself, more
//! behind one pointer.
//!
//! Nearly every sum and product a derivation makes has two or three operands (a product of
//! a coefficient and one or two factors, a sum of two terms; the counts are in
//! BENCHMARKS.md, "Derivation at scale"). Kept in the node, they cost no allocation when
//! the node is built, none freed when an equal node was already in the arena (most
//! constructions find one), and no second cache miss when the intern table compares a
//! candidate or a pass reads the children. The enum stays 16 bytes, so a [`super::Node`]
//! stays 24.

use std::fmt;
use std::hash::{Hash, Hasher};
use std::ops::Deref;

use super::Id;

/// The operands of [`super::Node::Add`] or [`super::Node::Mul`], read as a slice `&[Id]`
/// (through `Deref`); equal, hashed and printed as that slice.
#[derive(Clone)]
pub struct Operands(Repr);

/// Two or three ids in place; any other count on the heap. A count has one form only, so
/// equal slices are equal representations.
#[derive(Clone)]
enum Repr {
    Two([Id; 2]),
    Three([Id; 3]),
    /// A thin pointer (the boxed slice's own pointer is two words), so that the enum fits
    /// in 16 bytes next to the 12 of `Three`.
    Many(Box<Box<[Id]>>),
}

impl Operands {
    /// The operands as a slice.
    pub fn as_slice(&self) -> &[Id] {
        match &self.0 {
            Repr::Two(a) => a,
            Repr::Three(a) => a,
            Repr::Many(b) => b,
        }
    }
}

impl Deref for Operands {
    type Target = [Id];

    fn deref(&self) -> &[Id] {
        self.as_slice()
    }
}

impl From<&[Id]> for Operands {
    fn from(ids: &[Id]) -> Self {
        Operands(match *ids {
            [a, b] => Repr::Two([a, b]),
            [a, b, c] => Repr::Three([a, b, c]),
            _ => Repr::Many(Box::new(ids.into())),
        })
    }
}

impl From<Vec<Id>> for Operands {
    fn from(ids: Vec<Id>) -> Self {
        match ids.len() {
            2 | 3 => Operands::from(ids.as_slice()),
            _ => Operands(Repr::Many(Box::new(ids.into_boxed_slice()))),
        }
    }
}

impl From<super::Short<Id>> for Operands {
    fn from(ids: super::Short<Id>) -> Self {
        if ids.spilled() {
            Operands::from(ids.into_vec())
        } else {
            Operands::from(&ids[..])
        }
    }
}

impl<const N: usize> From<[Id; N]> for Operands {
    fn from(ids: [Id; N]) -> Self {
        Operands::from(&ids[..])
    }
}

impl FromIterator<Id> for Operands {
    fn from_iter<I: IntoIterator<Item = Id>>(iter: I) -> Self {
        let mut iter = iter.into_iter();
        let mut first = [Id(0); 3];
        let mut k = 0;
        for id in iter.by_ref() {
            first[k] = id;
            k += 1;
            if k == 3 {
                break;
            }
        }
        match iter.next() {
            None => Operands::from(&first[..k]),
            Some(fourth) => {
                let mut all = first.to_vec();
                all.push(fourth);
                all.extend(iter);
                Operands::from(all)
            }
        }
    }
}

impl PartialEq for Operands {
    fn eq(&self, other: &Self) -> bool {
        self.as_slice() == other.as_slice()
    }
}

impl Eq for Operands {}

/// Hashed as the slice: equal operands hash alike whatever their form.
impl Hash for Operands {
    fn hash<H: Hasher>(&self, state: &mut H) {
        self.as_slice().hash(state);
    }
}

impl fmt::Debug for Operands {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.as_slice().fmt(f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::hash_map::DefaultHasher;

    fn ids(n: u32) -> Vec<Id> {
        (0..n).map(|k| Id(7 * k + 3)).collect()
    }

    fn hash_of(x: &impl Hash) -> u64 {
        let mut h = DefaultHasher::new();
        x.hash(&mut h);
        h.finish()
    }

    /// Every route into `Operands` gives back the same slice, in order, equal and hashed
    /// as the slice itself, for counts in place (2, 3) and on the heap (0, 1, 4, 9, and 20,
    /// beyond a scratch list's inline eight).
    #[test]
    fn every_route_keeps_the_slice() {
        for n in [0, 1, 2, 3, 4, 9, 20] {
            let v = ids(n);
            let forms = [
                Operands::from(v.as_slice()),
                Operands::from(v.clone()),
                v.iter().copied().collect::<Operands>(),
                Operands::from(v.iter().copied().collect::<super::super::Short<Id>>()),
            ];
            for o in &forms {
                assert_eq!(o.as_slice(), v.as_slice(), "n = {n}");
                assert_eq!(o, &forms[0]);
                assert_eq!(hash_of(o), hash_of(&v.as_slice()), "n = {n}");
                assert_eq!(format!("{o:?}"), format!("{v:?}"));
            }
        }
        assert_ne!(Operands::from(ids(3)), Operands::from(ids(4)));
        assert_eq!(Operands::from([Id(1), Id(2)]).as_slice(), &[Id(1), Id(2)]);
    }

    /// Two or three operands live in the node: the enum is two words, and a node one
    /// more.
    #[test]
    fn operands_are_two_words_and_a_node_three() {
        assert_eq!(std::mem::size_of::<Operands>(), 16);
        assert_eq!(std::mem::size_of::<super::super::Node>(), 24);
        assert!(matches!(Operands::from(ids(2)).0, Repr::Two(_)));
        assert!(matches!(Operands::from(ids(3)).0, Repr::Three(_)));
        assert!(matches!(Operands::from(ids(4)).0, Repr::Many(_)));
    }
}
