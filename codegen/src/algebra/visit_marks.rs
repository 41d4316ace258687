//! Marks of the nodes one walk has visited, for walks repeated many times over one growing
//! arena (one per derivative of a matrix entry).
//!
//! A node is marked with the walk's number, so starting a walk clears nothing: a fresh set
//! or map per walk costs an allocation and, once it has grown, a clearing as large as the
//! largest walk so far. Memory is one `u32` per node of the arena.

use crate::algebra::expr::Id;

/// The visited marks: `marks[n]` is the number of the last walk that visited node `n`.
#[derive(Clone, Debug, Default)]
pub(crate) struct VisitMarks {
    marks: Vec<u32>,
    walk: u32,
}

impl VisitMarks {
    /// Starts a walk: no node is marked visited.
    pub(crate) fn start(&mut self) {
        self.walk = self.walk.wrapping_add(1);
        if self.walk == 0 {
            // The counter wrapped around: no old mark may equal a new walk's number.
            self.marks.fill(0);
            self.walk = 1;
        }
    }

    /// Marks `id` visited; true the first time in this walk.
    pub(crate) fn first_visit(&mut self, id: Id) -> bool {
        let k = id.index();
        if k >= self.marks.len() {
            self.marks.resize(k + 1, 0);
        }
        std::mem::replace(&mut self.marks[k], self.walk) != self.walk
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A node is visited once per walk, and again in the next walk; marks survive the
    /// counter's wrap-around without a stale match.
    #[test]
    fn each_walk_visits_a_node_once() {
        let mut v = VisitMarks::default();
        for _ in 0..3 {
            v.start();
            assert!(v.first_visit(Id::new(5)));
            assert!(!v.first_visit(Id::new(5)));
            assert!(v.first_visit(Id::new(0)));
            assert!(v.first_visit(Id::new(100)));
            assert!(!v.first_visit(Id::new(0)));
        }
        v.walk = u32::MAX;
        v.start();
        assert!(
            v.first_visit(Id::new(5)),
            "a wrapped counter clears old marks"
        );
        assert!(!v.first_visit(Id::new(5)));
    }
}
